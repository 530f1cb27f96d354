"""PreferForwardCritic charges driving backwards, away from the goal, as Nav2's does.

Nav2 (prefer_forward_critic.cpp): skipped while state.local_path_length <
threshold_to_consider (0.5); otherwise each rollout pays cost_weight (5) times the
sum over its steps of max(-vx, 0) * model_dt (the distance it reverses), raised to
cost_power.
"""

from __future__ import annotations

import numpy as np
import pytest

from btnav.control.mppi.critics import PreferForwardCritic

from .batch import make_data, path_length, polyline, straight_path

T, DT = 30, 0.1


def critic(**params) -> PreferForwardCritic:
    return PreferForwardCritic("PreferForwardCritic", PreferForwardCritic.Params(**params))


def scored(path=None, **params):
    vx = np.zeros((4, T), np.float32)
    vx[0] = 1.0  # forward all the way
    vx[1] = -1.0  # reversing all the way
    vx[2, :10] = -0.5  # reversing for a second, then forward
    vx[2, 10:] = 0.3
    vx[3] = 0.0  # standing
    data = make_data(batch=4, steps=T, vx=vx, path=straight_path(3.0) if path is None else path)
    critic(**params).score(data)
    return data


def test_defaults_are_nav2s():
    p = PreferForwardCritic.Params()
    assert (p.cost_weight, p.cost_power, p.threshold_to_consider) == (5.0, 1, 0.5)


def test_reversing_costs_the_distance_reversed():
    data = scored()
    # 1 m/s back * 0.1 s * 30 steps * 5 = 15 (Nav2's own test); 0.5 m/s for 10 steps: 2.5.
    assert data.costs == pytest.approx([0.0, 15.0, 2.5, 0.0], abs=1e-4)
    assert data.costs.argmax() == 1


def test_near_the_goal_it_is_off():
    assert (scored(path=straight_path(0.45)).costs == 0).all()
    assert scored(path=straight_path(0.45), threshold_to_consider=0.4).costs[1] == pytest.approx(
        15.0, abs=1e-4
    )


def test_weight_and_power():
    assert scored(cost_weight=1.0, cost_power=2).costs == pytest.approx(
        [0.0, 9.0, 0.25, 0.0], abs=1e-4
    )
    assert (scored(enabled=False).costs == 0).all()


def test_switch_is_judged_by_the_path_length():
    # The goal 0.3 m away in a straight line, 0.7 m along the path.
    path = polyline((0.0, 0.0), (0.0, 0.2), (0.3, 0.2), (0.3, 0.0))
    assert path_length(path) == pytest.approx(0.7)
    assert scored(path=path).costs[1] == pytest.approx(15.0, abs=1e-4)
