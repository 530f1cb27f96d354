"""DWB's rollouts are Nav2's StandardTrajectoryGenerator's, strafing ones included.

Nav2 (standard_traj_generator.cpp): each step first moves the velocity towards the
sample within the acceleration limits (LimitedAccelGenerator: holds the sample), then
moves the robot by its body-frame (vx, vy) turned to the heading at the step's start.
The poses are the start, one per step, and (include_last_point) the last one again.
The numbers are those of Nav2's twist_gen.cpp tests (forward = 0.3 m/s).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from btnav.control.dwb.kinematic_parameters import KinematicParameters
from btnav.control.dwb.local_planner import DWBParams
from btnav.control.dwb.trajectory_generator import simulate
from btnav.core.geometry import Pose2D
from btnav.core.messages import Twist

from .nav2_robot import NAV2_TEST_ROBOT

ORIGIN = Pose2D(0.0, 0.0, 0.0)
FORWARD = Twist(0.3, 0.0, 0.0)


def generate(cmd: Twist, start: Twist | None = None, limited: bool = False, pose=ORIGIN, **params):
    """Nav2's generateTrajectory(pose, start_vel, cmd_vel) for one sample (start: cmd)."""
    p = DWBParams(**{"linear_granularity": 0.5, **params})
    kin = KinematicParameters(
        **{**NAV2_TEST_ROBOT, **{k: v for k, v in params.items() if k in NAV2_TEST_ROBOT}}
    )
    sample = np.array([[cmd.linear_x, cmd.linear_y, cmd.angular_z]])
    return simulate(p, kin, pose, start or cmd, sample, limited).poses[0]


def test_basic_two_steps_and_the_last_pose_again():
    poses = generate(FORWARD)
    assert len(poses) == 4
    assert poses[0].tolist() == [0.0, 0.0, 0.0]
    assert poses[-1] == pytest.approx([1.7 * 0.3, 0.0, 0.0])
    assert poses[-1].tolist() == poses[-2].tolist()


def test_without_the_last_point_the_end_of_the_last_step_is_still_there():
    poses = generate(FORWARD, include_last_point=False)
    assert len(poses) == 3
    assert poses[-2] == pytest.approx([0.255, 0.0, 0.0])
    assert poses[-1] == pytest.approx([0.51, 0.0, 0.0])


def test_a_holonomic_sample_slides_sideways_without_turning():
    poses = generate(Twist(0.3, 0.2, 0.0))
    assert len(poses) == 4
    assert poses[-1] == pytest.approx([0.3 * 1.7, 0.2 * 1.7, 0.0])


def test_a_twisty_holonomic_sample_is_nav2s_to_the_last_digits():
    poses = generate(Twist(0.3, -0.2, 0.111), angular_granularity=0.025)
    assert len(poses) == 10  # 8 steps (the turn needs them), the start and the last again
    assert poses[-1] == pytest.approx(
        [0.5355173615993063, -0.29635287789821596, 0.111 * 1.7], abs=1e-12
    )


def test_a_strafe_is_sideways_to_the_robot_whatever_its_heading():
    # facing +y, a strafe to the left (body +y) goes to world -x
    poses = generate(Twist(0.0, 0.25, 0.0), pose=Pose2D(1.0, 2.0, math.pi / 2))
    assert poses[-1] == pytest.approx([1.0 - 0.25 * 1.7, 2.0, math.pi / 2])
    assert np.ptp(poses[:, 2]) == 0.0


def test_sim_time_is_the_horizon():
    poses = generate(FORWARD, sim_time=2.5)
    assert len(poses) == 4 and poses[-2] == pytest.approx([2.5 * 0.3, 0.0, 0.0])


def test_from_rest_the_velocity_ramps_at_the_acceleration_limit():
    timing = {"sim_time": 5.0, "discretize_by_time": True, "time_granularity": 1.0}
    poses = generate(FORWARD, start=Twist(), acc_lim_x=0.1, **timing)
    assert len(poses) == 7
    assert poses[1:6, 0] == pytest.approx([0.1, 0.3, 0.6, 0.9, 1.2])
    held = generate(FORWARD, start=Twist(), limited=True, acc_lim_x=0.1, **timing)
    assert held[1:6, 0] == pytest.approx([0.3, 0.6, 0.9, 1.2, 1.5])  # LimitedAccelGenerator


def test_strafing_ramps_at_acc_lim_y():
    timing = {"sim_time": 3.0, "discretize_by_time": True, "time_granularity": 1.0}
    poses = generate(Twist(0.0, 0.3, 0.0), start=Twist(), acc_lim_y=0.1, **timing)
    assert poses[1:4, 1] == pytest.approx([0.1, 0.3, 0.6]) and (poses[:, 0] == 0.0).all()
