"""The CostCritic's compiled pass (cost_critic_kernel.py) gives the numpy path's costs and
fail flag bit for bit: random rollouts over painted, inscribed, lethal and unknown cells
and off the map, a non-integer critical cost (so the summation order shows), unknown
space tracked or not, near the goal or not, every rollout colliding."""

from __future__ import annotations

import numpy as np
import pytest

from btnav.control.mppi.critics import CostCritic
from btnav.costmap.cost_values import INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE, NO_INFORMATION

from .batch import costmap, make_data

T, B = 56, 300


def scored(method: str, x: np.ndarray, y: np.ndarray, cm, path, **params):
    """data.costs and fail_flag, the rollouts laid out as the optimizer lays them."""
    critic = CostCritic("CostCritic", CostCritic.Params(**params))
    critic.method = method  # type: ignore[assignment]
    data = make_data(batch=B, steps=T, path=path, cm=cm)
    data.x, data.y = x.T, y.T  # (B, T) views of (T, B) rows: the batch axis contiguous
    data.yaws = np.zeros((T, B), np.float32).T
    critic.score(data)
    return data.costs, data.fail_flag


@pytest.mark.parametrize("track_unknown", [False, True])
@pytest.mark.parametrize("near_goal", [False, True])
def test_compiled_costs_are_numpys(track_unknown, near_goal):
    rng = np.random.default_rng(11)
    cm = costmap(track_unknown)
    cm.costs[:] = rng.integers(0, 200, cm.costs.shape).astype(np.uint8)
    for cost in (INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE, NO_INFORMATION):
        cm.costs[rng.random(cm.costs.shape) < 0.002] = cost
    x = np.cumsum(rng.normal(0.0, 0.2, (T, B)), axis=0).astype(np.float32) + 1.0
    y = np.cumsum(rng.normal(0.0, 0.2, (T, B)), axis=0).astype(np.float32) + 1.0
    x[5, :10] = -50.0  # off the map
    path = np.array([[0, 0, 0], [0.2 if near_goal else 5.0, 0, 0]], np.float32)
    params = {"critical_cost": 300.37, "near_collision_cost": 190, "trajectory_point_step": 3}
    a = scored("numpy", x, y, cm, path, **params)
    k = scored("kernel", x, y, cm, path, **params)
    assert (a[0].view(np.int32) == k[0].view(np.int32)).all()
    assert a[1] == k[1]
    assert 0 < int((a[0] >= 100.0).sum()) < B  # some rollouts collide (~790), not all


def test_every_rollout_colliding_fails_the_iteration_either_way():
    cm = costmap()
    cm.costs[:] = LETHAL_OBSTACLE
    x = np.zeros((T, B), np.float32)
    path = np.array([[0, 0, 0], [5.0, 0, 0]], np.float32)
    assert scored("numpy", x, x, cm, path)[1] and scored("kernel", x, x, cm, path)[1]
