"""VelocityDeadbandCritic: penalises speeds a platform cannot execute (inside its deadband)."""

from __future__ import annotations

import numpy as np
from pydantic import Field, field_validator

from ....plugins import register
from ..critic_data import CriticData
from ..critic_function import NAMESPACE, CriticFunction


@register("critic", NAMESPACE + "VelocityDeadbandCritic")
class VelocityDeadbandCritic(CriticFunction):
    """Sum over the horizon of how far |vx|, |vy|, |wz| stay below their deadband, times dt."""

    class Params(CriticFunction.Params):
        cost_weight: float = Field(35.0, ge=0.0)
        deadband_velocities: list[float] = [0.0, 0.0, 0.0]

        @field_validator("deadband_velocities")
        @classmethod
        def _three(cls, v: list[float]) -> list[float]:
            if len(v) != 3 or any(x < 0 for x in v):
                raise ValueError("must be three non-negative speeds [vx, vy, wz]")
            return v

    def score(self, data: CriticData) -> None:
        if not self.enabled:
            return
        dvx, dvy, dwz = (np.float32(v) for v in self.params.deadband_velocities)
        term = np.maximum(dvx - np.abs(data.vx), 0) + np.maximum(dwz - np.abs(data.wz), 0)
        if data.is_holonomic:
            term = term + np.maximum(dvy - np.abs(data.vy), 0)
        self.add(data, term.sum(axis=1) * np.float32(data.model_dt))
