"""TwirlingCritic: penalises needless rotation (meant for holonomic robots)."""

from __future__ import annotations

import numpy as np
from pydantic import Field

from ....plugins import register
from ..critic_data import CriticData
from ..critic_function import NAMESPACE, CriticFunction


@register("critic", NAMESPACE + "TwirlingCritic")
class TwirlingCritic(CriticFunction):
    """Mean |wz| over the rollout, except once the pruned path is shorter than the goal
    checker's xy tolerance."""

    class Params(CriticFunction.Params):
        cost_weight: float = Field(10.0, ge=0.0)

    def score(self, data: CriticData) -> None:
        if not self.enabled:
            return
        checker = data.goal_checker
        # Nav2 compares with the x of the checker's pose tolerance (its xy tolerance).
        if (
            checker is not None
            and hasattr(checker, "get_tolerances")
            and data.local_path_length() < float(checker.get_tolerances()[0].x)
        ):
            return
        self.add(data, np.abs(data.wz).mean(axis=1))
