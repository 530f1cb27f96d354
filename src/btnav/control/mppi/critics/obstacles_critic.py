"""ObstaclesCritic: obstacle avoidance from distances recovered from inflated costs."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from pydantic import Field

from ....core import fmath
from ....costmap.cost_values import INSCRIBED_INFLATED_OBSTACLE
from ....params.schema import ignored
from ....plugins import register
from ..critic_data import CriticData, cell_costs, in_collision, tracking_unknown
from ..critic_function import NAMESPACE, CriticFunction


@register("critic", NAMESPACE + "ObstaclesCritic")
class ObstaclesCritic(CriticFunction):
    """Inverts the inflation layer's exponential decay to get a distance to the nearest
    obstacle at each rollout point; rollouts closer than `collision_margin_distance`
    pay `critical_weight` per metre inside the margin, others (while the pruned path is
    at least `near_goal_distance` long)
    `repulsion_weight` per metre inside `inflation_radius`; a collision costs
    `collision_cost`. Circle only (see `critic_data.in_collision`).

    The inflation parameters are this critic's own (`inflation_radius`,
    `cost_scaling_factor`, `inscribed_radius`): set them to your inflation layer's,
    as Nav2 Humble required.
    """

    class Params(CriticFunction.Params):
        cost_weight: float = Field(1.0, ge=0.0)
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

    def _distances(self) -> NDArray[np.float32]:
        """The distance each cost value (0..255) stands for, computed once per parameters:
        cost = 252 exp(-k (d - r))  =>  d = r - ln(cost / 252) / k; free cells are far.
        (A table lookup, and `fmath.log`: np.log's bits depend on the CPU.)"""
        p = self.params
        key = (p.inscribed_radius, p.cost_scaling_factor, p.inflation_radius)
        if getattr(self, "_table_key", None) != key:
            costs = np.arange(256)
            c = np.clip(costs.astype(np.float32), 1.0, INSCRIBED_INFLATED_OBSTACLE - 1)
            dist = np.float32(p.inscribed_radius) - fmath.log(c / np.float32(252.0)) / np.float32(
                p.cost_scaling_factor
            )
            self._table = np.where(costs == 0, np.float32(p.inflation_radius), dist)
            self._table_key = key
        return self._table

    def score(self, data: CriticData) -> None:
        if not self.enabled:
            return
        p = self.params
        step = p.trajectory_point_step
        costs = cell_costs(data.costmap, data.x[:, ::step], data.y[:, ::step])
        collide = in_collision(
            costs,
            consider_footprint=p.consider_footprint,
            tracking_unknown=tracking_unknown(data.costmap),
        ).any(axis=1)
        dist = self._distances()[costs]
        margin = np.float32(p.collision_margin_distance)
        critical = np.where(dist < margin, margin - dist, np.float32(0.0)).sum(axis=1)
        repulsive = np.zeros_like(critical)
        if data.local_path_length() >= p.near_goal_distance:
            repulsive = np.maximum(np.float32(p.inflation_radius) - dist, 0).sum(axis=1)
        n = np.float32(costs.shape[1])
        raw = (
            np.float32(p.critical_weight) * critical
            + np.float32(p.repulsion_weight) * repulsive / n
        )
        raw = np.where(collide, np.float32(p.collision_cost), raw).astype(np.float32)
        data.fail_flag = data.fail_flag or bool(collide.all())
        self.add(data, raw)
