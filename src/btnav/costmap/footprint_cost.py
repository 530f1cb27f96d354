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
    mx = np.clip(fx, 0, costmap.size_x - 1).astype(np.int64)
    my = np.clip(fy, 0, costmap.size_y - 1).astype(np.int64)
    # Each edge i runs from vertex i to vertex i + 1 (the last back to the first).
    x0, y0 = mx, my
    x1, y1 = np.roll(mx, -1, axis=1), np.roll(my, -1, axis=1)
    dx, dy = np.abs(x1 - x0), np.abs(y1 - y0)
    sx = np.where(x1 >= x0, 1, -1)
    sy = np.where(y1 >= y0, 1, -1)
    major = np.maximum(dx, dy)
    minor = np.minimum(dx, dy)
    k = np.arange(int(major.max(initial=0)) + 1)[None, None, :]  # pixel index along an edge
    valid = k <= major[..., None]
    # LineIterator: the numerator starts at major // 2 and gains `minor` a pixel; the minor
    # coordinate steps each time it reaches `major`.
    steps = (major[..., None] // 2 + k * minor[..., None]) // np.maximum(major, 1)[..., None]
    x_major = (dx >= dy)[..., None]
    cx = x0[..., None] + sx[..., None] * np.where(x_major, k, steps)
    cy = y0[..., None] + sy[..., None] * np.where(x_major, steps, k)
    cells = costmap.costs[np.where(valid, cy, y0[..., None]), np.where(valid, cx, x0[..., None])]
    flat = cells.reshape(len(px), -1)
    cost = flat.max(axis=1)
    cost = np.where((flat == LETHAL_OBSTACLE).any(axis=1), LETHAL_OBSTACLE, cost)
    cost = np.where(off.any(axis=1), LETHAL_OBSTACLE, cost)
    return cost.astype(np.uint8).reshape(shape)
