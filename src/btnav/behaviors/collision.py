"""Collision checking ahead for behaviours: footprints on the local costmap.

Nav2's behaviours ask a CostmapTopicCollisionChecker whether a pose is free: the
robot's footprint is placed at the pose and the highest cost under its outline is
compared with LETHAL_OBSTACLE. A pose off the costmap, or with an unknown
(NO_INFORMATION) cell under the outline, counts as a collision, as in Nav2.
Here all the poses of a simulated motion are checked in one vectorised call.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..core import fmath
from ..core.geometry import Pose2D
from ..costmap.cost_values import LETHAL_OBSTACLE
from ..costmap.costmap_2d import Costmap2D


def _outline(footprint: NDArray[np.float64], step: float) -> NDArray[np.float64]:
    """Points along the closed polygon's edges, no further apart than `step`."""
    a = footprint
    b = np.roll(footprint, -1, axis=0)
    pts = []
    for (ax, ay), (bx, by) in zip(a, b, strict=True):
        n = max(1, int(np.ceil(fmath.hypot(bx - ax, by - ay) / step)))
        t = np.arange(n) / n
        pts.append(np.stack([ax + t * (bx - ax), ay + t * (by - ay)], axis=1))
    return np.concatenate(pts) if pts else np.zeros((0, 2))


class CollisionChecker:
    """Is the footprint free of lethal cells at a pose (in the costmap's frame)?

    `costmap` is a `CostmapROS` (anything with `.costmap` and `.footprint`), read
    afresh on each call so a costmap that updates in between is seen. `to_costmap`
    maps a pose from the behaviour's frame into the costmap's frame (identity when
    both are `odom`, the usual case).
    """

    def __init__(
        self,
        costmap: Any,
        to_costmap: Callable[[], Pose2D] | None = None,
    ) -> None:
        self.costmap_ros = costmap
        self.to_costmap = to_costmap

    @property
    def costmap(self) -> Costmap2D:
        return self.costmap_ros.costmap  # type: ignore[no-any-return]

    def footprint_costs(self, poses: ArrayLike) -> NDArray[np.int64]:
        """The highest cost under the footprint outline at each (x, y, yaw) pose;
        LETHAL_OBSTACLE + 1 (= NO_INFORMATION) for a pose whose outline leaves the map."""
        p = np.asarray(poses, dtype=float).reshape(-1, 3)
        if self.to_costmap is not None:
            t = self.to_costmap()
            s, c = fmath.sincos(t.yaw)
            p = np.stack(
                [
                    t.x + c * p[:, 0] - s * p[:, 1],
                    t.y + s * p[:, 0] + c * p[:, 1],
                    p[:, 2] + t.yaw,
                ],
                axis=1,
            )
        cm = self.costmap
        outline = _outline(np.asarray(self.costmap_ros.footprint, float), 0.5 * cm.resolution)
        s, c = fmath.sincos(p[:, 2, None])
        xs = p[:, 0:1] + c * outline[None, :, 0] - s * outline[None, :, 1]
        ys = p[:, 1:2] + s * outline[None, :, 0] + c * outline[None, :, 1]
        m, inside = cm.world_to_map(np.stack([xs, ys], axis=-1))
        costs = np.full(inside.shape, LETHAL_OBSTACLE + 1, dtype=np.int64)
        costs[inside] = cm.costs[m[..., 1][inside], m[..., 0][inside]]
        _, centre_in = cm.world_to_map(p[:, :2])
        out = costs.max(axis=1) if costs.shape[1] else np.zeros(len(p), np.int64)
        out[~centre_in] = LETHAL_OBSTACLE + 1
        return out

    def is_collision_free(self, pose: Pose2D | Sequence[float]) -> bool:
        return bool(self.first_collision([tuple(pose)]) is None)

    def first_collision(self, poses: ArrayLike) -> int | None:
        """Index of the first pose in collision, or None if all are free."""
        p = np.asarray(poses, dtype=float).reshape(-1, 3)
        if len(p) == 0:
            return None
        hit = np.nonzero(self.footprint_costs(p) >= LETHAL_OBSTACLE)[0]
        return int(hit[0]) if hit.size else None
