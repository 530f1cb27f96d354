"""ConstraintCritic: penalises rollout velocities outside the kinematic limits."""

from __future__ import annotations

import numpy as np
from pydantic import Field

from ....plugins import register
from ..critic_data import CriticData
from ..critic_function import NAMESPACE, CriticFunction


@register("critic", NAMESPACE + "ConstraintCritic")
class ConstraintCritic(CriticFunction):
    """Sum over the horizon of how far vx leaves [vx_min, vx_max], times model_dt.

    With an Ackermann model, also how far the turning radius |vx / wz| falls below
    `min_turning_r`: the samples are left free to turn tighter (the model constrains
    only the optimal sequence, as Nav2's does), so this term is what steers the batch
    away from turns the car cannot make. The optimizer clips the samples to the velocity
    box, so the vx terms mostly act while the robot's current speed is beyond the limits.
    """

    class Params(CriticFunction.Params):
        cost_weight: float = Field(4.0, ge=0.0)

    def score(self, data: CriticData) -> None:
        if not self.enabled:
            return
        vx = data.vx
        if (
            not data.is_holonomic
            and data.min_turning_r is None
            and vx.max() <= np.float32(data.vx_max)
            and vx.min() >= np.float32(data.vx_min)
        ):
            # every term is max(<= 0, 0): zeros, and adding zeros leaves the costs as they
            # are (costs start at +0 and only ever get terms added, so none is -0)
            return
        over = np.maximum(vx - np.float32(data.vx_max), 0) + np.maximum(
            np.float32(data.vx_min) - vx, 0
        )
        if data.is_holonomic:
            vy = np.abs(data.vy)
            over = over + np.maximum(vy - np.float32(data.vy_max), 0)
        if data.min_turning_r is not None:
            # Nav2 floors |wz| at 1e-6: standing still (radius 0) is below the minimum too
            radius = np.abs(vx) / np.maximum(np.abs(data.wz), np.float32(1e-6))
            over = over + np.maximum(np.float32(data.min_turning_r) - radius, np.float32(0.0))
        self.add(data, over.sum(axis=1) * np.float32(data.model_dt))
