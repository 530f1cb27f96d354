"""The robot's motion simulated forward at a constant command (nav2_collision_monitor's
kinematics.cpp), for the approach action."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ..core import fmath
from ..core.messages import Twist


def step_times(horizon: float, dt: float) -> list[float]:
    """The times Nav2's simulation loop visits: 0, dt, 2 dt, ... accumulated as Nav2
    adds them, while <= `horizon` (the sum's rounding decides the last: 13 times for
    1.2 s in steps of 0.1, but 3 for 0.3 s, as 0.1 + 0.1 + 0.1 > 0.3)."""
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
    for k in range(steps):  # a few dozen steps (Nav2's arithmetic, step by step)
        x += vx * dt
        y += vy * dt
        theta += velocity.angular_z * dt
        vx, vy = vx * c - vy * s, vx * s + vy * c
        out[k] = (x, y, theta)
    return out
