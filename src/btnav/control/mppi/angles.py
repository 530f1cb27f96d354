"""Angle helpers on float32 batches."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

_PI = np.float32(np.pi)
_TWO_PI = np.float32(2 * np.pi)


def abs_angle_diff(
    a: NDArray[np.float32], b: NDArray[np.float32] | np.float32
) -> NDArray[np.float32]:
    """|shortest angular distance| between angles, in [0, pi]."""
    d = np.abs(np.mod(a - b, _TWO_PI))
    return np.minimum(d, _TWO_PI - d)
