"""dwb_critics::BaseObstacle: the cost under the trajectory; any lethal, inscribed or unknown cell
(or leaving the costmap) makes it illegal. Scores the last pose's cost (or the sum, `sum_scores`)."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ....costmap.cost_values import INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE, NO_INFORMATION
from ....costmap.costmap_2d import Costmap2D
from ....plugins import register
from ..critic import Trajectories, TrajectoryCritic


@register("critic", "dwb_critics::BaseObstacle", aliases=["dwb_critics::BaseObstacleCritic"])
class BaseObstacleCritic(TrajectoryCritic):
    class Params(TrajectoryCritic.Params):
        sum_scores: bool = False

    def pose_costs(
        self, trajs: Trajectories, costmap: Costmap2D
    ) -> tuple[NDArray[np.uint8], NDArray[np.bool_]]:
        """Nav2's scorePose for every pose: the (S, T) costs (at least those the score reads:
        the last pose's, every pose's with `sum_scores`) and which poses are illegal.
        A circular robot: the cell under the pose's centre."""
        m, inside = costmap.world_to_map(trajs.poses[..., :2])
        cost = np.full(inside.shape, NO_INFORMATION, dtype=np.uint8)
        cost[inside] = costmap.costs[m[..., 1][inside], m[..., 0][inside]]
        illegal = (
            ~inside
            | (cost == LETHAL_OBSTACLE)
            | (cost == INSCRIBED_INFLATED_OBSTACLE)
            | (cost == NO_INFORMATION)
        )
        return cost, illegal

    def score(self, trajs: Trajectories, costmap: Costmap2D) -> NDArray[np.float64]:
        cost, illegal = self.pose_costs(trajs, costmap)
        c = cost.astype(float)
        score = c.sum(axis=1) if self.params.sum_scores else c[:, -1]
        return np.where(illegal.any(axis=1), np.inf, score)
