"""DWB's limits under a speed limit, and which twists are valid at all (Nav2's
kinematic_parameters.cpp: setSpeedLimit and isValidSpeed)."""

from __future__ import annotations

import numpy as np
import pytest

from btnav.control.dwb import DWBLocalPlanner
from btnav.control.dwb.kinematic_parameters import KinematicParameters
from btnav.control.dwb.local_planner import DWBParams
from btnav.core.geometry import Pose2D
from btnav.core.messages import Twist

from ..unicycle import free_costmap, straight_path
from .nav2_robot import NAV2_TEST_ROBOT

BASE = KinematicParameters(**NAV2_TEST_ROBOT)


def maxima(k: KinematicParameters) -> list[float]:
    return [k.max_speed_xy, k.max_vel_x, k.max_vel_y, k.max_vel_theta]


def test_a_percentage_scales_every_maximum():
    assert maxima(BASE.with_speed_limit(50.0, True)) == pytest.approx([0.275, 0.275, 0.05, 0.5])


def test_an_absolute_limit_becomes_max_speed_xy_and_scales_the_rest_alike():
    # the same trajectory shapes, slower: every maximum times 0.2 / 0.55
    ratio = 0.2 / 0.55
    assert maxima(BASE.with_speed_limit(0.2, False)) == pytest.approx(
        [0.2, 0.55 * ratio, 0.1 * ratio, 1.0 * ratio]
    )
    assert BASE.with_speed_limit(0.8, False) == BASE  # above the robot's own: nothing
    assert BASE.with_speed_limit(0.0, False) == BASE  # NO_SPEED_LIMIT
    assert BASE.with_speed_limit(50.0, True).min_vel_y == BASE.min_vel_y  # minima stay


def test_valid_speeds_is_nav2s_isvalidspeed():
    v = np.array(
        [
            [0.55, 0.0, 0.0],  # at max_speed_xy
            [0.55, 0.1, 0.0],  # over it, by combining axes
            [0.05, 0.0, 0.2],  # slower than min_speed_xy and than min_speed_theta
            [0.05, 0.0, 0.5],  # slow, but turning fast enough
            [0.0, 0.1, 0.0],  # a pure strafe at min_speed_xy
            [0.0, 0.0, 0.0],  # the zero twist
        ]
    )
    assert BASE.valid_speeds(v).tolist() == [True, False, False, True, True, False]
    unlimited = KinematicParameters(
        **{**NAV2_TEST_ROBOT, "max_speed_xy": -1.0, "min_speed_xy": -1.0}
    )
    assert unlimited.valid_speeds(v).tolist() == [True, True, True, True, True, False]


def test_dwb_under_a_speed_limit_samples_slower_strafes_and_turns():
    omni = {"min_vel_y": -0.4, "max_vel_y": 0.4, "acc_lim_y": 2.5, "decel_lim_y": -2.5}
    dwb = DWBLocalPlanner(params=DWBParams(max_vel_x=0.5, max_speed_xy=0.5, **omni))
    dwb.set_plan(straight_path())

    def sampled() -> list[float]:
        """The fastest forward, left, right and turning samples."""
        dwb.compute_velocity_commands(Pose2D(), Twist(), free_costmap())
        assert dwb.last_trajectories is not None
        v = dwb.last_trajectories.velocity
        return [v[:, 0].max(), v[:, 1].max(), v[:, 1].min(), np.abs(v[:, 2]).max()]

    assert sampled() == pytest.approx([0.5, 0.4, -0.4, 1.0])
    dwb.set_speed_limit(50.0, True)
    assert dwb.max_vel_x == pytest.approx(0.25)
    # min_vel_y is not scaled (as in Nav2): strafing right is held by max_speed_xy alone
    assert sampled() == pytest.approx([0.25, 0.2, -0.25, 0.5])
    dwb.set_speed_limit(0.0, False)
    assert sampled() == pytest.approx([0.5, 0.4, -0.4, 1.0])
