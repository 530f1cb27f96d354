"""GoalAngleCritic: near the goal, turns rollouts to the goal's heading."""

from __future__ import annotations

import numpy as np
from pydantic import Field

from ....plugins import register
from ..angles import abs_angle_diff
from ..critic_data import CriticData
from ..critic_function import NAMESPACE, CriticFunction


@register("critic", NAMESPACE + "GoalAngleCritic")
class GoalAngleCritic(CriticFunction):
    """Once the pruned path is at most `threshold_to_consider` long: mean |yaw - goal yaw|
    over the rollout (the goal: the path's last pose).

    `symmetric_yaw_tolerance` accepts the goal heading or its reverse, whichever is closer.
    """

    class Params(CriticFunction.Params):
        cost_weight: float = Field(3.0, ge=0.0)
        threshold_to_consider: float = Field(0.5, ge=0.0)
        symmetric_yaw_tolerance: bool = False

    def score(self, data: CriticData) -> None:
        if not self.enabled or data.local_path_length() > self.params.threshold_to_consider:
            return
        err = abs_angle_diff(data.yaws, np.float32(data.path_end()[2]))
        if self.params.symmetric_yaw_tolerance:
            err = np.minimum(err, np.float32(np.pi) - err)
        self.add(data, err.mean(axis=1))
