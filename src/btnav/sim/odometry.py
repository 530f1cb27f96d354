"""Wheel odometry: dead reckoning of the true motion with AMCL's differential noise model.

Each update splits the true motion since the last one into AMCL's (rot1, trans,
rot2) and perturbs each part with zero-mean Gaussian noise whose *variance* is
linear in the motion (per metre or radian), not quadratic as in AMCL's sampler:

    var(rot1)  = alpha1 * |rot1| + alpha2 * |trans|
    var(trans) = alpha3 * |trans| + alpha4 * (|rot1| + |rot2|)
    var(rot2)  = alpha1 * |rot2| + alpha2 * |trans|

Variances of independent increments add, so the drift after a path depends on the
path (its length and total turning) and not on how often odometry is published:
N updates of d metres give the variance of one update of N*d metres. With
variances quadratic in the motion, doubling the rate would halve the drift.

Over a straight line of length D (rot1 = rot2 = 0) the heading variance grows by
2*alpha2*D and the along-track variance by alpha3*D; over an in-place turn of angle
A the heading variance grows by alpha1*A and the position variance by alpha4*A.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from ..core import fmath
from ..core.geometry import Pose2D
from ..core.messages import Odometry
from ..core.rng import stream
from .world import World

#: Below this translation (m) an update counts as a pure rotation for the noise: the
#: direction of a nanometre of solver jitter is meaningless, and reading it as a
#: quarter turn would add a quarter turn's worth of rotation noise.
MIN_TRANSLATION = 1e-6
#: Updates' worth of noise drawn from the stream at once.
_NOISE_BLOCK = 256


def decompose(dx: float, dy: float, dyaw: float) -> tuple[float, float, float]:
    """A robot-frame motion as (rot1, trans, rot2): turn, drive straight, turn (exact).

    Driving backwards is a negative `trans` with a small `rot1` (AMCL takes the
    smaller of rot1 and rot1 - pi for the same reason), so reversing is not read
    as two half turns.
    """
    trans = math.hypot(dx, dy)
    if dx < 0.0:
        trans = -trans
        rot1 = fmath.arctan2(-dy, -dx)
    else:
        rot1 = fmath.arctan2(dy, dx)
    return rot1, trans, dyaw - rot1


def _stds(
    rot1: float, trans: float, rot2: float, dyaw: float, alphas: tuple[float, ...] | NDArray
) -> tuple[float, float, float]:
    """Standard deviations of the (rot1, trans, rot2) noise: variances linear in the motion."""
    a1, a2, a3, a4 = (float(a) for a in alphas)
    t, r1, r2 = abs(trans), abs(rot1), abs(rot2)
    if t < MIN_TRANSLATION:  # a turn in place (plus jitter): its noise is a turn's
        r1, r2 = 0.0, abs(dyaw)
    return (
        math.sqrt(a1 * r1 + a2 * t),
        math.sqrt(a3 * t + a4 * (r1 + r2)),
        math.sqrt(a1 * r2 + a2 * t),
    )


def sample_motion(
    poses: NDArray[np.float64],
    motion: tuple[float, float, float],
    alphas: tuple[float, float, float, float] | NDArray[np.float64],
    rng: np.random.Generator,
) -> NDArray[np.float64]:
    """Apply one true robot-frame `motion` (dx, dy, dyaw) with noise to (N, 3) odometry poses.

    Vectorised over N so statistics over many runs are cheap; the yaw is not wrapped
    (callers wrap it when they make a `Pose2D`).
    """
    rot1, trans, rot2 = decompose(*motion)
    std = np.array(_stds(rot1, trans, rot2, motion[2], alphas))
    noise = rng.standard_normal((poses.shape[0], 3)) * std
    h_rot1 = rot1 + noise[:, 0]
    h_trans = trans + noise[:, 1]
    h_rot2 = rot2 + noise[:, 2]
    out = np.empty_like(poses)
    heading = poses[:, 2] + h_rot1
    sin, cos = fmath.sincos(heading)
    out[:, 0] = poses[:, 0] + h_trans * cos
    out[:, 1] = poses[:, 1] + h_trans * sin
    out[:, 2] = heading + h_rot2
    return out


class WheelOdometry:
    """The odom -> base_footprint estimate a diff-drive base publishes.

    The pose starts at identity at the robot's start pose (REP-105's odom frame).
    The twist is the body's true velocity: encoders measure speed well; what drifts
    is its integral, which is what the noise models.
    """

    def __init__(
        self,
        world: World,
        *,
        alphas: tuple[float, float, float, float] | None = None,
        rate: float | None = None,
        rng: np.random.Generator | None = None,
        seed: int = 0,
    ) -> None:
        spec = world.spec.robot.odometry
        self.world = world
        self.alphas = tuple(float(a) for a in (alphas if alphas is not None else spec.noise))
        self.rate = float(rate if rate is not None else spec.rate)
        if not self.rate > 0:
            raise ValueError(f"an odometry rate must be positive, got {self.rate}")
        self.rng = rng if rng is not None else stream(seed, "odometry")
        self.frame_id = "odom"
        self.child_frame_id = "base_footprint"
        body = world.robot.body
        self._true = (*body.position, body.angle)  # x, y, unwrapped yaw in the world
        self._noise: list[list[float]] = []
        self._noise_next = 0
        self._pose = (0.0, 0.0, 0.0)  # x, y and unwrapped yaw in odom
        self.last = Odometry(world.time, Pose2D(), world.robot_twist)

    @property
    def pose(self) -> Pose2D:
        """The latest odometry pose in `odom`."""
        return self.last.pose

    def _next_noise(self) -> tuple[float, float, float]:
        """Three standard normal draws, taken from the stream in blocks (the same values
        as drawing them one update at a time, at a fraction of the calls)."""
        if self._noise_next >= len(self._noise):
            self._noise = self.rng.standard_normal((_NOISE_BLOCK, 3)).tolist()
            self._noise_next = 0
        self._noise_next += 1
        return self._noise[self._noise_next - 1]

    def update(self, now: float) -> Odometry:
        """Integrate the true motion since the last update (with noise); stamp it `now`."""
        body = self.world.robot.body
        tx, ty = body.position
        yaw = body.angle  # unwrapped: odometry integrates its differences
        px, py, pyaw = self._true
        s, c = fmath.sincos(pyaw)
        ddx, ddy = tx - px, ty - py
        motion = (c * ddx + s * ddy, -s * ddx + c * ddy, yaw - pyaw)
        # sample_motion for one run, in floats (same draws, a few times faster).
        rot1, trans, rot2 = decompose(*motion)
        s1, st, s2 = _stds(rot1, trans, rot2, motion[2], self.alphas)
        n1, nt, n2 = self._next_noise()
        x, y, th = self._pose
        heading = th + rot1 + n1 * s1
        sh, ch = fmath.sincos(heading)
        x += (trans + nt * st) * ch
        y += (trans + nt * st) * sh
        th = heading + rot2 + n2 * s2
        self._pose = (x, y, th)
        self._true = (tx, ty, yaw)
        self.last = Odometry(now, Pose2D(x, y, th), self.world.robot_twist)
        return self.last

    measure = update


def make_odometry(world: World, seed: int = 0) -> WheelOdometry:
    """The world's odometry as its file configures it, on the seed's `odometry` stream."""
    return WheelOdometry(world, rng=stream(seed, "odometry"))
