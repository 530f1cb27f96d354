"""Goal and progress checkers behave as nav2_controller's, and Nav2's params sections validate."""

from __future__ import annotations

import math

import numpy as np
import pytest

from btnav.control.goal_checkers import SimpleGoalChecker, StoppedGoalChecker
from btnav.control.progress_checkers import PoseProgressChecker, SimpleProgressChecker
from btnav.core.geometry import Pose2D
from btnav.core.messages import Path, Twist
from btnav.params import load_params

GOAL = Pose2D(1.0, 2.0, 0.5)
STILL = Twist()


def test_simple_goal_checker_needs_xy_and_yaw():
    gc = SimpleGoalChecker(params=SimpleGoalChecker.Params(stateful=False))
    assert not gc.is_goal_reached(Pose2D(1.3, 2.0, 0.5), GOAL, STILL)
    assert not gc.is_goal_reached(Pose2D(1.1, 2.0, 1.0), GOAL, STILL)
    assert gc.is_goal_reached(Pose2D(1.1, 2.1, 0.6), GOAL, STILL)
    # Not stateful: leaving xy tolerance while turning loses the goal.
    assert gc.is_goal_xy_reached(Pose2D(1.1, 2.0, 2.0), GOAL, STILL)
    assert not gc.is_goal_reached(Pose2D(1.4, 2.0, 0.5), GOAL, STILL)


def test_stateful_goal_checker_only_checks_yaw_after_xy():
    gc = SimpleGoalChecker()  # stateful by default, as Nav2
    assert not gc.is_goal_reached(Pose2D(1.1, 2.0, 2.0), GOAL, STILL)  # xy reached, yaw not
    # The robot drifts out of xy tolerance while rotating: only yaw is checked now.
    assert gc.is_goal_reached(Pose2D(1.5, 2.0, 0.5), GOAL, STILL)
    gc.reset()
    assert not gc.is_goal_reached(Pose2D(1.5, 2.0, 0.5), GOAL, STILL)


def test_goal_checker_path_length_tolerance():
    gc = SimpleGoalChecker(params=SimpleGoalChecker.Params(path_length_tolerance=1.0))
    loop = Path(0.0, np.array([[1, 2, 0], [3, 2, 0], [3, 3, 0], [1, 3, 0], [1, 2, 0.5]], float))
    assert not gc.is_goal_reached(Pose2D(1.0, 2.0, 0.5), GOAL, STILL, loop)
    assert gc.is_goal_reached(Pose2D(1.0, 2.0, 0.5), GOAL, STILL, Path(0.0, loop.poses[-1:]))


def test_symmetric_yaw_tolerance():
    gc = SimpleGoalChecker(params=SimpleGoalChecker.Params(symmetric_yaw_tolerance=True))
    assert gc.is_goal_reached(Pose2D(1.0, 2.0, 0.5 - math.pi), GOAL, STILL)


def test_stopped_goal_checker_needs_the_robot_stopped():
    gc = StoppedGoalChecker(params=StoppedGoalChecker.Params(stateful=False))
    at = Pose2D(1.0, 2.0, 0.5)
    assert not gc.is_goal_reached(at, GOAL, Twist(linear_x=0.3))
    assert not gc.is_goal_reached(at, GOAL, Twist(angular_z=0.4))
    assert gc.is_goal_reached(at, GOAL, Twist(linear_x=0.1, angular_z=0.1))
    _, vel_tol, _ = gc.get_tolerances()
    assert vel_tol.linear_x == 0.25 and vel_tol.angular_z == 0.25


def test_progress_checker_fires_after_time_allowance():
    pc = SimpleProgressChecker(
        params=SimpleProgressChecker.Params(
            required_movement_radius=0.5, movement_time_allowance=10.0
        )
    )
    assert pc.check(Pose2D(0, 0, 0), 0.0)
    assert pc.check(Pose2D(0.4, 0, 0), 9.9)  # within the radius, within the allowance
    assert not pc.check(Pose2D(0.45, 0, 0), 10.1)  # 10.1 s without leaving the 0.5 m circle
    assert pc.check(Pose2D(0.6, 0, 0), 10.2)  # moving resets the baseline
    assert pc.check(Pose2D(0.6, 0, 0), 20.1)
    assert not pc.check(Pose2D(0.6, 0, 3.0), 20.3)  # rotation is no progress for the simple checker
    pc.reset()
    assert pc.check(Pose2D(0.6, 0, 0), 100.0)


def test_pose_progress_checker_counts_rotation():
    pc = PoseProgressChecker()
    assert pc.check(Pose2D(0, 0, 0), 0.0)
    assert pc.check(Pose2D(0, 0, 0.6), 9.0)  # turned more than required_movement_angle (0.5)
    assert pc.check(Pose2D(0, 0, 0.6), 18.0)
    assert not pc.check(Pose2D(0, 0, 0.7), 19.1)


def test_nav2_sections_resolve_to_btnav_classes(nav2_params_file):
    from btnav.control.path_handler import FeasiblePathHandler

    server = load_params(nav2_params_file).server("controller_server")
    pc = server.plugins["progress_checker"]
    assert pc.cls is SimpleProgressChecker
    assert pc.params.required_movement_radius == 0.5 and pc.params.movement_time_allowance == 10.0
    gc = server.plugins["general_goal_checker"]
    assert gc.cls is SimpleGoalChecker
    assert gc.params.stateful and gc.params.xy_goal_tolerance == 0.25
    assert gc.params.path_length_tolerance == 1.0
    ph = server.plugins["PathHandler"]
    assert ph.cls is FeasiblePathHandler
    assert ph.params.prune_distance == 2.0 and ph.params.minimum_rotation_angle == 0.785
    assert not ph.params.reject_unit_path
    # They build from their validated params.
    assert gc.cls("general_goal_checker", gc.params).is_goal_reached(GOAL, GOAL, STILL)


def test_bad_goal_checker_value_is_refused():
    with pytest.raises(ValueError):
        SimpleGoalChecker.Params(xy_goal_tolerance=-1.0)
