"""The Ackermann drive: a car's bicycle kinematics, steered as a real base bridge steers it.

A car cannot turn in place: its yaw rate is its speed times the curvature its steering
angle gives, w = v * tan(steering) / wheelbase, about the rear axle (base_footprint).
cmd_vel's (v, w) becomes a steering angle as the usual cmd_vel-to-Ackermann bridge
computes it, steering = atan(wheelbase * w / v) (zero when v or w is zero); a curvature
tighter than `max_steering_angle` allows is clipped, and the wheels reach a new angle
at `max_steering_speed`, so the physics itself never turns tighter than the car's
minimum turning radius, wheelbase / tan(max_steering_angle). The speed follows the
command within `limits.v_max`, `v_min` (reversing) and `a_max`; `limits.w_max` does
not apply: the yaw rate follows from speed and steering.
"""

from __future__ import annotations

import pymunk
from pydantic import Field

from ..core import fmath
from ..core.messages import Twist
from ..plugins import register
from .drive import Drive, set_angular_velocity, set_velocity
from .world_spec import LimitsSpec, Real


@register("drive", "ackermann", aliases=("ackermann_steering",))
class AckermannDrive(Drive):
    """Front-wheel steering, rear axle at the robot's origin; reverses within `v_min`."""

    class Params(Drive.Params):
        wheelbase: Real = Field(0.325, gt=0.0, le=20.0, description="front to rear axle, m")
        max_steering_angle: Real = Field(
            0.34, gt=0.0, lt=1.5, description="the steering's stop either side, rad"
        )
        max_steering_speed: Real = Field(
            3.0, gt=0.0, le=100.0, description="how fast the steering turns, rad/s"
        )

    params: Params

    @property
    def min_turning_radius(self) -> float:
        """The tightest circle the rear axle can drive, m."""
        s, c = fmath.sincos(self.params.max_steering_angle)
        return float(self.params.wheelbase * c / s)

    def configure(self, limits: LimitsSpec) -> None:  # type: ignore[override]
        super().configure(limits)
        self._v = 0.0  # speed and steering the last control step set
        self.steering = 0.0
        self._w = 0.0
        self._goal = (0.0, 0.0)  # speed and steering angle the command asks for

    def command(self, vx: float, vy: float, w: float) -> None:
        p, lim = self.params, self.limits
        steering = 0.0
        if vx != 0.0 and w != 0.0:
            # atan(wheelbase * w / v): the ratio's angle, in (-pi/2, pi/2) when reversing too.
            steering = fmath.arctan2(p.wheelbase * w if vx > 0.0 else -p.wheelbase * w, abs(vx))
        limit = p.max_steering_angle
        self._goal = (min(max(vx, lim.v_low), lim.v_max), min(max(steering, -limit), limit))

    def control(self, body: pymunk.Body, dt: float, *, free: bool) -> None:
        p, lim = self.params, self.limits
        v_goal, steering_goal = self._goal
        s, c = fmath.sincos(body.angle)
        if free:
            v_cur = self._v
        else:
            vx, vy = body.velocity
            v_cur = c * vx + s * vy
        dv_max, ds_max = lim.a_max * dt, p.max_steering_speed * dt
        v = v_cur + min(max(v_goal - v_cur, -dv_max), dv_max)
        v = min(max(v, lim.v_low), lim.v_max)
        steering = self.steering + min(max(steering_goal - self.steering, -ds_max), ds_max)
        ss, cs = fmath.sincos(steering)
        w = v * ss / (cs * p.wheelbase)
        set_velocity(body, (v * c, v * s))
        set_angular_velocity(body, w)
        self._v, self.steering, self._w = v, steering, w

    @property
    def last_control(self) -> Twist:
        return Twist(self._v, 0.0, self._w)
