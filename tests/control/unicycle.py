"""A unicycle integrated from a controller's commands: enough to test controllers without a world."""

from __future__ import annotations

import math

import numpy as np

from btnav.core.geometry import Pose2D
from btnav.core.messages import Path, Twist
from btnav.costmap.costmap_2d import Costmap2D


def free_costmap(size_m: float = 12.0, res: float = 0.05, origin: float = -1.0) -> Costmap2D:
    n = round(size_m / res)
    return Costmap2D.empty(n, n, res, origin, origin, frame_id="odom")


def straight_path(length: float = 4.0, step: float = 0.05) -> Path:
    x = np.arange(0.0, length + 1e-9, step)
    return Path(0.0, np.stack([x, np.zeros_like(x), np.zeros_like(x)], axis=-1), "odom")


def curved_path(radius: float = 2.0, angle: float = math.pi / 2, step: float = 0.05) -> Path:
    """A straight metre, then a left arc of `radius` through `angle`."""
    x0 = np.arange(0.0, 1.0, step)
    straight = np.stack([x0, np.zeros_like(x0), np.zeros_like(x0)], axis=-1)
    t = np.arange(0.0, angle + 1e-9, step / radius)
    arc = np.stack([1.0 + radius * np.sin(t), radius * (1 - np.cos(t)), t], axis=-1)
    return Path(0.0, np.concatenate([straight, arc]), "odom")


def drive(
    controller,
    path: Path,
    costmap: Costmap2D,
    goal_checker,
    start: Pose2D | None = None,
    dt: float = 0.05,
    max_steps: int = 800,
    v_max: float = 1.0,
    w_max: float = 3.0,
):
    """Run the control loop; returns (final pose, list of commands, poses (N,3), reached)."""
    controller.set_plan(path)
    goal = Pose2D.from_array(path.poses[-1])
    goal_checker.reset()
    pose, vel = start or Pose2D(), Twist()
    cmds, poses = [], [pose.as_array()]
    for _ in range(max_steps):
        if goal_checker.is_goal_reached(pose, goal, vel):
            return pose, cmds, np.array(poses), True
        cmd = controller.compute_velocity_commands(pose, vel, costmap, goal_checker)
        v = float(np.clip(cmd.linear_x, -v_max, v_max))
        w = float(np.clip(cmd.angular_z, -w_max, w_max))
        yaw = pose.yaw + 0.5 * w * dt
        pose = Pose2D(
            pose.x + v * dt * math.cos(yaw), pose.y + v * dt * math.sin(yaw), pose.yaw + w * dt
        )
        vel = Twist(linear_x=v, angular_z=w)
        cmds.append((v, w))
        poses.append(pose.as_array())
    return pose, cmds, np.array(poses), False
