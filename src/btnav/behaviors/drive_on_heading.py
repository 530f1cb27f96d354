"""DriveOnHeading: drive straight by a distance at a speed (nav2_behaviors::DriveOnHeading).

The command speeds up and slows down within `acceleration_limit` and
`deceleration_limit` (per cycle at `cycle_frequency`), brakes so as to stop at the
target distance (v <= sqrt(-2 * deceleration_limit * remaining)), and never goes
below `minimum_speed` until the distance is covered. Each cycle the rest of the
straight line within `simulate_ahead_time` is simulated on the local costmap with
the footprint; a lethal cell under it stops the robot with COLLISION_AHEAD.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from pydantic import Field

from ..core import fmath
from ..core.geometry import Pose2D
from ..core.nav2_msgs import DriveOnHeadingFeedback
from ..plugins import register
from .behavior import Behavior, BehaviorOutcome


def _point(value: Any) -> tuple[float, float, float]:
    """A target as geometry_msgs/Point (x, y, z); a bare number is x."""
    if isinstance(value, int | float):
        return (float(value), 0.0, 0.0)
    v = tuple(float(c) for c in value)
    return (*v, 0.0, 0.0, 0.0)[:3]  # type: ignore[return-value]


@register("behavior", "nav2_behaviors::DriveOnHeading", aliases=["btnav/DriveOnHeading"])
class DriveOnHeading(Behavior):
    """Drive straight `target.x` metres at `speed`, within acceleration limits."""

    action = "DriveOnHeading"

    class Params(Behavior.Params):
        acceleration_limit: float = Field(2.5, gt=0.0, description="m/s^2 when speeding up")
        deceleration_limit: float = Field(
            -2.5, lt=0.0, description="m/s^2 when slowing down (negative, as Nav2 writes it)"
        )
        minimum_speed: float = Field(0.10, ge=0.0, description="m/s the command never goes below")

    def _command(self, goal: Any) -> tuple[float, float] | BehaviorOutcome:
        """(signed distance, signed speed), or INVALID_INPUT."""
        x, y, z = _point(goal.target)
        if y != 0.0 or z != 0.0:
            return self.fail(
                "INVALID_INPUT", f"{self.action} drives along x only; target y, z must be 0"
            )
        if not (math.isfinite(x) and math.isfinite(goal.speed)):
            return self.fail("INVALID_INPUT", "target and speed must be finite")
        if goal.speed == 0.0 or (x > 0.0) != (goal.speed > 0.0):
            return self.fail(
                "INVALID_INPUT",
                f"speed ({goal.speed}) must be non-zero and have the sign of the distance ({x})",
            )
        return x, float(goal.speed)

    def on_run(self, goal: Any, now: float) -> BehaviorOutcome | None:
        command = self._command(goal)
        if isinstance(command, BehaviorOutcome):
            return command
        self.command_x, self.command_speed = command
        self.check_collisions = not goal.disable_collision_checks
        self.set_time_allowance(goal.time_allowance, now)
        self.initial_pose: Pose2D = self.robot_pose()
        self.last_vel = 0.0
        return None

    def on_action_completion(self) -> None:
        self.last_vel = 0.0

    def _speed(self, remaining: float) -> float:
        """This cycle's speed: accelerate/decelerate within limits, brake into the target."""
        p = self.params
        dt = 1.0 / self.cycle_frequency
        forward = self.command_speed > 0.0
        v = self.last_vel
        if forward:
            lo, hi = v + p.deceleration_limit * dt, v + p.acceleration_limit * dt
        else:
            lo, hi = v - p.acceleration_limit * dt, v - p.deceleration_limit * dt
        cmd = min(max(self.command_speed, lo), hi)
        stop = math.sqrt(max(0.0, -2.0 * p.deceleration_limit * remaining))
        if abs(cmd) > stop:
            cmd = math.copysign(stop, self.command_speed)
        if abs(cmd) < p.minimum_speed:
            cmd = math.copysign(p.minimum_speed, self.command_speed)
        return cmd

    def on_cycle_update(self, now: float) -> BehaviorOutcome | None:
        if self.timed_out(now):
            return self.fail(
                "TIMEOUT",
                f"{self.name}: time_allowance of {self.time_allowance:g} s ran out",
            )
        pose = self.robot_pose()
        distance = self.initial_pose.distance_to(pose)
        self.publish_feedback(DriveOnHeadingFeedback(distance))
        remaining = abs(self.command_x) - distance
        if remaining <= 0.0:
            return self.succeed()

        v = self._speed(remaining)
        if self.check_collisions and self.collision_checker is not None:
            k = np.arange(max(1, int(self.cycle_frequency * self.server.simulate_ahead_time)))
            d = v * k / self.cycle_frequency
            d = d[np.abs(d) < remaining]  # only the part of the line still to drive
            s, c = fmath.sincos(pose.yaw)
            poses = np.stack(
                [
                    pose.x + d * c,
                    pose.y + d * s,
                    np.full(d.shape, pose.yaw),
                ],
                axis=1,
            )
            hit = self.collision_checker.first_collision(poses)
            if hit is not None:
                return self.fail(
                    "COLLISION_AHEAD",
                    f"{self.name}: the footprint would hit an obstacle "
                    f"{abs(d[hit]):.2f} m further on; stopped after {distance:.2f} m",
                )
        self.publish_cmd(linear_x=v)
        self.last_vel = v
        return None
