"""TwirlingCritic charges rotation, except within the goal checker's xy tolerance.

Nav2 (twirling_critic.cpp): with a goal checker, skipped while
state.local_path_length < the checker's xy tolerance; otherwise each rollout pays
cost_weight (10) times its mean |wz|, raised to cost_power.
"""

from __future__ import annotations

import numpy as np
import pytest

from btnav.control.goal_checkers import SimpleGoalChecker
from btnav.control.mppi.critics import TwirlingCritic

from .batch import make_data, path_length, polyline, straight_path

T = 30


def critic(**params) -> TwirlingCritic:
    return TwirlingCritic("TwirlingCritic", TwirlingCritic.Params(**params))


def scored(path=None, checker=None, **params):
    wz = np.zeros((3, T), np.float32)
    wz[0] = 10.0  # spinning (Nav2's test)
    wz[1, ::2], wz[1, 1::2] = 0.4, -0.6  # wiggling: mean |wz| 0.5
    data = make_data(
        batch=3,
        steps=T,
        wz=wz,
        path=straight_path(3.0) if path is None else path,
        goal_checker=checker,
    )
    critic(**params).score(data)
    return data


def test_defaults_are_nav2s():
    p = TwirlingCritic.Params()
    assert (p.cost_weight, p.cost_power) == (10.0, 1)


def test_rotation_costs_its_mean_magnitude():
    data = scored(checker=SimpleGoalChecker())
    assert data.costs == pytest.approx([100.0, 5.0, 0.0], abs=1e-4)  # 10 * mean |wz|


def test_off_within_the_goal_checkers_xy_tolerance():
    near = straight_path(0.2)  # 0.2 m to go, inside the 0.25 m tolerance
    assert (scored(path=near, checker=SimpleGoalChecker()).costs == 0).all()
    loose = SimpleGoalChecker(params=SimpleGoalChecker.Params(xy_goal_tolerance=0.1))
    assert scored(path=near, checker=loose).costs[0] == pytest.approx(100.0, abs=1e-4)
    # Without a goal checker it never switches off.
    assert scored(path=near).costs[0] == pytest.approx(100.0, abs=1e-4)


def test_weight_and_power():
    data = scored(cost_weight=1.0, cost_power=2)
    assert data.costs == pytest.approx([100.0, 0.25, 0.0], abs=1e-4)
    assert (scored(enabled=False).costs == 0).all()


def test_switch_is_judged_by_the_path_length():
    # The goal 0.2 m away in a straight line, 0.4 m along the path: outside 0.25 m.
    path = polyline((0.0, 0.0), (0.0, 0.1), (0.2, 0.1), (0.2, 0.0))
    assert path_length(path) == pytest.approx(0.4)
    data = scored(path=path, checker=SimpleGoalChecker())
    assert data.costs[0] == pytest.approx(100.0, abs=1e-4)
