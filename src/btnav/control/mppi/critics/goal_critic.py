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
    """Once the pruned path is at most `threshold_to_consider` long: mean distance of the
    rollout's points to the path's last pose (the goal, by then)."""

    class Params(CriticFunction.Params):
        cost_weight: float = Field(5.0, ge=0.0)
        threshold_to_consider: float = Field(1.4, ge=0.0)

    def score(self, data: CriticData) -> None:
        if not self.enabled or data.local_path_length() > self.params.threshold_to_consider:
            return
        end = data.path_end()
        gx, gy = np.float32(end[0]), np.float32(end[1])
        dist = fmath.hypot(data.x - gx, data.y - gy)
        self.add(data, dist.mean(axis=1))
