"""DWB's velocity samples are Nav2's XYThetaIterator's, holonomic ones included.

Nav2 (one_d_velocity_iterator.hpp, xy_theta_iterator.cpp, kinematic_parameters.hpp):
each axis samples max(2, n) velocities across the window the acceleration limits reach
from the current velocity (clamped into its limits first), with zero added where the
samples step over it; every combination is kept unless it is faster than max_speed_xy,
slower than both min_speed_xy and min_speed_theta, or the zero twist. The counts below
are those of Nav2's own twist_gen.cpp tests, on its test robot (0.55 m/s forward,
+/-0.1 m/s sideways, 1 rad/s), so they pin the whole iteration, not just its range.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from btnav.control.dwb.kinematic_parameters import KinematicParameters
from btnav.control.dwb.local_planner import DWBParams
from btnav.control.dwb.trajectory_generator import axis_samples, sample_velocities
from btnav.core.messages import Twist

from .nav2_robot import NAV2_TEST_ROBOT

SIM_TIME = 1.7  # StandardTrajectoryGenerator samples within sim_time
PERIOD = 0.05  # LimitedAccelGenerator within one control period (20 Hz)


def samples(counts=(20, 5, 20), acc_time=SIM_TIME, velocity=None, **changes) -> np.ndarray:
    kin = KinematicParameters(**{**NAV2_TEST_ROBOT, **changes})
    return sample_velocities(kin, counts, velocity or Twist(), acc_time)


def ranges(v: np.ndarray) -> list[float]:
    return [
        v[:, 0].min(),
        v[:, 0].max(),
        v[:, 1].min(),
        v[:, 1].max(),
        v[:, 2].min(),
        v[:, 2].max(),
    ]


@pytest.mark.parametrize(
    ("name", "changes", "count"),
    [
        ("standard_gen", {}, 1926),
        ("max_xy", {"max_speed_xy": 1.0}, 2010),
        ("min_xy", {"min_speed_xy": -1.0}, 2015),
        ("min_theta", {"min_speed_theta": -1.0}, 2015),
        ("no_limits", {"max_speed_xy": -1.0, "min_speed_xy": -1.0, "min_speed_theta": -1.0}, 2099),
    ],
)
def test_the_sample_counts_of_nav2s_twist_gen_tests(name, changes, count):
    v = samples(**changes)
    assert len(v) == count, name
    assert ranges(v) == pytest.approx([0.0, 0.55, -0.1, 0.1, -1.0, 1.0])


def test_no_limits_is_every_combination_plus_the_zeros_less_the_zero_twist():
    unlimited = {"max_speed_xy": -1.0, "min_speed_xy": -1.0, "min_speed_theta": -1.0}
    assert len(samples(**unlimited)) == 20 * 5 * 20 + 100 - 1  # twist_gen's own arithmetic
    assert len(samples((10, 3, 5), **unlimited)) == 10 * 3 * 5 - 1


def test_limited_accel_samples_only_what_one_period_reaches():
    v = samples(acc_time=PERIOD, min_speed_theta=-1.0)
    assert len(v) == 2099  # dwa_gen: everything reachable is within the limits
    assert ranges(v) == pytest.approx([0.0, 0.125, -0.1, 0.1, -0.16, 0.16])


def test_from_a_moving_start_the_window_is_clipped_by_the_limits():
    v = samples(acc_time=PERIOD, velocity=Twist(0.1, -0.08, 0.05), min_speed_theta=-1.0)
    assert len(v) == 2519  # twist_gen's nonzero
    assert ranges(v) == pytest.approx([0.0, 0.225, -0.1, 0.045, -0.11, 0.21])
    assert np.hypot(v[:, 0], v[:, 1]).max() == pytest.approx(0.24622144504490268)


def test_a_holonomic_window_strafes_both_ways_and_a_diff_drives_never():
    holonomic = samples()
    assert (holonomic[:, 1] < 0).any() and (holonomic[:, 1] > 0).any()
    assert set(np.round(holonomic[:, 1], 9)) == {-0.1, -0.05, 0.0, 0.05, 0.1}  # vy_samples 5
    diff = samples(min_vel_y=0.0, max_vel_y=0.0)  # Nav2's DWB section: max_vel_y 0
    assert len(diff) > 0 and (diff[:, 1] == 0.0).all()
    # Nav2's own nav2_params: vy_samples 5 but acc_lim_y 0: the window is the current vy
    assert (samples(acc_lim_y=0.0, decel_lim_y=0.0)[:, 1] == 0.0).all()


def test_max_speed_xy_caps_the_combined_speed_not_each_axis():
    omni = dict(min_vel_y=-0.5, max_vel_y=0.5, max_vel_x=0.5, min_speed_xy=0.0, min_speed_theta=0.0)
    v = samples((11, 11, 5), max_speed_xy=0.5, **omni)
    speed = np.hypot(v[:, 0], v[:, 1])
    assert speed.max() == pytest.approx(0.5)
    assert ((np.abs(v[:, 0]) == 0.5) & (v[:, 1] == 0.0)).any()  # straight ahead at full speed
    assert ((v[:, 0] == 0.0) & (np.abs(v[:, 1]) == 0.5)).any()  # full-speed strafe
    assert not ((v[:, 0] > 0.3) & (np.abs(v[:, 1]) > 0.4)).any()  # no 0.64 m/s diagonal
    uncapped = samples((11, 11, 5), max_speed_xy=-1.0, **omni)
    assert np.hypot(uncapped[:, 0], uncapped[:, 1]).max() == pytest.approx(math.hypot(0.5, 0.5))


def test_zero_joins_an_axis_whose_samples_step_over_it():
    # 20 turning rates from -1 to 1 miss zero by 0.053: the iterator adds it, once
    w = axis_samples(0.0, -1.0, 1.0, 3.2, 3.2, SIM_TIME, 20)
    assert len(w) == 21 and list(w).count(0.0) == 1 and np.all(np.diff(w) > 0)
    # an odd count lands on zero itself, and a window on one side of zero has none
    assert len(axis_samples(0.0, -1.0, 1.0, 3.2, 3.2, SIM_TIME, 5)) == 5
    assert 0.0 not in axis_samples(0.3, 0.0, 0.5, 1.0, 1.0, 0.05, 5)


def test_one_sample_or_none_is_read_as_two_and_a_closed_window_as_one():
    assert list(axis_samples(0.0, -0.5, 0.5, 2.5, 2.5, SIM_TIME, 1)) == [-0.5, 0.0, 0.5]
    assert list(axis_samples(0.0, -0.5, 0.5, 2.5, 2.5, SIM_TIME, 0)) == [-0.5, 0.0, 0.5]
    assert list(axis_samples(0.2, -0.5, 0.5, 0.0, 0.0, SIM_TIME, 5)) == [0.2]
    assert DWBParams(vy_samples=0).vy_samples == 0  # accepted, as Nav2 reads it


def test_a_current_velocity_beyond_the_limits_is_clamped_before_the_window():
    # 0.8 m/s against a (speed-limited) 0.3 m/s: Nav2 samples down from 0.3, not from 0.8
    v = axis_samples(0.8, 0.0, 0.3, 2.5, 2.5, PERIOD, 5)
    assert v[0] == pytest.approx(0.175) and v[-1] == pytest.approx(0.3)


def test_the_zero_twist_is_never_a_sample():
    v = samples(min_speed_xy=-1.0, min_speed_theta=-1.0)
    assert not ((v[:, 0] == 0.0) & (v[:, 1] == 0.0) & (v[:, 2] == 0.0)).any()
    assert ((v[:, 0] == 0.0) & (v[:, 1] == 0.0)).sum() == 20  # turning on the spot stays
