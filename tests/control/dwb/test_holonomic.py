"""DWB drives a holonomic base sideways: the shipped omni section strafes along a path that
runs to the robot's left and keeps its heading, on a base that honours vx, vy and wz."""

from __future__ import annotations

import math
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import yaml

from btnav.control.dwb import DWBLocalPlanner
from btnav.control.dwb.local_planner import DWBParams
from btnav.control.goal_checkers import SimpleGoalChecker
from btnav.core.geometry import Pose2D
from btnav.core.messages import Path as PlanPath
from btnav.core.messages import Twist

from ..unicycle import free_costmap

REPO = Path(__file__).resolve().parents[3]
RECTANGLE = np.array([[-0.35, -0.15], [0.35, -0.15], [0.35, 0.15], [-0.35, 0.15]])


def omni_section(**changes) -> DWBParams:
    """params/omni_nav2_params.yaml's FollowPathDWB, as the controller server reads it."""
    doc = yaml.safe_load((REPO / "params" / "omni_nav2_params.yaml").read_text())
    section = dict(doc["controller_server"]["ros__parameters"]["FollowPathDWB"])
    section.pop("plugin")
    return DWBParams.model_validate({**section, **changes})


def leftward_path(length: float = 2.0, step: float = 0.05) -> PlanPath:
    """Straight to the robot's left (+y), its poses facing along it, as NavFn's do."""
    y = np.arange(0.0, length + 1e-9, step)
    poses = np.stack([np.zeros_like(y), y, np.full_like(y, math.pi / 2)], axis=-1)
    return PlanPath(0.0, poses, "odom")


def drive_holonomic(dwb: DWBLocalPlanner, path: PlanPath, max_steps: int = 400, dt: float = 0.05):
    """The control loop on a base that moves as commanded (vx, vy in its own frame, wz)."""
    dwb.set_plan(path)
    checker = SimpleGoalChecker()
    goal = Pose2D.from_array(path.poses[-1])
    goal = Pose2D(goal.x, goal.y, 0.0)  # reach it facing +x, as the robot starts
    pose, vel = Pose2D(), Twist()
    poses, cmds = [pose.as_array()], []
    costmap = free_costmap()
    for _ in range(max_steps):
        if checker.is_goal_reached(pose, goal, vel):
            return np.array(poses), np.array(cmds), True
        cmd = dwb.compute_velocity_commands(pose, vel, costmap, checker)
        c, s = math.cos(pose.yaw), math.sin(pose.yaw)
        pose = Pose2D(
            pose.x + (cmd.linear_x * c - cmd.linear_y * s) * dt,
            pose.y + (cmd.linear_x * s + cmd.linear_y * c) * dt,
            pose.yaw + cmd.angular_z * dt,
        )
        vel = cmd
        poses.append(pose.as_array())
        cmds.append((cmd.linear_x, cmd.linear_y, cmd.angular_z))
    return np.array(poses), np.array(cmds), False


def test_the_omni_section_strafes_to_a_goal_on_its_left_without_turning():
    path = leftward_path()
    goal = path.poses[-1]
    dwb = DWBLocalPlanner(params=omni_section())
    dwb.configure(SimpleNamespace(footprint=RECTANGLE))
    poses, cmds, reached = drive_holonomic(dwb, path)
    assert reached
    assert math.hypot(poses[-1, 0] - goal[0], poses[-1, 1] - goal[1]) <= 0.25
    assert np.abs(poses[:, 2]).max() < 0.05  # heading held: it slid, it did not turn
    assert cmds[:, 1].max() >= 0.4  # strafing near the 0.5 m/s limit
    assert np.abs(poses[:, 0]).max() < 0.15  # along the path, not round a turn
    assert np.hypot(cmds[:, 0], cmds[:, 1]).max() <= 0.5 + 1e-6  # max_speed_xy


def test_without_strafe_samples_the_same_section_gets_nowhere_to_the_left():
    # max_vel_y = min_vel_y = 0, all else the same: no sample has vy, and Twirling (400 per
    # rad/s) outweighs what turning towards the path would gain: in 7.5 s it has not moved
    dwb = DWBLocalPlanner(params=omni_section(min_vel_y=0.0, max_vel_y=0.0))
    dwb.configure(SimpleNamespace(footprint=RECTANGLE))
    poses, cmds, reached = drive_holonomic(dwb, leftward_path(), max_steps=150)
    assert (cmds[:, 1] == 0.0).all()
    assert not reached and poses[:, 1].max() < 0.2
