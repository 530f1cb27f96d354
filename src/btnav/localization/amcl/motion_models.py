"""nav2_amcl's motion models: move every particle by the odometry delta, with noise.

`odometry_update(poses, pose, delta, rng)` takes the particles (N, 3), the odometry
pose now and the change since the last filter update (dx, dy in the odom frame, dyaw
wrapped), as nav2_amcl's `MotionModel::odometryUpdate`, and returns the moved
particles. The noise is sampled per particle (Probabilistic Robotics' sample_motion_
model_odometry); the standard deviations are those of nav2_amcl, quadratic in the
motion: std(rot1) = sqrt(alpha1 rot1^2 + alpha2 trans^2), and so on.

- `DifferentialMotionModel` (alpha1..alpha4): rot1, trans, rot2 with rotations read as
  the smaller of the turn and the turn minus pi, so driving backwards is not two half
  turns of noise; under 1 cm of travel rot1 is 0 (an in-place turn).
- `OmniMotionModel` (alpha1..alpha5): translation along the odometry bearing, a
  strafe across it (alpha5 from translation, alpha4 from rotation) and a rotation.
"""

from __future__ import annotations

import math
from typing import ClassVar

import numpy as np
from numpy.typing import NDArray

from ...core import fmath
from ...core.geometry import normalize_angle
from ...plugins import canonical

F64 = NDArray[np.float64]


def _turn_noise(rot: float) -> float:
    """|rot| or |rot - pi|, the smaller (nav2_amcl's delta_rot_noise)."""
    return min(abs(normalize_angle(rot)), abs(normalize_angle(rot - math.pi)))


class MotionModel:
    """The noise parameters and `odometry_update` of one of nav2_amcl's models."""

    NAME: ClassVar[str] = ""

    def __init__(
        self, alpha1: float, alpha2: float, alpha3: float, alpha4: float, alpha5: float = 0.0
    ) -> None:
        self.alpha1, self.alpha2, self.alpha3, self.alpha4, self.alpha5 = (
            float(alpha1),
            float(alpha2),
            float(alpha3),
            float(alpha4),
            float(alpha5),
        )

    def odometry_update(
        self,
        poses: F64,
        pose: tuple[float, float, float],
        delta: tuple[float, float, float],
        rng: np.random.Generator,
    ) -> F64:
        raise NotImplementedError


class DifferentialMotionModel(MotionModel):
    """nav2_amcl::DifferentialMotionModel."""

    NAME = "nav2_amcl::DifferentialMotionModel"

    def stds(
        self, pose: tuple[float, float, float], delta: tuple[float, float, float]
    ) -> tuple[float, float, float, float, float, float]:
        """(rot1, trans, rot2) of the odometry delta and the std of the noise on each."""
        dx, dy, dyaw = delta
        trans = fmath.hypot(dx, dy)
        old_yaw = pose[2] - dyaw
        rot1 = 0.0 if trans < 0.01 else normalize_angle(fmath.arctan2(dy, dx) - old_yaw)
        rot2 = normalize_angle(dyaw - rot1)
        n1, n2 = _turn_noise(rot1), _turn_noise(rot2)
        a1, a2, a3, a4 = self.alpha1, self.alpha2, self.alpha3, self.alpha4
        t2 = trans * trans
        return (
            rot1,
            trans,
            rot2,
            math.sqrt(a1 * n1 * n1 + a2 * t2),
            math.sqrt(a3 * t2 + a4 * n1 * n1 + a4 * n2 * n2),
            math.sqrt(a1 * n2 * n2 + a2 * t2),
        )

    def odometry_update(
        self,
        poses: F64,
        pose: tuple[float, float, float],
        delta: tuple[float, float, float],
        rng: np.random.Generator,
    ) -> F64:
        rot1, trans, rot2, s1, st, s2 = self.stds(pose, delta)
        noise = rng.standard_normal((3, poses.shape[0]))
        rot1_hat = normalize_angle(rot1 - noise[0] * s1)
        trans_hat = trans - noise[1] * st
        rot2_hat = normalize_angle(rot2 - noise[2] * s2)
        heading = poses[:, 2] + rot1_hat
        s, c = fmath.sincos(heading)
        out = np.empty_like(poses)
        out[:, 0] = poses[:, 0] + trans_hat * c
        out[:, 1] = poses[:, 1] + trans_hat * s
        out[:, 2] = normalize_angle(heading + rot2_hat)
        return out


class OmniMotionModel(MotionModel):
    """nav2_amcl::OmniMotionModel."""

    NAME = "nav2_amcl::OmniMotionModel"

    def stds(self, delta: tuple[float, float, float]) -> tuple[float, float, float]:
        """std of the (translation, rotation, strafe) noise for the odometry delta."""
        dx, dy, rot = delta
        t2, r2 = dx * dx + dy * dy, rot * rot
        return (
            math.sqrt(self.alpha3 * t2 + self.alpha4 * r2),
            math.sqrt(self.alpha1 * r2 + self.alpha2 * t2),
            math.sqrt(self.alpha4 * r2 + self.alpha5 * t2),
        )

    def odometry_update(
        self,
        poses: F64,
        pose: tuple[float, float, float],
        delta: tuple[float, float, float],
        rng: np.random.Generator,
    ) -> F64:
        dx, dy, rot = delta
        trans = fmath.hypot(dx, dy)
        st, sr, ss = self.stds(delta)
        old_yaw = pose[2] - rot
        bearing = normalize_angle(fmath.arctan2(dy, dx) - old_yaw) + poses[:, 2]
        s, c = fmath.sincos(bearing)
        noise = rng.standard_normal((3, poses.shape[0]))
        trans_hat = trans + noise[0] * st
        rot_hat = rot + noise[1] * sr
        strafe_hat = noise[2] * ss
        out = np.empty_like(poses)
        out[:, 0] = poses[:, 0] + (trans_hat * c + strafe_hat * s)
        out[:, 1] = poses[:, 1] + (trans_hat * s - strafe_hat * c)
        out[:, 2] = normalize_angle(poses[:, 2] + rot_hat)
        return out


MOTION_MODELS: dict[str, type[MotionModel]] = {
    canonical(m.NAME): m for m in (DifferentialMotionModel, OmniMotionModel)
}


def make_motion_model(name: str, alphas: tuple[float, float, float, float, float]) -> MotionModel:
    """nav2_amcl's `robot_model_type` (already checked by the params schema)."""
    return MOTION_MODELS[canonical(name)](*alphas)
