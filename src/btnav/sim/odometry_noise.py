"""How wheel odometry drifts, per drive: AMCL's differential and omni models, run forward.

Each update perturbs the true robot-frame motion's parts (AMCL's rot1, trans, rot2; for
omni nav2_amcl::OmniMotionModel's trans, strafe, rot) with zero-mean Gaussian noise whose
*variance* is linear in the motion, not quadratic as in AMCL's sampler: variances of
independent increments add, so the drift after a path depends on the path and not on how
often odometry is published. The formulas: docs/decisions/0022.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from ..core import fmath

#: Below this translation (m) an update counts as a pure rotation for the noise: the
#: direction of a nanometre of solver jitter is meaningless, and reading it as a
#: quarter turn would add a quarter turn's worth of rotation noise.
MIN_TRANSLATION = 1e-6

Pose = tuple[float, float, float]


class OdometryNoise:
    """One drive's odometry noise: `step` moves an odometry pose by a noisy true motion."""

    def step(
        self, pose: Pose, motion: Pose, alphas: Sequence[float], draws: Sequence[float]
    ) -> Pose:
        """The odometry pose (x, y, unwrapped yaw) after the true robot-frame `motion`
        (dx, dy, dyaw), perturbed with three standard normal `draws`."""
        raise NotImplementedError


def decompose(dx: float, dy: float, dyaw: float) -> tuple[float, float, float]:
    """A robot-frame motion as (rot1, trans, rot2): turn, drive straight, turn (exact).

    Driving backwards is a negative `trans` with a small `rot1` (AMCL takes the
    smaller of rot1 and rot1 - pi for the same reason), so reversing is not read
    as two half turns.
    """
    trans = fmath.hypot(dx, dy)
    if dx < 0.0:
        trans = -trans
        rot1 = fmath.arctan2(-dy, -dx)
    else:
        rot1 = fmath.arctan2(dy, dx)
    return rot1, trans, dyaw - rot1


def differential_stds(
    rot1: float, trans: float, rot2: float, dyaw: float, alphas: Sequence[float]
) -> tuple[float, float, float]:
    """Standard deviations of the (rot1, trans, rot2) noise: variances linear in the motion."""
    a1, a2, a3, a4 = (float(a) for a in alphas[:4])
    t, r1, r2 = abs(trans), abs(rot1), abs(rot2)
    if t < MIN_TRANSLATION:  # a turn in place (plus jitter): its noise is a turn's
        r1, r2 = 0.0, abs(dyaw)
    return (
        math.sqrt(a1 * r1 + a2 * t),
        math.sqrt(a3 * t + a4 * (r1 + r2)),
        math.sqrt(a1 * r2 + a2 * t),
    )


class DiffDriveNoise(OdometryNoise):
    """AMCL's differential model: rot1, trans, rot2, each with its own noise."""

    def step(
        self, pose: Pose, motion: Pose, alphas: Sequence[float], draws: Sequence[float]
    ) -> Pose:
        rot1, trans, rot2 = decompose(*motion)
        s1, st, s2 = differential_stds(rot1, trans, rot2, motion[2], alphas)
        n1, nt, n2 = draws
        x, y, th = pose
        heading = th + rot1 + n1 * s1
        sh, ch = fmath.sincos(heading)
        x += (trans + nt * st) * ch
        y += (trans + nt * st) * sh
        return x, y, heading + rot2 + n2 * s2


class OmniNoise(OdometryNoise):
    """AMCL's omni model: translation along the bearing, strafe across it, rotation."""

    def step(
        self, pose: Pose, motion: Pose, alphas: Sequence[float], draws: Sequence[float]
    ) -> Pose:
        dx, dy, rot = motion
        a1, a2, a3, a4, a5 = (float(a) for a in (*alphas, 0.0)[:5])
        trans, r = fmath.hypot(dx, dy), abs(rot)
        st = math.sqrt(a3 * trans + a4 * r)
        sr = math.sqrt(a1 * r + a2 * trans)
        ss = math.sqrt(a4 * r + a5 * trans)
        nt, nr, ns = draws
        x, y, th = pose
        bearing = th + (fmath.arctan2(dy, dx) if trans >= MIN_TRANSLATION else 0.0)
        sb, cb = fmath.sincos(bearing)
        along, strafe = trans + nt * st, ns * ss
        return x + along * cb + strafe * sb, y + along * sb - strafe * cb, th + rot + nr * sr


def sample_motion(
    poses: NDArray[np.float64],
    motion: Pose,
    alphas: Sequence[float] | NDArray[np.float64],
    rng: np.random.Generator,
) -> NDArray[np.float64]:
    """The differential model over (N, 3) odometry poses at once, for drift statistics
    over many runs (the yaw is not wrapped; callers wrap it when they make a `Pose2D`)."""
    rot1, trans, rot2 = decompose(*motion)
    std = np.array(differential_stds(rot1, trans, rot2, motion[2], list(alphas)))
    noise = rng.standard_normal((poses.shape[0], 3)) * std
    out = np.empty_like(poses)
    heading = poses[:, 2] + (rot1 + noise[:, 0])
    sin, cos = fmath.sincos(heading)
    out[:, 0] = poses[:, 0] + (trans + noise[:, 1]) * cos
    out[:, 1] = poses[:, 1] + (trans + noise[:, 1]) * sin
    out[:, 2] = heading + (rot2 + noise[:, 2])
    return out
