"""dwb_plugins::KinematicParameters: the velocity and acceleration limits DWB samples within.

One immutable set of limits per control cycle, as Nav2's KinematicsHandler hands its
iterator a copy. Holonomic bases set `min_vel_y`/`max_vel_y` (with `acc_lim_y`,
`decel_lim_y`); `max_speed_xy` caps the combined speed hypot(vx, vy), so a diagonal
command is no faster than a straight one. A speed limit (from a speed filter) scales
max_speed_xy, max_vel_x, max_vel_y and max_vel_theta together, as Nav2's setSpeedLimit
does, so the trajectories keep their shapes at the lower speed.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

#: std::numeric_limits<float>::epsilon(): Nav2's tolerance on the squared speed checks.
FLT_EPSILON = float(np.finfo(np.float32).eps)

_FIELDS = (
    "min_vel_x",
    "min_vel_y",
    "max_vel_x",
    "max_vel_y",
    "max_vel_theta",
    "min_speed_xy",
    "max_speed_xy",
    "min_speed_theta",
    "acc_lim_x",
    "acc_lim_y",
    "acc_lim_theta",
    "decel_lim_x",
    "decel_lim_y",
    "decel_lim_theta",
)


@dataclass(frozen=True)
class KinematicParameters:
    """The limits of one cycle; decelerations are negative in Nav2's files (the sign is
    not relied on: btnav uses their magnitude)."""

    min_vel_x: float = 0.0
    min_vel_y: float = 0.0
    max_vel_x: float = 0.0
    max_vel_y: float = 0.0
    max_vel_theta: float = 0.0
    min_speed_xy: float = 0.0
    max_speed_xy: float = 0.0
    min_speed_theta: float = 0.0
    acc_lim_x: float = 0.0
    acc_lim_y: float = 0.0
    acc_lim_theta: float = 0.0
    decel_lim_x: float = 0.0
    decel_lim_y: float = 0.0
    decel_lim_theta: float = 0.0

    @classmethod
    def from_params(cls, params: Any) -> KinematicParameters:
        """The kinematic keys of a DWB section (DWBParams or anything with those names)."""
        return cls(**{name: float(getattr(params, name)) for name in _FIELDS})

    def axes(self) -> tuple[tuple[float, float, float, float], ...]:
        """(min, max, acc, decel magnitude) for x, y and theta (theta's range is symmetric)."""
        return (
            (self.min_vel_x, self.max_vel_x, abs(self.acc_lim_x), abs(self.decel_lim_x)),
            (self.min_vel_y, self.max_vel_y, abs(self.acc_lim_y), abs(self.decel_lim_y)),
            (
                -self.max_vel_theta,
                self.max_vel_theta,
                abs(self.acc_lim_theta),
                abs(self.decel_lim_theta),
            ),
        )

    def with_speed_limit(self, speed_limit: float, percentage: bool) -> KinematicParameters:
        """These (base) limits under a speed limit; 0 (Nav2's NO_SPEED_LIMIT) keeps them.

        A percentage scales all four maxima; an absolute limit below max_speed_xy becomes
        max_speed_xy and scales the other three by the same ratio; one above it changes
        nothing.
        """
        if speed_limit <= 0.0:
            return self
        if percentage:
            ratio = speed_limit / 100.0
            speed_xy = self.max_speed_xy * ratio
        elif speed_limit < self.max_speed_xy:
            ratio = speed_limit / self.max_speed_xy
            speed_xy = speed_limit
        else:
            return self
        return replace(
            self,
            max_speed_xy=speed_xy,
            max_vel_x=self.max_vel_x * ratio,
            max_vel_y=self.max_vel_y * ratio,
            max_vel_theta=self.max_vel_theta * ratio,
        )

    def valid_speeds(self, v: NDArray[np.float64]) -> NDArray[np.bool_]:
        """Nav2's isValidSpeed for each (vx, vy, wz) row of `v` (S, 3).

        Invalid: faster than max_speed_xy (unless negative); slower than min_speed_xy
        while also turning slower than min_speed_theta (either check off when negative);
        and the zero twist, which is no trajectory at all.
        """
        sq = v[:, 0] * v[:, 0] + v[:, 1] * v[:, 1]
        turn = np.abs(v[:, 2])
        ok = np.ones(len(v), dtype=bool)
        if self.max_speed_xy >= 0.0:
            ok &= sq <= self.max_speed_xy * self.max_speed_xy + FLT_EPSILON
        if self.min_speed_xy >= 0.0 and self.min_speed_theta >= 0.0:
            slow = sq + FLT_EPSILON < self.min_speed_xy * self.min_speed_xy
            ok &= ~(slow & (turn + FLT_EPSILON < self.min_speed_theta))
        ok &= ~((sq == 0.0) & (v[:, 2] == 0.0))
        return ok


__all__ = ["FLT_EPSILON", "KinematicParameters"]
