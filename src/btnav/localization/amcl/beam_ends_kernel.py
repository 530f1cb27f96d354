"""Where every particle's beams end, in a likelihood table's cells, compiled with numba.

The likelihood-field models score a particle by gathering one table value per beam
end. In numpy (`laser_models._endpoint_cells`) the (particles x beams) ends take ~10
whole-array passes (rotate, shift, clip, floor, flatten) for one gather: on the office
tour ~0.7 ms of AMCL's ~2.5 ms an update. Here one loop per particle and beam does
the same float operations in the same order: x = (c ex - s ey) + px,
y = (s ex + c ey) + py, clipped onto the table when asked (NaN stays NaN, as
np.clip leaves it), truncated to a cell, flattened row by row. The indices are
numpy's, so the gather and the sums after it are unchanged
(tests/localization/test_beam_ends_kernel.py compares both).

`cache=True`, no fastmath (no FMA contraction), no parallel: plain IEEE + - *.
"""

from __future__ import annotations

import numba as nb
import numpy as np
from numpy.typing import NDArray

from ...core.fmath_kernels import JIT


@nb.njit(**JIT)
def beam_end_cells(
    px: NDArray[np.float64],
    py: NDArray[np.float64],
    s: NDArray[np.float64],
    c: NDArray[np.float64],
    ex: NDArray[np.float64],
    ey: NDArray[np.float64],
    stride: int,
    rows: int,
    clip: bool,
    out: NDArray[np.intp],
) -> None:
    """`out[i, j]`: the flat table index of beam j's end (ex, ey: base frame, in cells)
    from particle i at (px, py) in padded cells with yaw (s, c): sin and cos."""
    x_max = stride - 1.0
    y_max = rows - 1.0
    for i in range(px.shape[0]):
        si, ci, xi, yi = s[i], c[i], px[i], py[i]
        for j in range(ex.shape[0]):
            gx = ci * ex[j] - si * ey[j]
            gx = gx + xi
            gy = si * ex[j] + ci * ey[j]
            gy = gy + yi
            if clip:
                if gx < 0.0:
                    gx = 0.0
                elif gx > x_max:
                    gx = x_max
                if gy < 0.0:
                    gy = 0.0
                elif gy > y_max:
                    gy = y_max
            out[i, j] = int(gy) * stride + int(gx)
