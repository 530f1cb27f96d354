"""The robot's motion simulated forward at a constant command, and points seen from the
poses it passes (nav2_collision_monitor/kinematics.cpp), for the approach action."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ..core import fmath
from ..core.messages import Twist


def step_times(horizon: float, dt: float) -> list[float]:
    """The times Nav2's simulation loop visits: 0, dt, 2 dt, ... accumulated as Nav2
    adds them, while <= `horizon` (so 12 steps, not 13, for 1.2 s in steps of 0.1)."""
    times = []
    t = 0.0
    while t <= horizon:
        times.append(t)
        t += dt
    return times


def projected_poses(velocity: Twist, dt: float, steps: int) -> NDArray[np.float64]:
    """(steps, 3) poses x, y, theta after 1, 2, ... steps of `dt` from the origin.

    Nav2's projectState: the position moves by the velocity, then the velocity vector
    turns with the robot by `angular_z * dt`, so the path is a polygonal arc.
    """
    out = np.empty((steps, 3))
    s, c = fmath.sincos(velocity.angular_z * dt)
    x = y = theta = 0.0
    vx, vy = velocity.linear_x, velocity.linear_y
    for k in range(steps):  # a few dozen steps; the points are transformed all at once
        x += vx * dt
        y += vy * dt
        theta += velocity.angular_z * dt
        vx, vy = vx * c - vy * s, vx * s + vy * c
        out[k] = (x, y, theta)
    return out


def points_seen_from(
    poses: NDArray[np.float64], points: NDArray[np.float64]
) -> NDArray[np.float64]:
    """(T, N, 2): `points` (N, 2) in the frame of each of `poses` (T, 3)."""
    s, c = fmath.sincos(poses[:, 2])
    dx = points[None, :, 0] - poses[:, 0, None]
    dy = points[None, :, 1] - poses[:, 1, None]
    out = np.empty((len(poses), len(points), 2))
    out[..., 0] = dx * c[:, None] + dy * s[:, None]
    out[..., 1] = -dx * s[:, None] + dy * c[:, None]
    return out
