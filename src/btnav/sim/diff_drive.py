"""The differential drive: forward speed and yaw rate, as Gazebo's diff_drive plugin takes them.

Each physics step the command is moved toward from the robot's *current* velocity by
at most a_max*dt (alpha_max*dt) and set as the body's velocity along its heading. The
solver then resolves contacts, so walls stop the robot physically and a moving
obstacle can push it; the velocity the next step starts from is what the physics
left, as with a real base. A lateral command is ignored, as the wheels cannot slide.
"""

from __future__ import annotations

import pymunk

from ..core import fmath
from ..core.messages import Twist
from ..plugins import register
from .drive import Drive, set_angular_velocity, set_velocity
from .world_spec import LimitsSpec


@register("drive", "diff_drive", aliases=("differential",))
class DiffDrive(Drive):
    """Two driven wheels on one axle: (v, w) within the limits, no sideways motion."""

    def configure(self, limits: LimitsSpec) -> None:  # type: ignore[override]
        super().configure(limits)
        self._limits = (limits.v_low, limits.v_max, limits.w_max, limits.a_max, limits.alpha_max)
        self._v = 0.0  # the velocity set in the last control step (robot frame)
        self._w = 0.0
        self._goal = (0.0, 0.0)  # the command within the speed limits

    def command(self, vx: float, vy: float, w: float) -> None:
        v_low, v_max, w_max = self._limits[:3]
        self._goal = (min(max(vx, v_low), v_max), min(max(w, -w_max), w_max))

    def control(self, body: pymunk.Body, dt: float, *, free: bool) -> None:
        v_goal, w_goal = self._goal
        if free and self._v == v_goal and self._w == w_goal:
            if w_goal == 0.0:
                return  # cruising straight: the body keeps the velocity it has
            v = v_goal  # cruising on an arc: turn the velocity with the body
            s, c = fmath.sincos(body.angle)
            set_velocity(body, (v * c, v * s))
            return
        v_low, v_max, w_max, a_max, alpha_max = self._limits
        s, c = fmath.sincos(body.angle)
        if free:
            v_cur, w_cur = self._v, self._w
        else:
            vx, vy = body.velocity
            v_cur, w_cur = c * vx + s * vy, body.angular_velocity
        dv_max, dw_max = a_max * dt, alpha_max * dt
        v = v_cur + min(max(v_goal - v_cur, -dv_max), dv_max)
        w = w_cur + min(max(w_goal - w_cur, -dw_max), dw_max)
        # Never exceed the limits, even if a push left the body faster than allowed.
        v = min(max(v, v_low), v_max)
        w = min(max(w, -w_max), w_max)
        set_velocity(body, (v * c, v * s))
        if w != w_cur or not free:
            set_angular_velocity(body, w)
        self._v, self._w = v, w

    @property
    def last_control(self) -> Twist:
        return Twist(self._v, 0.0, self._w)
