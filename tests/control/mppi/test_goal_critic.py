"""GoalCritic pulls rollouts to the goal once it is near, as Nav2's does.

Nav2 (goal_critic.cpp): skipped while state.local_path_length > threshold_to_consider
(default 1.4); otherwise each rollout pays cost_weight (default 5) times the mean over
its points of the distance to the path's last pose, raised to cost_power.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from btnav.control.mppi.critics import GoalCritic

from .batch import line, make_data, path_length, polyline, straight_path

T = 6


def critic(**params) -> GoalCritic:
    return GoalCritic("GoalCritic", GoalCritic.Params(**params))


def near_goal_batch(robot_x: float = 1.0, goal_x: float = 0.5):
    """The robot at (robot_x, 0), the goal on a straight path at (goal_x, 0). Rollouts:
    parked at the origin; driving from the robot onto the goal (0.1 m a step); parked 0.3 m
    beside the goal; parked on the goal."""
    path = straight_path(robot_x, x0=goal_x)[::-1].copy()  # from the robot to the goal
    trajs = [
        np.zeros((T, 3)),
        line(robot_x, 0.0, math.pi, 0.1, T),
        np.tile([goal_x, 0.3, 0.0], (T, 1)),
        np.tile([goal_x, 0.0, 0.0], (T, 1)),
    ]
    return make_data(trajs, path=path, robot=(robot_x, 0.0, 0.0))


def test_defaults_are_nav2s():
    p = GoalCritic.Params()
    assert (p.cost_weight, p.cost_power, p.threshold_to_consider) == (5.0, 1, 1.4)


def test_near_the_goal_each_rollout_pays_its_mean_distance_to_it():
    data = near_goal_batch()
    critic().score(data)
    # parked 0.5 m off: 5 * 0.5 (Nav2's own test); driving in: distances 0.5, 0.4, ..., 0.0,
    # mean 0.25; parked 0.3 m beside: 5 * 0.3; on the goal: 0.
    assert data.costs == pytest.approx([2.5, 1.25, 1.5, 0.0], abs=1e-5)
    assert np.argmin(data.costs) == 3


def test_far_from_the_goal_it_is_off():
    data = near_goal_batch(robot_x=1.0, goal_x=-1.0)  # 2 m of path to go
    critic().score(data)
    assert (data.costs == 0).all()


def test_threshold_to_consider_sets_the_switch_distance():
    data = near_goal_batch()  # 0.5 m to go
    critic(threshold_to_consider=0.4).score(data)
    assert (data.costs == 0).all()
    data = near_goal_batch()
    critic(threshold_to_consider=0.6).score(data)
    assert data.costs[0] == pytest.approx(2.5, abs=1e-5)


def test_weight_and_power():
    data = near_goal_batch()
    critic(cost_weight=2.0).score(data)
    assert data.costs == pytest.approx([1.0, 0.5, 0.6, 0.0], abs=1e-5)
    data = near_goal_batch()
    critic(cost_power=2).score(data)
    assert data.costs == pytest.approx([6.25, 1.5625, 2.25, 0.0], abs=1e-4)
    data = near_goal_batch()
    critic(enabled=False).score(data)
    assert (data.costs == 0).all()


def test_switch_is_judged_by_the_path_length():
    # Around a wall: the goal is 1.0 m away in a straight line, 2.0 m along the path.
    path = polyline((0.0, 0.0), (0.0, 0.5), (1.0, 0.5), (1.0, 0.0))
    assert path_length(path) == pytest.approx(2.0)
    data = make_data([np.zeros((T, 3))], path=path)
    critic().score(data)
    assert data.costs[0] == 0.0


def test_on_at_exactly_the_threshold():
    # 1.5 m (exact in float32 and float64) of straight path, threshold 1.5.
    data = make_data([np.zeros((T, 3))], path=straight_path(1.5))
    critic(threshold_to_consider=1.5).score(data)
    assert data.costs[0] == pytest.approx(5.0 * 1.5, rel=1e-5)
