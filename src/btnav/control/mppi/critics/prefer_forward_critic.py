"""PreferForwardCritic: away from the goal, penalises driving backwards."""

from __future__ import annotations

import numpy as np
from pydantic import Field

from ....plugins import register
from ..critic_data import CriticData
from ..critic_function import NAMESPACE, CriticFunction


@register("critic", NAMESPACE + "PreferForwardCritic")
class PreferForwardCritic(CriticFunction):
    """While the pruned path is at least `threshold_to_consider` long: reverse distance
    travelled (sum of -vx * dt)."""

    class Params(CriticFunction.Params):
        cost_weight: float = Field(5.0, ge=0.0)
        threshold_to_consider: float = Field(0.5, ge=0.0)

    def score(self, data: CriticData) -> None:
        if not self.enabled or data.local_path_length() < self.params.threshold_to_consider:
            return
        backward = np.maximum(-data.vx, np.float32(0.0))
        self.add(data, backward.sum(axis=1) * np.float32(data.model_dt))
