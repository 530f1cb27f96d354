"""ConstraintCritic scores velocities outside the limits as Nav2's does.

Nav2 (constraint_critic.cpp): per rollout, sum over time of the amount vx leaves
[vx_min, vx_max] (plus |vy| over vy_max for omni, plus how far |vx / wz| falls below
the minimum turning radius for Ackermann, with |wz| floored at 1e-6), times model_dt,
times cost_weight (default 4), raised to cost_power.
"""

from __future__ import annotations

import numpy as np
import pytest

from btnav.control.mppi.critics import ConstraintCritic

from .batch import make_data

B, T, DT = 4, 30, 0.1


def critic(**params) -> ConstraintCritic:
    return ConstraintCritic("ConstraintCritic", ConstraintCritic.Params(**params))


def diff_drive_batch(vx_rows, wz=1.0):
    """One rollout per vx value, holding that speed over the horizon."""
    vx = np.repeat(np.asarray(vx_rows, np.float32)[:, None], T, axis=1)
    return make_data(batch=len(vx_rows), steps=T, vx=vx, wz=wz, vx_max=0.5, vx_min=-0.35)


def test_defaults_are_nav2s():
    p = ConstraintCritic.Params()
    assert (p.cost_weight, p.cost_power, p.enabled) == (4.0, 1, True)


def test_within_limits_costs_nothing_and_speeding_costs_the_overshoot():
    # Rollouts: inside the limits (turning hard: diff drive ignores wz), 0.1 over vx_max,
    # 0.1 under vx_min, exactly at vx_max.
    data = diff_drive_batch([0.40, 0.60, -0.45, 0.50])
    critic().score(data)
    # 4.0 weight * 0.1 m/s over * 0.1 s * 30 steps = 1.2 (Nav2's own test numbers)
    assert data.costs == pytest.approx([0.0, 1.2, 1.2, 0.0], abs=1e-4)
    assert np.argmin(data.costs) in (0, 3)


def test_cost_power_squares_the_weighted_term():
    data = diff_drive_batch([0.40, 0.60, -0.45, 0.50])
    critic(cost_power=2).score(data)
    assert data.costs == pytest.approx([0.0, 1.44, 1.44, 0.0], abs=1e-4)


def test_weight_scales_linearly_and_disabled_adds_nothing():
    data = diff_drive_batch([0.60, 0.40])
    critic(cost_weight=8.0).score(data)
    assert data.costs == pytest.approx([2.4, 0.0], abs=1e-4)
    data = diff_drive_batch([0.60, 0.40])
    critic(enabled=False).score(data)
    assert (data.costs == 0).all()


def test_violation_on_part_of_the_horizon_counts_only_those_steps():
    vx = np.full((1, T), 0.4, np.float32)
    vx[0, :10] = 0.7  # 0.2 over for the first 10 steps
    data = make_data(batch=1, steps=T, vx=vx, vx_max=0.5, vx_min=-0.35)
    critic().score(data)
    assert data.costs[0] == pytest.approx(4.0 * 0.2 * DT * 10, abs=1e-4)  # 0.8


def test_omni_adds_lateral_overshoot_either_side():
    vx = np.zeros((3, T), np.float32)
    vy = np.zeros((3, T), np.float32)
    vx[0] = 0.6  # 0.1 over vx_max
    vy[1] = 0.5  # 0.2 over vy_max = 0.3
    vx[2], vy[2] = 0.6, -0.5  # both: 1.2 + 2.4
    data = make_data(
        batch=3, steps=T, vx=vx, vy=vy, is_holonomic=True, vx_max=0.5, vx_min=-0.35, vy_max=0.3
    )
    critic().score(data)
    assert data.costs == pytest.approx([1.2, 2.4, 3.6], abs=1e-4)
    data.costs[:] = 0
    critic(cost_power=2).score(data)
    assert data.costs == pytest.approx([1.44, 5.76, 12.96], abs=1e-3)


def test_diff_drive_ignores_lateral_speed():
    data = make_data(batch=1, steps=T, vx=0.4, vy=0.9, vx_max=0.5, vx_min=-0.35, vy_max=0.3)
    critic().score(data)
    assert data.costs[0] == 0.0


def test_ackermann_penalises_turns_tighter_than_the_minimum_radius():
    # min_turning_r 0.2: vx 0.4 at wz 1.5 turns on r = 0.267 (fine); at wz 2.5 on r = 0.16.
    wz = np.array([[1.5] * T, [2.5] * T, [-2.5] * T], np.float32)
    data = make_data(batch=3, steps=T, vx=0.4, wz=wz, vx_max=0.5, vx_min=-0.35, min_turning_r=0.2)
    critic().score(data)
    # 4.0 * 0.1 s * (0.2 - 0.4 / 2.5) * 30 = 0.48 (Nav2's own test numbers)
    assert data.costs == pytest.approx([0.0, 0.48, 0.48], abs=1e-4)
    data.costs[:] = 0
    critic(cost_power=2).score(data)
    assert data.costs == pytest.approx([0.0, 0.2304, 0.2304], abs=1e-4)


def test_ackermann_standing_still_pays_the_minimum_radius_as_nav2s_does():
    data = make_data(batch=1, steps=T, vx=0.0, wz=0.0, min_turning_r=0.2)
    critic().score(data)
    assert data.costs[0] == pytest.approx(4.0 * 0.2 * DT * T, abs=1e-4)  # 2.4
