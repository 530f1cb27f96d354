"""The obstacle layer's raytrace clearing compiled with numba, with trace_flat's cells.

`obstacle_layer.trace_flat` lays every sample of every beam out as numpy arrays
(~10 000 for a 360-beam scan over a 3 m window): ~15 passes over them cost ~0.3 ms a
scan, most of a local costmap update. Here one loop per beam computes the same float
operations in the same order (the ray pulled back onto the map, its start, the step
count, each sample `k / n * d + f0` floored) and frees each sampled cell on the map at
once; the far part (`keep_lethal`) leaves LETHAL cells as they are, as the layer's
numpy path does. The cells freed are trace_flat's, so the grid is the same bytes
(tests/costmap/test_raytrace_kernel.py compares both).

`cache=True`, no fastmath (no FMA contraction), no parallel, `error_model="numpy"`:
plain IEEE + - * / and floor, the bits numpy computes.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from numpy.typing import NDArray

from ..core.fmath_kernels import JIT
from .cost_values import FREE_SPACE, LETHAL_OBSTACLE


@nb.njit(**JIT)
def clear_rays(
    costs: NDArray[np.uint8],
    nx: int,
    ny: int,
    resolution: float,
    origin: NDArray[np.float64],
    lo: NDArray[np.float64],
    hi: NDArray[np.float64],
    starts: NDArray[np.float64],
    ends: NDArray[np.float64],
    keep_lethal: bool,
) -> int:
    """Free the cells `trace_flat(costmap, origin, starts, ends)` lists in the flat grid
    `costs` (LETHAL ones stay with `keep_lethal`); returns how many samples it lists."""
    o_x, o_y = origin[0], origin[1]
    lo_x, lo_y = lo[0], lo[1]
    up_x, up_y = hi[0] - o_x, hi[1] - o_y
    down_x, down_y = lo_x - o_x, lo_y - o_y
    listed = 0
    for i in range(ends.shape[0]):
        dx, dy = ends[i, 0] - o_x, ends[i, 1] - o_y
        # the largest t in [0, 1] keeping origin + t*d on the map
        t = math.inf
        if dx > 0:
            t = min(t, up_x / dx)
        if dx < 0:
            t = min(t, down_x / dx)
        if dy > 0:
            t = min(t, up_y / dy)
        if dy < 0:
            t = min(t, down_y / dy)
        t = min(max(t, 0.0), 1.0)
        sx, sy = starts[i, 0], starts[i, 1]
        along = (sx - o_x) * dx + (sy - o_y) * dy
        if not along / max(dx * dx + dy * dy, 1e-300) <= t:
            continue  # the start lies beyond the (clipped) end
        # continuous cell coordinates of the two ends
        f0x = (sx - lo_x) / resolution
        f0y = (sy - lo_y) / resolution
        f1x = (o_x + t * dx - lo_x) / resolution
        f1y = (o_y + t * dy - lo_y) / resolution
        dfx, dfy = f1x - f0x, f1y - f0y
        span = max(abs(dfx), abs(dfy))
        cells = max(abs(math.floor(f1x) - math.floor(f0x)), abs(math.floor(f1y) - math.floor(f0y)))
        n = max(math.ceil(span), int(cells))  # steps at most a cell apart
        per = float(max(n, 1))
        for k in range(n + 1):
            frac = k / per
            ix = math.floor(frac * dfx + f0x)
            iy = math.floor(frac * dfy + f0y)
            if 0 <= ix < nx and 0 <= iy < ny:
                listed += 1
                cell = iy * nx + ix
                if not (keep_lethal and costs[cell] == LETHAL_OBSTACLE):
                    costs[cell] = FREE_SPACE
    return listed
