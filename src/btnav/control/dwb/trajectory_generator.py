"""dwb_plugins: kinematic limits, velocity sampling and trajectory simulation, vectorised.

`StandardTrajectoryGenerator` samples (vx, vy, wz) in the window reachable from
the current velocity within `sim_time` (acceleration limits), and simulates each
sample over `sim_time`, ramping from the current velocity towards it at the
acceleration limits. `LimitedAccelGenerator` (dwb_plugins::LimitedAccelGenerator)
uses the window reachable within one control period and holds the sampled
velocity constant. All samples share one time step (the finest any sample
needs under linear/angular granularity, or time_granularity), so the whole set
is one (S, T, 3) array.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from ...core import fmath
from ...core.geometry import Pose2D
from ...core.messages import Twist
from .critic import Trajectories


def sample_velocities(p, velocity: Twist, acc_time: float) -> NDArray[np.float64]:
    """(S, 3) valid velocity samples in the dynamic window (dwb_plugins::XYThetaIterator)."""
    cur = (velocity.linear_x, velocity.linear_y, velocity.angular_z)
    lims = (
        (p.min_vel_x, p.max_vel_x, p.acc_lim_x, p.decel_lim_x, p.vx_samples),
        (p.min_vel_y, p.max_vel_y, p.acc_lim_y, p.decel_lim_y, p.vy_samples),
        (-p.max_vel_theta, p.max_vel_theta, p.acc_lim_theta, p.decel_lim_theta, p.vtheta_samples),
    )
    axes = []
    for c, lo, hi, acc, dec, n in zip(cur, *zip(*lims, strict=True), strict=True):
        a = max(lo, c - abs(dec) * acc_time)
        b = min(hi, c + abs(acc) * acc_time)
        if a > b:  # the current velocity is outside the limits: the nearest limit
            a = b = min(max(c, lo), hi)
        if n <= 1 or a == b:
            axes.append(np.array([min(max(0.0, a), b) if n <= 1 else a]))
        else:
            axes.append(np.linspace(a, b, int(n)))
    vx, vy, w = np.meshgrid(*axes, indexing="ij")
    v = np.stack([vx.ravel(), vy.ravel(), w.ravel()], axis=-1)
    speed = fmath.hypot(v[:, 0], v[:, 1])
    ok = np.ones(len(v), bool)
    if p.max_speed_xy >= 0.0:
        ok &= speed <= p.max_speed_xy + 1e-9
    ok &= ~((speed < p.min_speed_xy) & (np.abs(v[:, 2]) < p.min_speed_theta))
    return v[ok]


def simulate(
    p, pose: Pose2D, velocity: Twist, samples: NDArray[np.float64], limited: bool
) -> Trajectories:
    """Roll every sample out over sim_time from `pose` (no Python loop over samples or steps)."""
    sim = p.sim_time
    if p.discretize_by_time:
        steps = max(math.ceil(sim / p.time_granularity), 1)
    else:
        lin = fmath.hypot(samples[:, 0], samples[:, 1]).max(initial=0.0) * sim
        ang = np.abs(samples[:, 2]).max(initial=0.0) * sim
        steps = max(
            math.ceil(lin / p.linear_granularity), math.ceil(ang / p.angular_granularity), 1
        )
    dt = sim / steps
    k = np.arange(1, steps + 1)  # step index (velocity applied during step k)
    if limited:
        vel = np.broadcast_to(samples[:, None, :], (len(samples), steps, 3))
    else:
        cur = np.array([velocity.linear_x, velocity.linear_y, velocity.angular_z])
        acc = np.abs([p.acc_lim_x, p.acc_lim_y, p.acc_lim_theta])
        dec = np.abs([p.decel_lim_x, p.decel_lim_y, p.decel_lim_theta])
        diff = samples - cur  # (S, 3)
        rate = np.where(diff > 0, acc, dec)  # (S, 3)
        rate = np.where(rate > 0, rate, np.inf)  # a zero limit means "no limit"
        ramp = np.minimum(np.abs(diff)[:, None, :], rate[:, None, :] * (k * dt)[None, :, None])
        vel = cur + np.sign(diff)[:, None, :] * ramp
    theta = pose.yaw + np.concatenate(
        [np.zeros((len(samples), 1)), np.cumsum(vel[..., 2] * dt, axis=1)], axis=1
    )
    s, c = fmath.sincos(theta[:, :-1])
    dx = (vel[..., 0] * c - vel[..., 1] * s) * dt
    dy = (vel[..., 0] * s + vel[..., 1] * c) * dt
    poses = np.empty((len(samples), steps + 1, 3))
    poses[:, 0] = (pose.x, pose.y, pose.yaw)
    poses[:, 1:, 0] = pose.x + np.cumsum(dx, axis=1)
    poses[:, 1:, 1] = pose.y + np.cumsum(dy, axis=1)
    poses[:, 1:, 2] = theta[:, 1:]
    if not p.include_last_point:
        poses = poses[:, :-1]
    return Trajectories(samples, poses, dt)
