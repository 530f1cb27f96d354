"""The cells of nav2_util::LineIterator (Bresenham) between two cells, as arrays.

The major axis advances a cell each step; the minor one when the running numerator
(starting at half the major extent, gaining the minor extent a step) reaches the
major extent. Both ends are included.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray


def line_cells(x0: int, y0: int, x1: int, y1: int) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """(mx, my) of every cell LineIterator visits from (x0, y0) to (x1, y1)."""
    dx, dy = abs(x1 - x0), abs(y1 - y0)
    major, minor = max(dx, dy), min(dx, dy)
    along = np.arange(major + 1, dtype=np.int64)
    across = (major // 2 + along * minor) // max(major, 1)
    sx = 1 if x1 >= x0 else -1
    sy = 1 if y1 >= y0 else -1
    if dx >= dy:
        return x0 + sx * along, y0 + sy * across
    return x0 + sx * across, y0 + sy * along
