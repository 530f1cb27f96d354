"""ObstaclesCritic: obstacle avoidance from distances recovered from inflated costs."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray
from pydantic import Field

from ....core import fmath
from ....params.schema import ignored
from ....plugins import register
from ..critic_data import CriticData, cell_costs, check_footprint_setting, collision_check
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
    With `consider_footprint` (a robot with a `footprint` polygon), a point whose cost
    reaches the circumscribed cost is judged by its footprint's cost, whose clearance
    adds the inscribed radius back.

    The inflation parameters are those of the local costmap's inflation layer
    (`inflation_layer_name`, or the first), as Nav2 reads them; Nav2 Humble's own keys
    (`inflation_radius`, `cost_scaling_factor`, `inscribed_radius`), when given, win. A
    costmap without an inflation layer leaves only collisions, as in Nav2.
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
        inflation_layer_name: str = Field(
            "", description="the inflation layer whose decay the costs invert; empty: the first"
        )
        # Nav2 Humble's keys (Nav2 now reads the inflation layer): when given, they win.
        inflation_radius: float = Field(0.55, gt=0.0)
        cost_scaling_factor: float = Field(10.0, gt=0.0)
        inscribed_radius: float = Field(0.22, ge=0.0, description="m: the robot's radius")
        trajectory_point_step: int = Field(1, ge=1)

    def configure(self, costmap_ros: Any) -> None:
        super().configure(costmap_ros)
        check_footprint_setting(costmap_ros, self.name, self.params.consider_footprint)

    def _inflation(self) -> tuple[float, float, float]:
        """(cost_scaling_factor, inflation_radius, inscribed_radius) the costs were painted with."""
        p = self.params
        given = p.model_fields_set
        k, radius, inscribed = p.cost_scaling_factor, p.inflation_radius, p.inscribed_radius
        if self.costmap_ros is not None:
            inscribed = self.costmap_ros.inscribed_radius
            layer = self.costmap_ros.inflation_layer(p.inflation_layer_name)
            k = layer.params.cost_scaling_factor if layer is not None else 0.0
            radius = layer.params.inflation_radius if layer is not None else 0.0
        if "cost_scaling_factor" in given:
            k = p.cost_scaling_factor
        if "inflation_radius" in given:
            radius = p.inflation_radius
        if "inscribed_radius" in given:
            inscribed = p.inscribed_radius
        return k, radius, inscribed

    def _clearances(self, k: float) -> NDArray[np.float32]:
        """The clearance each cost value (0..255) stands for, computed once per parameters
        (a table lookup, and `fmath.log`: np.log's bits depend on the CPU)."""
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
        xs, ys = data.x[:, ::step], data.y[:, ::step]
        costs = cell_costs(data.costmap, xs, ys)
        # Nav2 scores the footprint's cost where it took it
        costs, on_footprint, collide_pt = collision_check(
            self.costmap_ros, data.costmap, costs, xs, ys, data.yaws[:, ::step],
            consider_footprint=p.consider_footprint, inflation_layer_name=p.inflation_layer_name,
        )  # fmt: skip
        collide = collide_pt.any(axis=1)
        # scored: the non-free points before a rollout's first collision
        scored = (costs > 0) & ~np.logical_or.accumulate(collide_pt, axis=1)
        k, inflation_radius, inscribed = self._inflation()
        zero = np.float32(0.0)
        critical = np.zeros(len(costs), np.float32)
        repulsive = np.zeros_like(critical)
        if k > 0.0 and inflation_radius > 0.0:  # else Nav2 cannot tell distances: collisions only
            clearance = self._clearances(k)[costs]
            clearance = np.where(on_footprint, clearance + np.float32(inscribed), clearance)
            margin = np.float32(p.collision_margin_distance)
            inside = scored & (clearance < margin)
            critical = np.where(inside, margin - clearance, zero).sum(axis=1)
            if data.local_path_length() >= p.near_goal_distance:
                repulsive = np.where(scored, np.float32(inflation_radius) - clearance, zero)
                repulsive = repulsive.sum(axis=1)
        raw = np.where(collide, np.float32(p.collision_cost), critical)
        normalised = (repulsive - repulsive.min()) / np.float32(costs.shape[1])
        term = np.float32(p.critical_weight) * raw + np.float32(p.repulsion_weight) * normalised
        if self.power != 1:
            term = term**self.power
        data.costs += term.astype(np.float32, copy=False)
        data.fail_flag = bool(collide.all())
