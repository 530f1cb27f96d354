"""The robot: a pymunk body with the world's footprint, moved by its drive plugin.

Each physics step the drive turns the last command into the body's velocity within
the robot's limits (`drive.py`); the solver then resolves contacts, so walls stop the
robot physically and a moving obstacle can push it.
"""

from __future__ import annotations

import math

import numpy as np
import pymunk

from ..core import fmath
from ..core.geometry import Pose2D
from ..core.messages import Twist
from .drive import Drive
from .scene import convex_parts
from .world_spec import RobotSpec, signed_area

#: pymunk collision type of every robot shape (the world counts contacts against it).
ROBOT_COLLISION_TYPE = 1
#: An arbitrary mass: the base is velocity-controlled, so mass only matters when a
#: kinematic obstacle pushes it (kinematic bodies win regardless).
ROBOT_MASS = 25.0


class Robot:
    """A base with a circular or polygonal footprint, driven by a `drive` plugin."""

    def __init__(self, spec: RobotSpec, drive: Drive) -> None:
        self.spec = spec
        self.limits = spec.limits
        self.drive = drive
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
            total = math.fsum(areas)  # fsum: the same bits on every CPython (decision 0092)
            moment = math.fsum(
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

    # -- commands -----------------------------------------------------------------------

    def set_cmd_vel(self, cmd: Twist) -> None:
        """Take a new velocity command (held until the next one), as a base takes cmd_vel."""
        self.drive.set_cmd_vel(cmd)

    @property
    def cmd_vel(self) -> Twist:
        return self.drive.cmd_vel

    def control(self, dt: float, *, free: bool = False) -> None:
        """Before a physics step: the drive sets the body's velocity from the command.

        `free` says nothing touched the robot in the last step, so its velocity is the
        one set then (no gravity, no damping): reading it back from pymunk is skipped.
        """
        self.drive.control(self.body, dt, free=free)

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
        return self.drive.last_control

    @property
    def twist(self) -> Twist:
        v, lateral, w = self._velocity()
        return Twist(v, lateral, w)
