"""PurePursuitController: the carrot, turning in place, the goal checker, the costmap check."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from btnav import plugins
from btnav.control.exceptions import InvalidPath, NoValidControl
from btnav.control.goal_checkers import SimpleGoalChecker
from btnav.core.geometry import Pose2D
from btnav.core.messages import Path, Twist
from btnav.costmap import Costmap2D
from btnav.costmap.cost_values import LETHAL_OBSTACLE

from btnav_example.pure_pursuit import PurePursuitController

#: A 10 x 10 m free local costmap centred on the origin.
FREE = Costmap2D(np.zeros((200, 200), np.uint8), 0.05, -5.0, -5.0, "odom")


def path_through(*points: tuple[float, float], step: float = 0.05) -> Path:
    """A densely sampled polyline, each pose facing along it."""
    pts = np.asarray(points, float)
    out = [pts[0]]
    for a, b in itertools.pairwise(pts):
        n = max(int(np.hypot(*(b - a)) / step), 1)
        out.extend(a + (b - a) * t for t in np.arange(1, n + 1) / n)
    xy = np.array(out)
    yaw = np.arctan2(*np.diff(xy, axis=0).T[::-1])
    return Path(0.0, np.column_stack([xy, np.append(yaw, yaw[-1])]), "odom")


def controller(**params) -> PurePursuitController:
    return PurePursuitController("FollowPath", PurePursuitController.Params(**params))


def test_it_is_registered():
    assert plugins.lookup("controller", "btnav_example/PurePursuitController") is (
        PurePursuitController
    )


def test_a_straight_path_ahead_is_driven_at_the_desired_speed():
    c = controller(desired_linear_vel=0.3)
    c.set_plan(path_through((0, 0), (3, 0)))
    cmd = c.compute_velocity_commands(Pose2D(0, 0, 0), Twist(), FREE)
    assert cmd.linear_x == pytest.approx(0.3)
    assert cmd.angular_z == pytest.approx(0.0)


def test_it_steers_towards_a_carrot_on_the_left():
    c = controller()
    c.set_plan(path_through((0, 0), (0.5, 0), (1.5, 0.6)))
    cmd = c.compute_velocity_commands(Pose2D(0, 0, 0), Twist(), FREE)
    assert cmd.linear_x > 0 and cmd.angular_z > 0
    assert np.hypot(*c.carrot) == pytest.approx(0.6, abs=0.05)  # lookahead_dist


def test_it_turns_in_place_when_the_path_is_behind_it():
    c = controller()
    c.set_plan(path_through((0, 0), (-2, 0)))
    cmd = c.compute_velocity_commands(Pose2D(0, 0, 0), Twist(), FREE)
    assert cmd.linear_x == 0.0
    assert abs(cmd.angular_z) == pytest.approx(1.0)  # rotate_to_heading_angular_vel


def test_at_the_goal_position_it_turns_to_the_goals_yaw_until_reset():
    c = controller()
    plan = path_through((0, 0), (1, 0))
    plan.poses[-1, 2] = math.pi / 2
    c.set_plan(plan)
    checker = SimpleGoalChecker()
    at_goal = Pose2D(0.9, 0.0, 0.0)
    cmd = c.compute_velocity_commands(at_goal, Twist(), FREE, checker)
    assert cmd.linear_x == 0.0 and cmd.angular_z > 0
    # a small slip while turning does not send it driving again (it stays turning) ...
    cmd = c.compute_velocity_commands(Pose2D(0.6, 0.0, 0.5), Twist(), FREE, checker)
    assert cmd.linear_x == 0.0
    # ... until the server resets it for the next goal (after a success or a cancel)
    c.reset()
    checker.reset()
    c.set_plan(path_through((0.6, 0), (3, 0)))
    cmd = c.compute_velocity_commands(Pose2D(0.6, 0.0, 0.0), Twist(), FREE, checker)
    assert cmd.linear_x > 0


def test_it_slows_down_on_the_approach():
    c = controller(desired_linear_vel=0.4, approach_dist=0.5)
    c.set_plan(path_through((0, 0), (0.45, 0)))
    cmd = c.compute_velocity_commands(Pose2D(0, 0, 0), Twist(), FREE)
    assert cmd.linear_x == pytest.approx(0.4 * 0.45 / 0.5)


def test_an_obstacle_on_the_arc_is_no_valid_control():
    costmap = Costmap2D(FREE.costs.copy(), 0.05, -5.0, -5.0, "odom")
    costmap.costs[95:105, 110] = LETHAL_OBSTACLE  # a wall 0.5 m ahead
    c = controller()
    c.set_plan(path_through((0, 0), (3, 0)))
    with pytest.raises(NoValidControl):
        c.compute_velocity_commands(Pose2D(0, 0, 0), Twist(), costmap)
    c = controller(use_collision_detection=False)
    c.set_plan(path_through((0, 0), (3, 0)))
    assert c.compute_velocity_commands(Pose2D(0, 0, 0), Twist(), costmap).linear_x > 0


def test_an_empty_plan_is_invalid_path():
    with pytest.raises(InvalidPath):
        controller().set_plan(Path(0.0, np.zeros((0, 3)), "odom"))


def test_a_speed_limit_caps_the_speed():
    c = controller(desired_linear_vel=0.4)
    c.set_plan(path_through((0, 0), (3, 0)))
    c.set_speed_limit(50.0, percentage=True)
    assert c.compute_velocity_commands(Pose2D(), Twist(), FREE).linear_x == pytest.approx(0.2)
    c.set_speed_limit(0.0, percentage=False)  # no limit
    assert c.compute_velocity_commands(Pose2D(), Twist(), FREE).linear_x == pytest.approx(0.4)


def test_closed_loop_it_follows_an_l_shaped_path_to_the_goal_pose():
    """A unicycle driven by the controller, and Nav2's goal checker deciding the end."""
    c = controller()
    plan = path_through((0, 0), (2, 0), (2, 2))
    c.set_plan(plan)
    checker = SimpleGoalChecker()
    pose, dt = Pose2D(0, 0, 0), 0.05
    goal = Pose2D(*plan.poses[-1])
    for _ in range(600):
        cmd = c.compute_velocity_commands(pose, Twist(), FREE, checker)
        if checker.is_goal_reached(pose, goal, cmd):
            break
        yaw = pose.yaw + cmd.angular_z * dt
        pose = Pose2D(
            pose.x + cmd.linear_x * dt * math.cos(yaw),
            pose.y + cmd.linear_x * dt * math.sin(yaw),
            yaw,
        )
        off = np.min(np.hypot(plan.poses[:, 0] - pose.x, plan.poses[:, 1] - pose.y))
        assert off < 0.3  # never far from the path (it cuts the corner a little)
    else:
        pytest.fail(f"the goal was not reached; the robot is at {pose}")
    assert pose.distance_to(goal) <= 0.25
