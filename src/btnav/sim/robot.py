"""The diff-drive robot: a pymunk body that follows cmd_vel within its drive limits.

Each physics step the last command is clipped to the speed limits, then moved
toward from the robot's *current* velocity by at most a_max*dt (alpha_max*dt), and
set as the body's velocity along its heading. The solver then resolves contacts, so
walls stop the robot physically and a moving obstacle can push it; the velocity
the next step starts from is what the physics left, as with a real base.
"""

from __future__ import annotations

import math

import numpy as np
import pymunk

from ..core import fmath
from ..core.geometry import Pose2D
from ..core.messages import Twist
from .scene import convex_parts
from .world_spec import RobotSpec, signed_area

#: pymunk's property setters, called directly: `body.velocity = v` goes through a
#: Python-level `__setattr__` hook first, which costs more than the setting itself.
set_velocity = pymunk.Body.velocity.fset
set_angular_velocity = pymunk.Body.angular_velocity.fset

#: pymunk collision type of every robot shape (the world counts contacts against it).
ROBOT_COLLISION_TYPE = 1
#: An arbitrary mass: the base is velocity-controlled, so mass only matters when a
#: kinematic obstacle pushes it (kinematic bodies win regardless).
ROBOT_MASS = 25.0


class DiffDriveRobot:
    """A differential-drive base with a circular or polygonal footprint."""

    def __init__(self, spec: RobotSpec) -> None:
        self.spec = spec
        self.limits = spec.limits
        lim = spec.limits
        self._limits = (lim.v_low, lim.v_max, lim.w_max, lim.a_max, lim.alpha_max)
        fp = spec.footprint
        self.radius: float | None = fp.radius
        self.polygon: np.ndarray | None = None
        if fp.radius is not None:
            body = pymunk.Body(ROBOT_MASS, pymunk.moment_for_circle(ROBOT_MASS, 0.0, fp.radius))
            shapes: list[pymunk.Shape] = [pymunk.Circle(body, fp.radius)]
        else:
            assert fp.polygon is not None
            self.polygon = np.asarray(fp.polygon, dtype=float)
            parts = convex_parts(self.polygon)
            areas = [abs(signed_area(p)) for p in parts]
            total = sum(areas)
            moment = sum(
                pymunk.moment_for_poly(ROBOT_MASS * a / total, [tuple(v) for v in p])
                for p, a in zip(parts, areas, strict=True)
            )
            body = pymunk.Body(ROBOT_MASS, max(moment, 1e-9))
            shapes = [pymunk.Poly(body, [tuple(v) for v in p]) for p in parts]
        x, y, yaw = spec.pose
        body.position = (x, y)
        body.angle = yaw
        for s in shapes:
            s.collision_type = ROBOT_COLLISION_TYPE
            s.friction = 0.0
            s.elasticity = 0.0
        self.body = body
        self.shapes = shapes
        self._cmd_v = 0.0
        self._cmd_w = 0.0
        self._v = 0.0  # the velocity set in the last control step (robot frame)
        self._w = 0.0
        self._goal = (0.0, 0.0)  # the command within the speed limits

    # -- commands -----------------------------------------------------------------------

    def set_cmd_vel(self, cmd: Twist) -> None:
        """Take a new velocity command (held until the next one), as a base takes cmd_vel."""
        v, w = float(cmd.linear_x), float(cmd.angular_z)
        if not (math.isfinite(v) and math.isfinite(w)):
            raise ValueError(f"cmd_vel must be finite, got v={v}, w={w}")
        self._cmd_v, self._cmd_w = v, w
        v_low, v_max, w_max = self._limits[:3]
        self._goal = (min(max(v, v_low), v_max), min(max(w, -w_max), w_max))

    @property
    def cmd_vel(self) -> Twist:
        return Twist(self._cmd_v, 0.0, self._cmd_w)

    def control(self, dt: float, *, free: bool = False) -> None:
        """Before a physics step: set the body's velocity from the command, within the limits.

        `free` says nothing touched the robot in the last step, so its velocity is the
        one set then (no gravity, no damping): reading it back from pymunk is skipped.
        """
        v_goal, w_goal = self._goal
        if free and self._v == v_goal and self._w == w_goal:
            if w_goal == 0.0:
                return  # cruising straight: the body keeps the velocity it has
            v, w = v_goal, w_goal  # cruising on an arc: turn the velocity with the body
            a = self.body.angle
            s, c = fmath.sincos(a)
            set_velocity(self.body, (v * c, v * s))
            return
        v_low, v_max, w_max, a_max, alpha_max = self._limits
        body = self.body
        a = body.angle
        s, c = fmath.sincos(a)
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

    # -- state --------------------------------------------------------------------------

    def _velocity(self) -> tuple[float, float, float]:
        """Forward, lateral and angular velocity in the robot frame."""
        vx, vy = self.body.velocity
        a = self.body.angle
        s, c = fmath.sincos(a)
        return c * vx + s * vy, -s * vx + c * vy, float(self.body.angular_velocity)

    @property
    def pose(self) -> Pose2D:
        x, y = self.body.position
        return Pose2D(x, y, self.body.angle)

    @property
    def yaw_unwrapped(self) -> float:
        """The heading without wrapping to (-pi, pi] (odometry integrates its differences)."""
        return float(self.body.angle)

    @property
    def last_control(self) -> Twist:
        """The velocity the last control step gave the body (its true velocity when free)."""
        return Twist(self._v, 0.0, self._w)

    @property
    def twist(self) -> Twist:
        v, lateral, w = self._velocity()
        return Twist(v, lateral, w)
