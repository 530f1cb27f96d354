"""CostCritic: keeps rollouts off lethal cells and out of high-cost space, from costmap values."""

from __future__ import annotations

from typing import Any

import numpy as np
from pydantic import Field

from ....core.kernel_switch import Method
from ....params.schema import Why, ignored
from ....plugins import register
from ..cost_critic_kernel import cost_critic_costs
from ..critic_data import (
    DEFAULT_METHOD,
    CriticData,
    cell_costs,
    check_footprint_setting,
    collision_check,
    tracking_unknown,
)
from ..critic_function import NAMESPACE, CriticFunction


@register("critic", NAMESPACE + "CostCritic")
class CostCritic(CriticFunction):
    """Cost of the cells under every `trajectory_point_step`-th rollout point, in one gather.

    Per rollout: a point in collision makes the whole rollout cost `collision_cost`;
    otherwise each point at or above `near_collision_cost` adds `critical_cost`, and
    (while the pruned path is at least `near_goal_distance` long) every other point adds
    its cell cost. The sum is scaled by `cost_weight / 254` per evaluated point, as Nav2 does, so
    the weights of Nav2's params mean the same. When every rollout collides, the
    iteration fails (the controller soft-resets and retries, then gives up).

    `consider_footprint` (a robot with a `footprint` polygon): where a point's cost
    reaches the circumscribed cost, the footprint's outline is checked instead and only
    a lethal cell under it is a collision; scoring still reads the centre's cost.
    """

    class Params(CriticFunction.Params):
        cost_weight: float = Field(3.81, ge=0.0)
        consider_footprint: bool = False
        collision_cost: float = Field(1000000.0, ge=0.0)
        near_collision_cost: int = Field(253, ge=0, le=255)
        critical_cost: float = Field(300.0, ge=0.0)
        near_goal_distance: float = Field(0.5, ge=0.0)
        trajectory_point_step: int = Field(2, ge=1)
        inflation_layer_name: str = Field(
            "", description="the inflation layer giving the circumscribed cost; empty: the first"
        )
        # Nav2 Humble keys of the CostCritic, no longer read by Nav2 either.
        inflation_radius: float = ignored(
            0.55, "a Humble-only key: Nav2 now reads the costmap", ge=0.0
        )
        cost_scaling_factor: float = ignored(
            10.0, "a Humble-only key: Nav2 now reads the costmap", ge=0.0
        )
        trajectory_visualization: bool = ignored(False, Why.VIZ)

    #: "kernel" (cost_critic_kernel.py) or "numpy" (the reference), the optimizer's
    #: DEFAULT_METHOD (BTNAV_MPPI=numpy); the same bits either way.
    method: Method = DEFAULT_METHOD

    def configure(self, costmap_ros: Any) -> None:
        super().configure(costmap_ros)
        check_footprint_setting(costmap_ros, self.name, self.params.consider_footprint)

    def score(self, data: CriticData) -> None:
        if not self.enabled:
            return
        p = self.params
        step = p.trajectory_point_step
        if self.method == "kernel" and self._kernel_ready(data):
            self._score_compiled(data)
            return
        xs, ys = data.x[:, ::step], data.y[:, ::step]
        costs = cell_costs(data.costmap, xs, ys)
        # Nav2 skips free points before it looks at the footprint; it scores centre costs
        _, _, collide_pt = collision_check(
            self.costmap_ros, data.costmap, costs, xs, ys, data.yaws[:, ::step],
            consider_footprint=p.consider_footprint,
            inflation_layer_name=p.inflation_layer_name, skip_free=True,
        )  # fmt: skip
        collide = collide_pt.any(axis=1)
        near_goal = data.local_path_length() < p.near_goal_distance
        critical = costs >= p.near_collision_cost
        if near_goal:
            point_cost = np.where(critical, np.float32(p.critical_cost), np.float32(0.0))
        else:
            point_cost = np.where(critical, np.float32(p.critical_cost), costs.astype(np.float32))
        raw = point_cost.sum(axis=1, dtype=np.float32)
        raw[collide] = np.float32(p.collision_cost)
        data.fail_flag = bool(collide.all())  # Nav2 assigns: this critic's verdict
        scale = np.float32(1.0 / (254.0 * xs.shape[1]))
        self.add(data, raw * scale)

    def _kernel_ready(self, data: CriticData) -> bool:
        """The compiled pass scores centre costs of float32 rollouts laid out as the
        optimizer lays them (the batch axis contiguous: numpy then adds the points
        left to right, as the kernel does); a footprint check stays numpy's."""
        return (
            not (self.params.consider_footprint and self.costmap_ros is not None)
            and data.x.dtype == np.float32
            and data.y.dtype == np.float32
            and data.x.ndim == 2
            and data.x.shape == data.y.shape
            and data.x.strides[0] == data.x.itemsize
            and data.y.strides[0] == data.y.itemsize
        )

    def _score_compiled(self, data: CriticData) -> None:
        """`score`'s numpy steps in one compiled pass (cost_critic_kernel.py)."""
        p, cm = self.params, data.costmap
        step = p.trajectory_point_step
        points = -(-data.x.shape[1] // step)
        origin = np.array([cm.origin_x, cm.origin_y], np.float32)
        out = np.empty(data.x.shape[0], np.float32)
        data.fail_flag = bool(
            cost_critic_costs(
                data.x.T, data.y.T, step, cm.costs, origin, np.float32(1.0 / cm.resolution),
                tracking_unknown(cm), data.local_path_length() < p.near_goal_distance,
                p.near_collision_cost, np.float32(p.critical_cost),
                np.float32(p.collision_cost), np.float32(1.0 / (254.0 * points)), out,
            )
        )  # fmt: skip
        self.add(data, out)
