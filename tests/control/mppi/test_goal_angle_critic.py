"""GoalAngleCritic turns rollouts to the goal's heading once it is near, as Nav2's does.

Nav2 (goal_angle_critic.cpp): skipped while state.local_path_length >
threshold_to_consider (default 0.5); otherwise each rollout pays cost_weight (default 3)
times the mean over its points of |shortest angle(yaw, goal yaw)| (the goal being the
path's last pose); with symmetric_yaw_tolerance, the smaller of that and the angle to
the reversed goal heading; raised to cost_power.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from btnav.control.mppi.critics import GoalAngleCritic

from .batch import make_data, path_length, polyline, straight_path

T = 5


def critic(**params) -> GoalAngleCritic:
    return GoalAngleCritic("GoalAngleCritic", GoalAngleCritic.Params(**params))


def parked(yaw):
    """A rollout turning on the spot: a yaw per point (or one yaw for all)."""
    yaws = np.broadcast_to(np.asarray(yaw, float), (T,))
    return np.stack([np.zeros(T), np.zeros(T), yaws], -1)


def batch(goal_yaw: float, to_go: float = 0.3):
    """The robot at the origin, the goal `to_go` ahead on a straight path, facing goal_yaw.
    Rollouts: facing 0; facing the goal yaw; turning 0 -> pi/2 in equal steps."""
    path = straight_path(to_go)
    path[-1, 2] = goal_yaw
    trajs = [parked(0.0), parked(goal_yaw), parked(np.linspace(0.0, math.pi / 2, T))]
    return make_data(trajs, path=path)


def test_defaults_are_nav2s():
    p = GoalAngleCritic.Params()
    assert (p.cost_weight, p.cost_power, p.threshold_to_consider) == (3.0, 1, 0.5)
    assert p.symmetric_yaw_tolerance is False


def test_near_the_goal_the_mean_heading_error_is_paid():
    data = batch(3.14)
    critic().score(data)
    # Facing 0 against 3.14: 3 * 3.14 = 9.42 (Nav2's own test); the turning rollout's
    # errors are 3.14 - k pi/8, mean 3.14 - pi/4.
    assert data.costs == pytest.approx([9.42, 0.0, 3 * (3.14 - math.pi / 4)], abs=1e-4)
    data = batch(1.57)
    critic().score(data)
    # 3 * 1.57 = 4.71 (Nav2's test); turning: |k pi/8 - 1.57|, mean of pi/2 - 1.57 + ...
    turning = np.abs(np.linspace(0.0, math.pi / 2, T) - 1.57).mean()
    assert data.costs == pytest.approx([4.71, 0.0, 3 * turning], abs=1e-4)


def test_angle_wraps_the_short_way_round():
    data = batch(-3.0)  # facing 3.0 is 0.283 rad from -3.0 the short way
    data = make_data([parked(3.0), parked(-2.9)], path=data.path)
    critic().score(data)
    assert data.costs == pytest.approx([3 * (2 * math.pi - 6.0), 3 * 0.1], abs=1e-4)


def test_symmetric_yaw_tolerance_accepts_the_reverse_heading():
    data = batch(3.14)
    critic(symmetric_yaw_tolerance=True).score(data)
    # Facing 0 is 0.0016 rad from the reversed goal heading (Nav2's test: ~0).
    assert data.costs[0] == pytest.approx(3 * (math.pi - 3.14), abs=1e-4)
    assert data.costs[1] == pytest.approx(0.0, abs=1e-5)
    data = batch(1.57)
    critic(symmetric_yaw_tolerance=True).score(data)
    assert data.costs[0] == pytest.approx(4.71, abs=1e-4)  # 1.57 either way


def test_far_from_the_goal_it_is_off():
    data = batch(3.14, to_go=0.6)
    critic().score(data)
    assert (data.costs == 0).all()
    data = batch(3.14, to_go=0.6)
    critic(threshold_to_consider=0.7).score(data)
    assert data.costs[0] == pytest.approx(9.42, abs=1e-4)


def test_weight_and_power():
    data = batch(1.5)
    critic(cost_weight=2.0, cost_power=2).score(data)
    assert data.costs[0] == pytest.approx((2 * 1.5) ** 2, abs=1e-4)
    data = batch(1.5)
    critic(enabled=False).score(data)
    assert (data.costs == 0).all()


def test_switch_is_judged_by_the_path_length():
    # The goal 0.3 m away in a straight line but 0.7 m along the path.
    path = polyline((0.0, 0.0), (0.0, 0.2), (0.3, 0.2), (0.3, 0.0))
    assert path_length(path) == pytest.approx(0.7)
    data = make_data([parked(1.0)], path=path)
    critic().score(data)
    assert data.costs[0] == 0.0


def test_on_at_exactly_the_threshold():
    path = straight_path(0.5)
    path[-1, 2] = 1.0
    data = make_data([parked(0.0)], path=path)
    critic().score(data)
    assert data.costs[0] == pytest.approx(3.0, abs=1e-5)
