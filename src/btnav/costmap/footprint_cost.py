"""nav2_costmap_2d::FootprintCollisionChecker::footprintCostAtPose, for many poses at once.

Nav2 lays the oriented footprint's outline on the grid, each edge rasterised with
Bresenham's line (nav2_util::LineIterator) between its vertices' cells, and takes the
highest cost on it; a vertex off the map is LETHAL. Only the outline counts (an
obstacle wholly inside a large footprint is not seen), as in Nav2. One difference: a
LETHAL cell anywhere on the outline makes the pose LETHAL, where Nav2's early return
can let an unknown cell on an earlier edge (255, above LETHAL) stand.

The poses are whole arrays: (poses, edges, cells along the longest edge), every
edge's Bresenham cells computed at once from integer arithmetic.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..core import fmath
from .cost_values import LETHAL_OBSTACLE
from .costmap_2d import Costmap2D


def footprint_costs(
    costmap: Costmap2D,
    footprint: ArrayLike,
    x: ArrayLike,
    y: ArrayLike,
    yaw: ArrayLike,
) -> NDArray[np.uint8]:
    """The footprint's cost at each pose (x, y, yaw of any one shape): that shape, uint8."""
    fp = np.asarray(footprint, dtype=np.float64).reshape(-1, 2)
    px = np.asarray(x, dtype=np.float64)
    shape = px.shape
    px = px.reshape(-1, 1)
    py = np.asarray(y, dtype=np.float64).reshape(-1, 1)
    s, c = fmath.sincos(np.asarray(yaw, dtype=np.float64).reshape(-1, 1))
    # (K, N) vertex cells, as Costmap2D::worldToMap (x < origin is off the map)
    wx = px + (fp[:, 0] * c - fp[:, 1] * s)
    wy = py + (fp[:, 0] * s + fp[:, 1] * c)
    fx = (wx - costmap.origin_x) / costmap.resolution
    fy = (wy - costmap.origin_y) / costmap.resolution
    off = (fx < 0) | (fy < 0) | (fx >= costmap.size_x) | (fy >= costmap.size_y)
    # int32 halves the memory the pixels take; it holds a flat index and major * minor
    # while neither side of the grid reaches 46341 cells.
    index = np.int32 if max(costmap.size_x, costmap.size_y) <= 46_340 else np.int64
    mx = np.clip(fx, 0, costmap.size_x - 1).astype(index)
    my = np.clip(fy, 0, costmap.size_y - 1).astype(index)
    # Each edge i runs from vertex i to vertex i + 1 (the last back to the first).
    x1, y1 = np.roll(mx, -1, axis=1), np.roll(my, -1, axis=1)
    dx, dy = np.abs(x1 - mx), np.abs(y1 - my)
    major = np.maximum(dx, dy)
    minor = np.minimum(dx, dy)
    # Pixel k of an edge along its major axis (past the edge's end: its last cell again,
    # which is on the outline anyway). LineIterator: the numerator starts at major // 2 and
    # gains `minor` a pixel; the minor coordinate steps each time it reaches `major`.
    k = np.arange(int(major.max(initial=0)) + 1, dtype=index)
    along = np.minimum(k, major[..., None])
    across = (major[..., None] // 2 + along * minor[..., None]) // np.maximum(major, 1)[..., None]
    # Each pixel's flat index: the edge's first cell, plus `along` steps on the major axis
    # and `across` on the minor (a step in y is a row, `size_x` cells).
    w = costmap.size_x
    step_x = np.where(x1 >= mx, 1, -1).astype(index)
    step_y = np.where(y1 >= my, w, -w).astype(index)
    x_major = dx >= dy
    major_step = np.where(x_major, step_x, step_y)[..., None]
    minor_step = np.where(x_major, step_y, step_x)[..., None]
    idx = (my * w + mx)[..., None] + major_step * along + minor_step * across
    flat = (
        np.ascontiguousarray(costmap.costs)
        .ravel()
        .take(idx.reshape(len(px), idx.shape[1] * idx.shape[2]))
    )
    cost = flat.max(axis=1)
    cost = np.where((flat == LETHAL_OBSTACLE).any(axis=1), LETHAL_OBSTACLE, cost)
    cost = np.where(off.any(axis=1), LETHAL_OBSTACLE, cost)
    return cost.astype(np.uint8).reshape(shape)
