"""The drive plugin base: how a base turns cmd_vel into motion, and how its odometry drifts.

A drive is what sits under a robot's `cmd_vel` in Gazebo (the diff_drive,
AckermannSteering or planar-move plugin): it owns the command interface (which parts
of a Twist it can honour and how it clips the rest), the physics of following a
command within the base's limits, and the noise of the odometry its wheels give.
World files name one under `robot.drive` (`diff_drive`, `ackermann`, `omni`, or a
user's plugin); the robot's body and footprint are the world's, the motion is the drive's.
"""

from __future__ import annotations

import math
from typing import Any, ClassVar

import pymunk

from ..core.errors import BtnavError, WorldError
from ..core.messages import Twist
from ..core.validation import StrictModel, validate
from ..core.yaml_io import YamlMap
from ..plugins import Plugin, lookup
from .odometry_noise import DiffDriveNoise, OdometryNoise
from .world_spec import LimitsSpec, WorldSpec

#: pymunk's property setters, called directly: `body.velocity = v` goes through a
#: Python-level `__setattr__` hook first, which costs more than the setting itself.
set_velocity = pymunk.Body.velocity.fset
set_angular_velocity = pymunk.Body.angular_velocity.fset


class Drive(Plugin):
    """Base of every `drive` plugin (`@register("drive", name)`).

    Built from its name and validated `Params`, then `configure(limits)` hands it the
    robot's speed and acceleration limits. Each physics sub-step the world calls
    `control(body, dt, free)` to set the body's velocity; pymunk then resolves contacts.
    """

    class Params(StrictModel):
        pass

    #: How the odometry this base's wheels give drifts (AMCL's model for the drive).
    odometry_noise: ClassVar[OdometryNoise] = DiffDriveNoise()

    limits: LimitsSpec

    def __init__(self, name: str, params: Any = None) -> None:
        super().__init__(name, params)
        self._cmd = Twist(0.0, 0.0, 0.0)

    def configure(self, limits: LimitsSpec) -> None:  # type: ignore[override]
        """The robot's limits, the same for every drive (speeds and accelerations)."""
        self.limits = limits

    def set_cmd_vel(self, cmd: Twist) -> None:
        """Take a new velocity command (held until the next one), as a base takes cmd_vel."""
        parts = (float(cmd.linear_x), float(cmd.linear_y), float(cmd.angular_z))
        if not all(math.isfinite(p) for p in parts):
            raise ValueError(
                f"cmd_vel must be finite, got vx={parts[0]}, vy={parts[1]}, w={parts[2]}"
            )
        self._cmd = Twist(*parts)
        self.command(*parts)

    @property
    def cmd_vel(self) -> Twist:
        """The last command as it was given (before any clipping)."""
        return self._cmd

    def command(self, vx: float, vy: float, w: float) -> None:
        """Turn a finite command into the drive's goal (clipped to what it can follow)."""
        raise NotImplementedError

    def control(self, body: pymunk.Body, dt: float, *, free: bool) -> None:
        """Before a physics step of `dt`: set `body`'s velocity toward the goal.

        `free` says nothing touched the robot in the last step, so its velocity is the
        one set then (no gravity, no damping): a drive may skip reading it back.
        """
        raise NotImplementedError

    @property
    def last_control(self) -> Twist:
        """The robot-frame velocity the last control step gave the body."""
        raise NotImplementedError


def make_drive(spec: WorldSpec, file: str | None = None) -> Drive:
    """The world's `robot.drive`, built and configured; an unknown name or a bad
    parameter is a `WorldError` at its line in the world file."""
    robot = spec.robot
    name = robot.drive_name
    key: list[str | int] = (
        ["robot", "drive"] if isinstance(robot.drive, str) else ["robot", "drive", name]
    )
    line = spec.line_of(*key)
    try:
        cls = lookup("drive", name)
    except BtnavError as exc:
        raise exc.located(file=file, line=line, key=key) from None
    doc = robot.drive_params if robot.drive_params is not None else YamlMap(file=file, line=line)
    params = validate(cls.Params, doc, file=file, key_prefix=key, error_cls=WorldError)
    drive: Drive = cls(name, params)
    drive.configure(robot.limits)
    return drive
