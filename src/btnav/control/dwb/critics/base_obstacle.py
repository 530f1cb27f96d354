"""dwb_critics::BaseObstacle: the cost under the trajectory; any lethal, inscribed or unknown cell
(or leaving the costmap) makes it illegal. Scores the last pose's cost (or the sum, `sum_scores`)."""

from __future__ import annotations

import numpy as np

from ....costmap.cost_values import INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE, NO_INFORMATION
from ....plugins import register
from ..critic import TrajectoryCritic


@register("critic", "dwb_critics::BaseObstacle", aliases=["dwb_critics::BaseObstacleCritic"])
class BaseObstacleCritic(TrajectoryCritic):
    class Params(TrajectoryCritic.Params):
        sum_scores: bool = False

    def score(self, trajs, costmap):
        m, inside = costmap.world_to_map(trajs.poses[..., :2])
        cost = np.full(inside.shape, NO_INFORMATION, dtype=np.uint8)
        cost[inside] = costmap.costs[m[..., 1][inside], m[..., 0][inside]]
        bad = (
            ~inside
            | (cost == LETHAL_OBSTACLE)
            | (cost == INSCRIBED_INFLATED_OBSTACLE)
            | (cost == NO_INFORMATION)
        ).any(axis=1)
        c = cost.astype(float)
        score = c.sum(axis=1) if self.params.sum_scores else c[:, -1]
        return np.where(bad, np.inf, score)
