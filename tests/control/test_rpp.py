"""Regulated Pure Pursuit drives a unicycle to the goal and regulates its speed as Nav2's does."""

from __future__ import annotations

import math

import numpy as np
import pytest

from btnav.control.exceptions import NoValidControl
from btnav.control.goal_checkers import SimpleGoalChecker
from btnav.control.regulated_pure_pursuit import RegulatedPurePursuitController as RPP
from btnav.core.geometry import Pose2D
from btnav.core.messages import Twist
from btnav.plugins import lookup

from .mppi.batch import costmap_server
from .unicycle import curved_path, drive, free_costmap, straight_path


@pytest.mark.parametrize("make_path", [straight_path, curved_path])
def test_reaches_goal(make_path):
    path = make_path()
    gc = SimpleGoalChecker()
    pose, _cmds, poses, reached = drive(RPP(), path, free_costmap(), gc)
    assert reached
    goal = path.poses[-1]
    assert math.hypot(pose.x - goal[0], pose.y - goal[1]) <= 0.25
    assert abs(math.remainder(pose.yaw - goal[2], 2 * math.pi)) <= 0.25
    # Stays on the path: every pose within 0.15 m of some path point.
    d = np.hypot(
        poses[:, None, 0] - path.poses[None, :, 0], poses[:, None, 1] - path.poses[None, :, 1]
    )
    assert d.min(axis=1).max() < 0.15


def test_rotates_to_heading_first_and_at_goal():
    ctrl = RPP()
    path = straight_path()
    ctrl.set_plan(path)
    cmd = ctrl.compute_velocity_commands(Pose2D(0, 0, math.pi / 2), Twist(), free_costmap())
    assert cmd.linear_x == 0.0 and cmd.angular_z < 0.0 and ctrl.is_rotating_to_heading
    # At the goal position with the wrong heading: rotate in place towards the goal yaw.
    ctrl.set_plan(path)
    cmd = ctrl.compute_velocity_commands(
        Pose2D(4.0, 0.0, 0.6), Twist(angular_z=-1.0), free_costmap(), SimpleGoalChecker()
    )
    assert cmd.linear_x == 0.0 and cmd.angular_z < 0.0


def test_slows_on_sharp_curvature_and_near_obstacles():
    ctrl = RPP()
    straight = ctrl.params.max_linear_vel
    # A tight arc (radius 0.4 < regulated_linear_scaling_min_radius 0.9).
    t = np.linspace(0, math.pi / 3, 40)
    tight = np.stack([0.4 * np.sin(t), 0.4 * (1 - np.cos(t)), t], axis=-1)
    from btnav.core.messages import Path

    long = np.concatenate(
        [
            tight,
            tight[-1]
            + np.stack(
                [
                    np.linspace(0.02, 2, 50) * math.cos(t[-1]),
                    np.linspace(0.02, 2, 50) * math.sin(t[-1]),
                    np.full(50, t[-1]),
                ],
                -1,
            )
            * [1, 1, 0],
        ]
    )
    ctrl.set_plan(Path(0.0, long))
    cmd = ctrl.compute_velocity_commands(Pose2D(), Twist(linear_x=0.3), free_costmap())
    assert 0 < cmd.linear_x < straight
    # Inflated cost under the robot slows it down (cost regulation).
    cm = free_costmap()
    cm.costs[:, :] = 200
    ctrl = RPP()
    ctrl.set_plan(straight_path())
    slow = ctrl.compute_velocity_commands(Pose2D(), Twist(linear_x=0.3), cm).linear_x
    assert slow < straight
    assert slow >= ctrl.params.regulated_linear_scaling_min_speed


def test_cost_regulation_measures_from_the_robots_edge_as_nav2_does():
    # Nav2 turns a centre cost into a distance with the layered costmap's inscribed radius:
    # (k r - ln cost + ln 253) / k; the server's radius makes the robot slow down less.
    cm = free_costmap()
    cm.costs[:, :] = 200
    server = costmap_server(robot_radius=0.22)
    speeds = []
    for configured in (False, True):
        ctrl = RPP(params=RPP.Params(use_cost_regulated_linear_velocity_scaling=True))
        if configured:
            ctrl.configure(server)
        ctrl.set_plan(straight_path())
        speeds.append(ctrl.compute_velocity_commands(Pose2D(), Twist(linear_x=0.3), cm).linear_x)
    p = ctrl.params
    clearance = math.log(253.0 / 200.0) / p.inflation_cost_scaling_factor
    expected = [
        max(
            p.max_linear_vel * p.cost_scaling_gain * d / p.cost_scaling_dist,
            p.regulated_linear_scaling_min_speed,
        )
        for d in (clearance, server.inscribed_radius + clearance)
    ]
    assert speeds == pytest.approx(expected, rel=1e-6)
    assert speeds[1] > speeds[0]


def test_approach_velocity_scaling():
    ctrl = RPP()
    ctrl.set_plan(straight_path())
    far = ctrl.compute_velocity_commands(
        Pose2D(1.0, 0, 0), Twist(linear_x=0.5), free_costmap()
    ).linear_x
    near = ctrl.compute_velocity_commands(
        Pose2D(3.8, 0, 0), Twist(linear_x=0.5), free_costmap()
    ).linear_x
    assert far == pytest.approx(0.5) and near < 0.25


def test_collision_ahead_raises():
    cm = free_costmap()
    mx = int((0.4 + 1.0) / cm.resolution)
    cm.costs[:, mx : mx + 4] = 254
    ctrl = RPP()
    ctrl.set_plan(straight_path())
    with pytest.raises(NoValidControl):
        ctrl.compute_velocity_commands(Pose2D(), Twist(linear_x=0.5), cm)


def test_registered_under_nav2s_name_and_drives_forward():
    # Its time per cycle against a 10 ms target is in bench/controllers.py.
    assert (
        lookup(
            "controller", "nav2_regulated_pure_pursuit_controller::RegulatedPurePursuitController"
        )
        is RPP
    )
    assert RPP.Params(desired_linear_vel=0.3).max_linear_vel == 0.3
    ctrl = RPP()
    ctrl.set_plan(curved_path())
    cm = free_costmap()
    cmd = ctrl.compute_velocity_commands(Pose2D(0.5, 0.0, 0.0), Twist(linear_x=0.4), cm)
    assert math.isfinite(cmd.linear_x) and math.isfinite(cmd.angular_z)
    assert cmd.linear_x > 0.0
