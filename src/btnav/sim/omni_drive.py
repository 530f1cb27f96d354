"""The omnidirectional drive: vx, vy and w all honoured, as Gazebo's planar move plugin does.

Mecanum or omni wheels let the base strafe. Each axis moves toward its command within
its own limit and acceleration (forward: `limits.v_max`/`v_min`, sideways: `vy_max`,
both at `limits.a_max`; yaw: `limits.w_max` at `alpha_max`). Its odometry drifts as
nav2_amcl's OmniMotionModel assumes (alpha5: strafe noise per metre).
"""

from __future__ import annotations

from typing import ClassVar

import pymunk
from pydantic import Field

from ..core import fmath
from ..core.messages import Twist
from ..plugins import register
from .drive import Drive, set_angular_velocity, set_velocity
from .odometry_noise import OdometryNoise, OmniNoise
from .world_spec import LimitsSpec, Real


def _toward(current: float, goal: float, step: float) -> float:
    return current + min(max(goal - current, -step), step)


@register("drive", "omni", aliases=("omnidirectional", "holonomic"))
class OmniDrive(Drive):
    """A holonomic base: forward, sideways and yaw velocities at once."""

    class Params(Drive.Params):
        vy_max: Real = Field(0.5, gt=0.0, le=100.0, description="fastest strafe either way, m/s")

    params: Params
    odometry_noise: ClassVar[OdometryNoise] = OmniNoise()

    def configure(self, limits: LimitsSpec) -> None:  # type: ignore[override]
        super().configure(limits)
        self._velocity = (0.0, 0.0, 0.0)  # robot-frame vx, vy, w the last step set
        self._goal = (0.0, 0.0, 0.0)

    def command(self, vx: float, vy: float, w: float) -> None:
        lim, vy_max = self.limits, self.params.vy_max
        self._goal = (
            min(max(vx, lim.v_low), lim.v_max),
            min(max(vy, -vy_max), vy_max),
            min(max(w, -lim.w_max), lim.w_max),
        )

    def control(self, body: pymunk.Body, dt: float, *, free: bool) -> None:
        lim = self.limits
        s, c = fmath.sincos(body.angle)
        if free:
            vx, vy, w = self._velocity
        else:
            wx, wy = body.velocity
            vx, vy, w = c * wx + s * wy, -s * wx + c * wy, body.angular_velocity
        gx, gy, gw = self._goal
        dv, dw = lim.a_max * dt, lim.alpha_max * dt
        vx = min(max(_toward(vx, gx, dv), lim.v_low), lim.v_max)
        vy = min(max(_toward(vy, gy, dv), -self.params.vy_max), self.params.vy_max)
        w = min(max(_toward(w, gw, dw), -lim.w_max), lim.w_max)
        set_velocity(body, (c * vx - s * vy, s * vx + c * vy))
        set_angular_velocity(body, w)
        self._velocity = (vx, vy, w)

    @property
    def last_control(self) -> Twist:
        return Twist(*self._velocity)
