"""dwb_critics::Twirling: the commanded turning rate, so that of two otherwise equal
trajectories the robot takes the one that spins less (a holonomic robot's habit)."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ....costmap.costmap_2d import Costmap2D
from ....plugins import register
from ..critic import Trajectories, TrajectoryCritic


@register("critic", "dwb_critics::Twirling", aliases=["dwb_critics::TwirlingCritic"])
class TwirlingCritic(TrajectoryCritic):
    def score(self, trajs: Trajectories, costmap: Costmap2D) -> NDArray[np.float64]:
        return np.abs(trajs.velocity[:, 2])
