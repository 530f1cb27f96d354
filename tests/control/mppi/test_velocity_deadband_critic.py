"""VelocityDeadbandCritic charges speeds inside the platform's deadband, as Nav2's does.

Nav2 (velocity_deadband_critic.cpp): each rollout pays cost_weight (35) times the sum
over its steps of (max(|deadband vx| - |vx|, 0) + max(|deadband wz| - |wz|, 0), plus the
same for vy with a holonomic model) * model_dt, raised to cost_power. The deadband
defaults to [0, 0, 0]: the critic does nothing until it is set.
"""

from __future__ import annotations

import numpy as np
import pytest

from btnav.control.mppi.critics import VelocityDeadbandCritic

from .batch import make_data

T, DT = 30, 0.1
DEADBAND = [0.08, 0.08, 0.08]


def critic(**params) -> VelocityDeadbandCritic:
    params.setdefault("deadband_velocities", DEADBAND)
    return VelocityDeadbandCritic("VelocityDeadbandCritic", VelocityDeadbandCritic.Params(**params))


def scored(holonomic: bool, **params):
    """Rollouts: outside the deadband; inside it on every axis (Nav2's test); inside it
    backwards and turning clockwise; inside on vx for a third of the horizon only."""
    vx = np.array([[0.8] * T, [0.01] * T, [-0.01] * T, [0.02] * 10 + [0.5] * 20], np.float32)
    vy = np.array([[0.6] * T, [0.02] * T, [-0.02] * T, [0.5] * T], np.float32)
    wz = np.array([[0.8] * T, [0.021] * T, [-0.021] * T, [0.5] * T], np.float32)
    data = make_data(batch=4, steps=T, vx=vx, vy=vy, wz=wz, is_holonomic=holonomic)
    critic(**params).score(data)
    return data


def test_weight_is_nav2s():
    p = VelocityDeadbandCritic.Params()
    assert (p.cost_weight, p.cost_power) == (35.0, 1)


def test_default_deadband_is_zero():
    assert VelocityDeadbandCritic.Params().deadband_velocities == [0.0, 0.0, 0.0]


def test_holonomic_charges_every_axis_inside_the_deadband():
    data = scored(holonomic=True)
    # 35 * 0.1 s * (0.07 + 0.06 + 0.059) * 30 = 19.845 (Nav2's own test);
    # vx 0.02 for 10 steps: 35 * 0.1 * 0.06 * 10 = 2.1.
    assert data.costs == pytest.approx([0.0, 19.845, 19.845, 2.1], abs=1e-3)


def test_diff_drive_ignores_vy():
    data = scored(holonomic=False)
    # 35 * 0.1 * (0.07 + 0.059) * 30 = 13.545
    assert data.costs == pytest.approx([0.0, 13.545, 13.545, 2.1], abs=1e-3)


def test_a_zero_deadband_does_nothing():
    data = scored(holonomic=True, deadband_velocities=[0.0, 0.0, 0.0])
    assert (data.costs == 0).all()


def test_weight_and_power():
    data = scored(holonomic=False, cost_weight=3.5, cost_power=2)
    assert data.costs == pytest.approx([0.0, 1.3545**2, 1.3545**2, 0.21**2], abs=1e-4)
    assert (scored(holonomic=True, enabled=False).costs == 0).all()
