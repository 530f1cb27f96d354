"""RotateToGoal: near the goal, slow down, then only rotate, towards the goal's yaw.

Nav2 (rotate_to_goal.cpp): the robot is "in window" once within xy_goal_tolerance of
the goal with at most path_length_tolerance of plan left, and "rotating" once in window
and no faster than trans_stopped_velocity; both latch until reset (a new plan). Out of
window every trajectory scores 0. In window but not rotating, a trajectory not slower
than the current speed is illegal, others score speed^2 * slowing_factor + |yaw error|
at their end. Rotating, any translation is illegal and a rotation scores its |yaw
error| at the end (or at lookahead_time, interpolated, when >= 0).
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from btnav.control.dwb.critics.rotate_to_goal import RotateToGoalCritic
from btnav.control.dwb.local_planner import DWBParams
from btnav.core.geometry import Pose2D
from btnav.core.messages import Twist
from btnav.plugins import lookup

from .trajs import costmap, line_plan, prepare, trajectories, velocity_set

GOAL_YAW = 1.0
NEAR = Pose2D(2.85, 2.55, 0.0)  # 0.2 m from the goal at (3.05, 2.55)
FAR = Pose2D(1.05, 2.55, 0.0)


def critic(planner=None, **params) -> RotateToGoalCritic:
    planner = DWBParams() if planner is None else planner  # tolerances 0.25 m, 0.25 m/s, 1 m
    return RotateToGoalCritic("RotateToGoal", RotateToGoalCritic.Params(**params), planner)


def plan_from(pose: Pose2D, *corners):
    pts = [(pose.x, pose.y), *corners, (3.05, 2.55)]
    plan = np.concatenate([line_plan(*a, *b)[:-1] for a, b in itertools.pairwise(pts)])
    plan = np.concatenate([plan, [[3.05, 2.55, GOAL_YAW]]])
    return plan


def prepared(c, pose: Pose2D, speed: float, *corners):
    assert prepare(c, pose, plan_from(pose, *corners), costmap(), Twist(linear_x=speed))
    return c


# Commanded (vx, vy, wz); poses integrated over 0.4 s: end yaw = wz * 0.4.
SAMPLES = velocity_set(
    [(0.5, 0.0, 0.0), (0.4, 0.0, 0.0), (0.2, 0.0, 0.3), (0.0, 0.0, 0.5), (0.0, 0.0, -0.5)]
)


def test_registered_under_nav2s_names_with_nav2s_defaults():
    assert lookup("critic", "dwb_critics::RotateToGoal") is RotateToGoalCritic
    assert lookup("critic", "dwb_critics::RotateToGoalCritic") is RotateToGoalCritic
    p = RotateToGoalCritic.Params()
    assert (p.slowing_factor, p.lookahead_time) == (5.0, -1.0)


def test_away_from_the_goal_it_scores_nothing():
    c = prepared(critic(), FAR, 0.4)
    assert (c.score(SAMPLES, costmap()) == 0).all()


def test_in_window_and_moving_it_must_slow_down():
    c = prepared(critic(), NEAR, 0.4)
    scores = c.score(SAMPLES, costmap())
    assert np.isinf(scores[:2]).all()  # not slower than 0.4 m/s
    # 0.2^2 * 5 + |1.0 - 0.12| = 1.08; rotating on the spot: |1.0 - 0.2|, |1.0 + 0.2|
    assert scores[2:] == pytest.approx([1.08, 0.8, 1.2])
    assert np.argmin(scores) == 3


def test_slowing_factor_weighs_the_speed():
    c = prepared(critic(slowing_factor=10.0), NEAR, 0.4)
    assert c.score(SAMPLES, costmap())[2] == pytest.approx(0.04 * 10 + 0.88)


def test_stopped_in_window_it_may_only_rotate():
    c = prepared(critic(), NEAR, 0.1)  # slower than trans_stopped_velocity
    trajs = velocity_set([(0.1, 0.0, 0.0), (0.0, 0.05, 0.0), (0.0, 0.0, 0.5), (0.0, 0.0, -0.5)])
    scores = c.score(trajs, costmap())
    assert np.isinf(scores[:2]).all()
    assert scores[2:] == pytest.approx([0.8, 1.2])


def test_the_states_latch_until_reset():
    c = prepared(critic(), NEAR, 0.1)
    prepared(c, FAR, 0.4)  # driven away and speeding up: still rotating
    assert np.isinf(c.score(velocity_set([(0.2, 0.0, 0.0)]), costmap())).all()
    c.reset()
    prepared(c, FAR, 0.4)
    assert (c.score(SAMPLES, costmap()) == 0).all()


def test_not_in_window_while_more_than_path_length_tolerance_of_plan_is_left():
    # 0.2 m from the goal as the crow flies, 1.2 m along the plan (round a wall).
    detour = ((2.85, 3.05), (3.05, 3.05))
    c = prepared(critic(), NEAR, 0.1, *detour)
    assert (c.score(SAMPLES, costmap()) == 0).all()


def test_lookahead_time_scores_the_yaw_at_that_time():
    poses = np.stack([np.full(5, 2.85), np.full(5, 2.55), [0.0, 0.2, 0.4, 0.6, 0.8]], -1)
    turning = trajectories([poses], [(0.0, 0.0, 2.0)], dt=0.1)
    c = prepared(critic(lookahead_time=0.2), NEAR, 0.1)
    assert c.score(turning, costmap())[0] == pytest.approx(1.0 - 0.4)
    c = prepared(critic(lookahead_time=5.0), NEAR, 0.1)  # past the end: the last pose
    assert c.score(turning, costmap())[0] == pytest.approx(1.0 - 0.8)
    c = prepared(critic(), NEAR, 0.1)
    assert c.score(turning, costmap())[0] == pytest.approx(1.0 - 0.8)


def test_lookahead_time_between_poses_interpolates():
    poses = np.stack([np.full(5, 2.85), np.full(5, 2.55), [0.0, 0.2, 0.4, 0.6, 0.8]], -1)
    turning = trajectories([poses], [(0.0, 0.0, 2.0)], dt=0.1)
    c = prepared(critic(lookahead_time=0.25), NEAR, 0.1)
    assert c.score(turning, costmap())[0] == pytest.approx(1.0 - 0.5)


def test_yaw_error_is_the_short_way_round():
    poses = np.stack([np.full(3, 2.85), np.full(3, 2.55), [0.0, -2.0, -3.0]], -1)
    c = prepared(critic(), NEAR, 0.1)
    score = c.score(trajectories([poses], [(0.0, 0.0, -2.0)]), costmap())[0]
    assert score == pytest.approx(2 * math.pi - 4.0)  # -3.0 is 2.28 rad from 1.0
