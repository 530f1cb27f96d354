"""dwb_plugins: velocity sampling and trajectory simulation, vectorised.

`StandardTrajectoryGenerator` samples (vx, vy, wz) in the window reachable from
the current velocity within `sim_time` (acceleration limits), and simulates each
sample over `sim_time`, ramping from the current velocity towards it at the
acceleration limits. `LimitedAccelGenerator` (dwb_plugins::LimitedAccelGenerator)
uses the window reachable within one control period and holds the sampled
velocity constant. The samples are Nav2's XYThetaIterator's (per axis, zero
included where the window straddles it; see `axis_samples`), filtered by
`KinematicParameters.valid_speeds`. All samples share one time step (the finest any
sample needs under linear/angular granularity, or time_granularity; Nav2 steps each
sample by its own), so the whole set is one (S, T, 3) array.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ...core import fmath
from ...core.geometry import Pose2D
from ...core.messages import Twist
from .critic import Trajectories
from .kinematic_parameters import KinematicParameters

#: OneDVelocityIterator's EPSILON: a window narrower than this is one velocity.
EPSILON = 1e-5


def axis_samples(
    current: float, lo: float, hi: float, acc: float, dec: float, acc_time: float, n: int
) -> NDArray[np.float64]:
    """One axis of the window (dwb_plugins::OneDVelocityIterator), in its order.

    The current velocity is first clamped into [lo, hi], then the window is what
    `acc` (up) and `dec` (down, magnitudes) reach within `acc_time`. A window under
    EPSILON wide is its lower end alone; otherwise at least two evenly spaced samples,
    both ends included, and zero where the samples step from below zero to above it
    (so stopping one axis, driving straight or not strafing, is always a choice).
    """
    c = min(max(current, lo), hi)
    top = min(hi, c + acc * acc_time) if c < hi else hi
    bottom = max(lo, c - dec * acc_time) if c > lo else lo
    if abs(top - bottom) < EPSILON:
        return np.array([bottom])
    values = np.linspace(bottom, top, max(2, int(n)))
    cross = np.flatnonzero((values[:-1] < 0.0) & (values[1:] > 0.0))
    if cross.size:
        values = np.insert(values, cross[0] + 1, 0.0)
    return values


def sample_velocities(
    kin: KinematicParameters,
    counts: tuple[int, int, int],
    velocity: Twist,
    acc_time: float,
) -> NDArray[np.float64]:
    """(S, 3) valid (vx, vy, wz) samples in the dynamic window (dwb_plugins::XYThetaIterator).

    Every combination of the three axes' samples (`counts`: vx_samples, vy_samples,
    vtheta_samples), x slowest and theta fastest as Nav2 iterates, less those
    `KinematicParameters.valid_speeds` rejects (max_speed_xy, min_speed_xy with
    min_speed_theta, the zero twist). A base with max_vel_y = min_vel_y = 0 gets vy = 0
    only; a holonomic one gets vy_samples strafe speeds (and zero).
    """
    cur = (velocity.linear_x, velocity.linear_y, velocity.angular_z)
    axes = [
        axis_samples(c, lo, hi, acc, dec, acc_time, n)
        for c, (lo, hi, acc, dec), n in zip(cur, kin.axes(), counts, strict=True)
    ]
    vx, vy, w = np.meshgrid(*axes, indexing="ij")
    v = np.stack([vx.ravel(), vy.ravel(), w.ravel()], axis=-1)
    return v[kin.valid_speeds(v)]


def simulate(
    p: Any,
    kin: KinematicParameters,
    pose: Pose2D,
    velocity: Twist,
    samples: NDArray[np.float64],
    limited: bool,
) -> Trajectories:
    """Roll every sample out over `p.sim_time` from `pose` (no Python loop over samples or steps).

    Each step moves the robot by its body-frame (vx, vy) turned to the step's starting
    heading, as Nav2's computeNewPosition does, so a strafing sample slides sideways.
    The poses are the start and one per step; `include_last_point` repeats the last one
    (Nav2's trajectories carry that duplicate: it weighs in `sum` and `product` scores).
    """
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
        acc = np.array([a for _lo, _hi, a, _d in kin.axes()])
        dec = np.array([d for _lo, _hi, _a, d in kin.axes()])
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
    last = steps + 1 if p.include_last_point else steps
    poses = np.empty((len(samples), last + 1, 3))
    poses[:, 0] = (pose.x, pose.y, pose.yaw)
    poses[:, 1 : steps + 1, 0] = pose.x + np.cumsum(dx, axis=1)
    poses[:, 1 : steps + 1, 1] = pose.y + np.cumsum(dy, axis=1)
    poses[:, 1 : steps + 1, 2] = theta[:, 1:]
    if p.include_last_point:
        poses[:, -1] = poses[:, steps]
    return Trajectories(samples, poses, dt)
