"""dwb_critics::ObstacleFootprint: BaseObstacle for a robot of any shape.

Each pose lays the costmap server's padded footprint (a 16-gon of `robot_radius` when
no `footprint` is given), turned to the pose's yaw, on the grid and takes the highest
cost on its outline (`costmap.footprint_cost`: the edges rasterised as Nav2's
LineIterator does). A lethal or unknown cell on the outline, a vertex or the centre
off the grid makes the trajectory illegal; an inscribed cell does not (the footprint
itself says whether the robot touches). Scores as BaseObstacle: the last pose's cost,
or the sum with `sum_scores`. Without a footprint the critic cannot prepare, and the
planner fails, as Nav2's does.

Laying 400 samples x 100 poses of footprint costs ~0.1 s a cycle, so the footprint is
laid only at the poses the score reads and where a hazard may lie under the outline:
within its reach of a lethal or unknown cell or the grid's edge, by one exact distance
transform of the grid per cycle (scipy). Everywhere else no outline cell is a hazard,
and the scores are the same as laying it at every pose (the tests compare them).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy import ndimage

from ....core import fmath
from ....core.geometry import Pose2D
from ....core.messages import Twist
from ....costmap.cost_values import LETHAL_OBSTACLE
from ....costmap.costmap_2d import Costmap2D
from ....costmap.footprint_cost import footprint_costs
from ....plugins import register
from ..critic import Trajectories
from .base_obstacle import BaseObstacleCritic


@register(
    "critic", "dwb_critics::ObstacleFootprint", aliases=["dwb_critics::ObstacleFootprintCritic"]
)
class ObstacleFootprintCritic(BaseObstacleCritic):
    #: The padded footprint in the robot frame, (N, 2), read from the costmap server on
    #: each `prepare` (Nav2's getRobotFootprint: it may change between cycles).
    footprint: NDArray[np.float64] | None = None

    def prepare(
        self, pose: Pose2D, velocity: Twist, goal: Pose2D, plan: Any, costmap: Costmap2D
    ) -> bool:
        server = self.costmap_ros
        fp = None if server is None else np.asarray(server.footprint, dtype=np.float64)
        self.footprint = fp if fp is not None and fp.size else None
        return self.footprint is not None

    def pose_costs(
        self, trajs: Trajectories, costmap: Costmap2D
    ) -> tuple[NDArray[np.uint8], NDArray[np.bool_]]:
        poses = trajs.poses
        m, inside = costmap.world_to_map(poses[..., :2])
        # Lay the footprint only where the result can matter: where a hazard may lie under the
        # outline, and at the poses the score reads. Elsewhere no outline cell is a hazard.
        padded = np.where(inside[..., None], m + 1, 0)  # (0, 0): the hazard border
        near = self._clearance(costmap)[padded[..., 1], padded[..., 0]] <= self._reach(costmap)
        lay = near & inside
        if self.params.sum_scores:
            lay = inside
        else:
            lay[:, -1] = inside[:, -1]
        cost = np.zeros(inside.shape, dtype=np.uint8)
        x, y, yaw = poses[..., 0][lay], poses[..., 1][lay], poses[..., 2][lay]
        cost[lay] = footprint_costs(costmap, self.footprint, x, y, yaw)
        # (footprint_costs gives LETHAL for a vertex off the grid; unknown is 255, above it)
        return cost, ~inside | (cost >= LETHAL_OBSTACLE)

    def _reach(self, costmap: Costmap2D) -> float:
        """How far (cells, centre to centre) from a pose's cell its outline's cells can lie:
        the footprint's circumradius plus 1.92 cells (a vertex and the pose each lie within
        0.71 of their cell's centre, Bresenham's cells within 0.5 of the segment), and a margin."""
        assert self.footprint is not None
        radius = float(fmath.hypot(self.footprint[:, 0], self.footprint[:, 1]).max())
        return radius / costmap.resolution + 2.5

    @staticmethod
    def _clearance(costmap: Costmap2D) -> NDArray[np.float64]:
        """Each cell's distance (cells) to the nearest lethal or unknown cell or to the grid's
        edge, on the grid padded by one cell of hazard all round (scipy's exact EDT)."""
        hazard = np.ones((costmap.size_y + 2, costmap.size_x + 2), dtype=bool)
        hazard[1:-1, 1:-1] = costmap.costs >= LETHAL_OBSTACLE
        return ndimage.distance_transform_edt(~hazard)  # type: ignore[no-any-return]
