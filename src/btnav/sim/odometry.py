"""Wheel odometry: dead reckoning of the true motion, drifting as the drive's noise model says.

Each update takes the true robot-frame motion since the last one and moves the odometry
pose by it, perturbed by the drive's `odometry_noise` (AMCL's differential model for a
diff drive or a car, its omni model for an omni base; `odometry_noise.py`), with
variances linear in the motion so the drift does not depend on the rate.
"""

from __future__ import annotations

import numpy as np

from ..core import fmath
from ..core.geometry import Pose2D
from ..core.messages import Odometry
from ..core.rng import stream
from .world import World

#: Updates' worth of noise drawn from the stream at once.
_NOISE_BLOCK = 256


class WheelOdometry:
    """The odom -> base_footprint estimate a base's wheel encoders give.

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
        self._noise_model = world.robot.drive.odometry_noise
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
        x, y, th = self._noise_model.step(self._pose, motion, self.alphas, self._next_noise())
        self._pose = (x, y, th)
        self._true = (tx, ty, yaw)
        self.last = Odometry(now, Pose2D(x, y, th), self.world.robot_twist)
        return self.last

    measure = update


def make_odometry(world: World, seed: int = 0) -> WheelOdometry:
    """The world's odometry as its file configures it, on the seed's `odometry` stream."""
    return WheelOdometry(world, rng=stream(seed, "odometry"))
