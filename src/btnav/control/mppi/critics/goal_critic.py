"""GoalCritic: near the goal, pulls every rollout point towards it."""

from __future__ import annotations

import numpy as np
from pydantic import Field

from ....core import fmath
from ....plugins import register
from ..critic_data import CriticData
from ..critic_function import NAMESPACE, CriticFunction


@register("critic", NAMESPACE + "GoalCritic")
class GoalCritic(CriticFunction):
    """Within `threshold_to_consider` of the goal: mean distance of the rollout's points to it."""

    class Params(CriticFunction.Params):
        cost_weight: float = Field(5.0, ge=0.0)
        threshold_to_consider: float = Field(1.4, ge=0.0)

    def score(self, data: CriticData) -> None:
        if not self.enabled or data.distance_to_goal() >= self.params.threshold_to_consider:
            return
        gx, gy = np.float32(data.goal[0]), np.float32(data.goal[1])
        dist = fmath.hypot(data.x - gx, data.y - gy)
        self.add(data, dist.mean(axis=1))
