"""Oscillation forbids reversing a direction until the robot has moved on.

Nav2 (oscillation.cpp): after each chosen command, the sign of vx is tracked, and (only
while |vx| <= x_only_threshold) the signs of vy and wz. When one flips, only the new
sign is allowed on that axis (trajectories of the other sign are illegal, whatever
their other velocities) until the robot is oscillation_reset_dist from where the flip
happened, or has turned oscillation_reset_angle, or (if >= 0) oscillation_reset_time
has passed; a negative distance or angle disables that check.
"""

from __future__ import annotations

import numpy as np

from btnav.control.dwb.critics.oscillation import OscillationCritic
from btnav.core.geometry import Pose2D
from btnav.core.messages import Twist
from btnav.plugins import lookup

from .trajs import costmap, line_plan, velocity_set

ORIGIN = Pose2D(1.05, 1.05, 0.0)
PLAN = line_plan(1.05, 1.05, 3.05, 1.05)


def critic(**params) -> OscillationCritic:
    return OscillationCritic("Oscillation", OscillationCritic.Params(**params))


def drive(c: OscillationCritic, *cmds, pose: Pose2D = ORIGIN) -> OscillationCritic:
    """Cycles in which the planner chose each command in turn with the robot at `pose`."""
    for vx, vy, wz in cmds:
        c.prepare(pose, Twist(), Pose2D.from_array(PLAN[-1]), PLAN, costmap())
        c.debrief(Twist(linear_x=vx, linear_y=vy, angular_z=wz), pose)
    return c


def legal(c: OscillationCritic, *velocities) -> list[bool]:
    return np.isfinite(c.score(velocity_set(velocities), costmap())).tolist()


def test_registered_under_nav2s_names_with_nav2s_defaults():
    assert lookup("critic", "dwb_critics::Oscillation") is OscillationCritic
    assert lookup("critic", "dwb_critics::OscillationCritic") is OscillationCritic
    p = OscillationCritic.Params()
    assert (p.oscillation_reset_dist, p.oscillation_reset_angle) == (0.05, 0.2)
    assert (p.oscillation_reset_time, p.x_only_threshold) == (-1.0, 0.05)


def test_without_a_flip_everything_is_legal_and_scores_zero():
    c = drive(critic(), (0.2, 0.0, 0.0), (0.1, 0.0, 0.3))
    trajs = velocity_set([(0.2, 0.0, 0.0), (-0.2, 0.0, 0.0), (0.0, 0.0, -0.5)])
    assert c.score(trajs, costmap()).tolist() == [0.0, 0.0, 0.0]


def test_after_forward_then_back_forward_is_illegal():
    c = drive(critic(), (0.2, 0.0, 0.0), (-0.2, 0.0, 0.0))
    assert legal(c, (0.1, 0.0, 0.0), (-0.1, 0.0, 0.0), (0.0, 0.0, 0.0)) == [False, True, True]
    c = drive(critic(), (-0.2, 0.0, 0.0), (0.2, 0.0, 0.0))
    assert legal(c, (0.1, 0.0, 0.0), (-0.1, 0.0, 0.0)) == [True, False]


def test_the_flag_clears_once_the_robot_has_moved_or_turned():
    flip = ((0.2, 0.0, 0.0), (-0.2, 0.0, 0.0))
    c = drive(critic(), *flip)
    drive(c, (-0.2, 0.0, 0.0), pose=Pose2D(1.01, 1.05, 0.0))  # 0.04 m: not yet
    assert legal(c, (0.1, 0.0, 0.0)) == [False]
    drive(c, (-0.2, 0.0, 0.0), pose=Pose2D(0.99, 1.05, 0.0))  # 0.06 m from the flip
    assert legal(c, (0.1, 0.0, 0.0)) == [True]
    c = drive(critic(), *flip)
    drive(c, (-0.2, 0.0, 0.0), pose=Pose2D(1.05, 1.05, 0.21))  # turned 0.21 rad
    assert legal(c, (0.1, 0.0, 0.0)) == [True]
    c = drive(critic(oscillation_reset_dist=0.1), *flip)
    drive(c, (-0.2, 0.0, 0.0), pose=Pose2D(0.99, 1.05, 0.0))
    assert legal(c, (0.1, 0.0, 0.0)) == [False]


def test_rotation_flips_count_only_when_not_driving():
    c = drive(critic(), (0.0, 0.0, 0.5), (0.0, 0.0, -0.5))
    assert legal(c, (0.0, 0.0, 0.5), (0.0, 0.0, -0.5)) == [False, True]
    c = drive(critic(), (0.2, 0.0, 0.5), (0.2, 0.0, -0.5))  # turning while driving
    assert legal(c, (0.0, 0.0, 0.5), (0.0, 0.0, -0.5)) == [True, True]


def test_strafing_flips_count_when_not_driving():
    c = drive(critic(), (0.0, 0.1, 0.0), (0.0, -0.1, 0.0))
    assert legal(c, (0.0, 0.1, 0.0), (0.0, -0.1, 0.0)) == [False, True]


def test_reset_forgets_the_flags():
    c = drive(critic(), (0.2, 0.0, 0.0), (-0.2, 0.0, 0.0))
    c.reset()
    assert legal(c, (0.1, 0.0, 0.0)) == [True]


def test_a_rotation_flag_rejects_turning_back_while_driving_too():
    c = drive(critic(), (0.0, 0.0, 0.5), (0.0, 0.0, -0.5))
    assert legal(c, (0.2, 0.0, 0.5)) == [False]


def test_strafing_flips_while_driving_are_not_tracked():
    c = drive(critic(), (0.2, 0.1, 0.0), (0.2, -0.1, 0.0))
    assert legal(c, (0.2, 0.1, 0.0)) == [True]


def test_x_only_threshold_is_inclusive():
    c = drive(critic(), (0.05, 0.0, 0.5), (0.05, 0.0, -0.5))
    assert legal(c, (0.0, 0.0, 0.5)) == [False]


def test_negative_reset_parameters_disable_the_reset():
    c = critic(oscillation_reset_dist=-1.0, oscillation_reset_angle=-1.0)
    drive(c, (0.2, 0.0, 0.0), (-0.2, 0.0, 0.0), (-0.2, 0.0, 0.0))
    assert legal(c, (0.1, 0.0, 0.0)) == [False]
