"""dwb_critics::PreferForward: for a robot that cannot see behind it.

A commanded velocity backwards, or slower than `strafe_x` while turning slower than
`strafe_theta` (creeping, neither driving nor turning), scores `penalty`; any other
scores its turning rate times `theta_scale` (the more it turns, the less it advances).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ....costmap.costmap_2d import Costmap2D
from ....plugins import register
from ..critic import Trajectories, TrajectoryCritic


@register("critic", "dwb_critics::PreferForward", aliases=["dwb_critics::PreferForwardCritic"])
class PreferForwardCritic(TrajectoryCritic):
    class Params(TrajectoryCritic.Params):
        penalty: float = 1.0
        strafe_x: float = 0.1
        strafe_theta: float = 0.2
        theta_scale: float = 10.0

    def score(self, trajs: Trajectories, costmap: Costmap2D) -> NDArray[np.float64]:
        p = self.params
        vx = trajs.velocity[:, 0]
        turn = np.abs(trajs.velocity[:, 2])
        penalised = (vx < 0.0) | ((vx < p.strafe_x) & (turn < p.strafe_theta))
        return np.where(penalised, p.penalty, turn * p.theta_scale)
