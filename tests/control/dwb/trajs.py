"""Hand-made DWB trajectory sets on a small costmap, as Nav2's critic tests build them.

The costmap is Nav2's test costmap: 5 m x 5 m at 0.1 m, origin (0, 0). Points on the
0.05 + 0.1 k grid are cell centres, never on a border.
"""

from __future__ import annotations

import math

import numpy as np

from btnav.control.dwb.critic import Trajectories
from btnav.core.geometry import Pose2D
from btnav.core.messages import Twist
from btnav.costmap.costmap_2d import Costmap2D

RES = 0.1
CELLS = 50


def costmap() -> Costmap2D:
    return Costmap2D.empty(CELLS, CELLS, RES, 0.0, 0.0, frame_id="odom")


def cell(x: float, y: float) -> tuple[int, int]:
    """(mx, my) of the cell holding world (x, y)."""
    return math.floor(x / RES), math.floor(y / RES)


def set_cost(cm: Costmap2D, mx: int, my: int, cost: int) -> Costmap2D:
    """Nav2's setCost(mx, my, cost)."""
    cm.costs[my, mx] = cost
    return cm


def straight(x0: float, y0: float, yaw: float, step: float, n: int) -> np.ndarray:
    k = np.arange(n)
    return np.stack(
        [x0 + k * step * math.cos(yaw), y0 + k * step * math.sin(yaw), np.full(n, yaw)], -1
    )


def ending_at(x: float, y: float, yaw: float, n: int = 5) -> np.ndarray:
    """n poses, all at (x, y, yaw): a trajectory of which only the end matters."""
    return np.tile([x, y, yaw], (n, 1)).astype(float)


def trajectories(poses, velocities=None, dt: float = 0.1) -> Trajectories:
    """S trajectories from a list of (T, 3) pose arrays (one length), with their (vx, vy, wz)."""
    poses = np.asarray(poses, float)
    if velocities is None:
        velocities = np.zeros((len(poses), 3))
    return Trajectories(np.asarray(velocities, float).reshape(-1, 3), poses, dt)


def velocity_set(velocities, dt: float = 0.1, n: int = 5) -> Trajectories:
    """Trajectories for commanded (vx, vy, wz), integrated from the origin (the poses
    matter little to the critics that read velocities)."""
    v = np.asarray(velocities, float).reshape(-1, 3)
    k = np.arange(n)[None, :]
    yaw = v[:, 2:3] * k * dt
    poses = np.stack([v[:, 0:1] * k * dt, v[:, 1:2] * k * dt, yaw], -1)
    return Trajectories(v, poses, dt)


def line_plan(x0: float, y0: float, x1: float, y1: float, step: float = 0.05) -> np.ndarray:
    """A plan from (x0, y0) to (x1, y1), points `step` apart, as planners make them."""
    n = max(round(math.hypot(x1 - x0, y1 - y0) / step), 1)
    t = np.arange(n + 1)[:, None] / n
    yaw = math.atan2(y1 - y0, x1 - x0)
    xy = np.array([x0, y0]) + t * np.array([x1 - x0, y1 - y0])
    return np.concatenate([xy, np.full((n + 1, 1), yaw)], axis=1)


def prepare(critic, pose: Pose2D, plan: np.ndarray, cm: Costmap2D, velocity: Twist | None = None):
    """Nav2's prepare(pose, velocity, goal, plan), the goal being the plan's last pose."""
    goal = Pose2D.from_array(plan[-1])
    return critic.prepare(pose, velocity or Twist(), goal, plan, cm)
