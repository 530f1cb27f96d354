"""ObstaclesCritic: obstacle avoidance from distances recovered from inflated costs."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from pydantic import Field

from ....core import fmath
from ....params.schema import ignored
from ....plugins import register
from ..critic_data import CriticData, cell_costs, in_collision, tracking_unknown
from ..critic_function import NAMESPACE, CriticFunction


@register("critic", NAMESPACE + "ObstaclesCritic")
class ObstaclesCritic(CriticFunction):
    """Nav2's ObstaclesCritic: inverts the inflation layer's exponential decay to get each
    rollout point's clearance (from the robot's inscribed circle to the nearest obstacle,
    `ln(253 / cost) / cost_scaling_factor`). A clearance under `collision_margin_distance`
    adds `margin - clearance` to the critical term; away from the goal (the pruned path at
    least `near_goal_distance` long) every non-free point adds `inflation_radius -
    clearance` to the repulsive term, which is normalised by the horizon after taking off
    the batch's smallest. A rollout stops being scored at its first collision and costs
    `collision_cost` in place of its critical term. The whole is `(critical_weight *
    critical + repulsion_weight * repulsive) ** cost_power`: Nav2 reads no cost_weight here.
    Circle only (see `critic_data.in_collision`).

    The inflation parameters are this critic's own (`inflation_radius`,
    `cost_scaling_factor`, `inscribed_radius`), as Nav2 Humble's: set them to your
    inflation layer's (Nav2 now reads that layer).
    """

    class Params(CriticFunction.Params):
        cost_weight: float = ignored(
            1.0, "Nav2's ObstaclesCritic weighs by critical_weight and repulsion_weight", ge=0.0
        )
        critical_weight: float = Field(20.0, ge=0.0)
        repulsion_weight: float = Field(1.5, ge=0.0)
        consider_footprint: bool = False
        collision_cost: float = Field(100000.0, ge=0.0)
        collision_margin_distance: float = Field(0.10, ge=0.0)
        near_goal_distance: float = Field(0.5, ge=0.0)
        inflation_radius: float = Field(0.55, gt=0.0)
        cost_scaling_factor: float = Field(10.0, gt=0.0)
        inscribed_radius: float = Field(0.22, ge=0.0, description="m: the robot's radius")
        trajectory_point_step: int = Field(1, ge=1)
        inflation_layer_name: str = ignored("", "btnav reads the critic's own inflation keys")

    def _clearances(self) -> NDArray[np.float32]:
        """The clearance each cost value (0..255) stands for, computed once per parameters
        (a table lookup, and `fmath.log`: np.log's bits depend on the CPU)."""
        k = self.params.cost_scaling_factor
        if getattr(self, "_table_key", None) != k:
            c = np.maximum(np.arange(256, dtype=np.float32), np.float32(1.0))
            self._table = (fmath.log(np.float32(253.0)) - fmath.log(c)) / np.float32(k)
            self._table_key = k
        return self._table

    def score(self, data: CriticData) -> None:
        if not self.enabled:
            return
        p = self.params
        step = p.trajectory_point_step
        costs = cell_costs(data.costmap, data.x[:, ::step], data.y[:, ::step])
        collide_pt = in_collision(
            costs,
            consider_footprint=p.consider_footprint,
            tracking_unknown=tracking_unknown(data.costmap),
        )
        # scored: the non-free points before a rollout's first collision
        scored = (costs > 0) & ~np.logical_or.accumulate(collide_pt, axis=1)
        clearance = self._clearances()[costs]
        margin = np.float32(p.collision_margin_distance)
        zero = np.float32(0.0)
        critical = np.where(scored & (clearance < margin), margin - clearance, zero).sum(axis=1)
        repulsive = np.zeros_like(critical)
        if data.local_path_length() >= p.near_goal_distance:
            repulsive = np.where(scored, np.float32(p.inflation_radius) - clearance, zero)
            repulsive = repulsive.sum(axis=1)
        collide = collide_pt.any(axis=1)
        raw = np.where(collide, np.float32(p.collision_cost), critical)
        normalised = (repulsive - repulsive.min()) / np.float32(costs.shape[1])
        term = np.float32(p.critical_weight) * raw + np.float32(p.repulsion_weight) * normalised
        if self.power != 1:
            term = term**self.power
        data.costs += term.astype(np.float32, copy=False)
        data.fail_flag = bool(collide.all())
