"""A zone that changes with the command (nav2_collision_monitor's VelocityPolygon): the
first sub-polygon whose velocity range holds the command is the shape for this cycle.

A sub-polygon holds a command when `theta_min <= angular_z <= theta_max` and, for a
non-holonomic robot, `linear_min <= linear_x <= linear_max`; for a `holonomic` one the
speed `hypot(x, y)` is in the linear range and its direction `atan2(y, x)` (0 at rest)
between `direction_start_angle` and `direction_end_angle` (wrapping through +-pi when
start > end). No sub-polygon holds it: the previous shape stays, as in Nav2.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from ..core import fmath
from ..core.messages import Twist
from ..params.collision_monitor import CollisionPolygon, VelocitySubPolygon
from .polygon import Polygon


class VelocityPolygon(Polygon):
    """A `velocity_polygon` zone; `sub_polygon` names the sub-polygon in use."""

    def __init__(
        self,
        name: str,
        params: CollisionPolygon,
        sources: list[str],
        footprint: Callable[[], NDArray[np.float64]] | None = None,
    ) -> None:
        super().__init__(name, params, sources, footprint=None)
        self.holonomic = params.holonomic
        self.sub_polygons: list[tuple[str, VelocitySubPolygon, NDArray[np.float64]]] = [
            (n, sub, np.asarray(sub.points, dtype=float)) for n, sub in params.sub_polygons.items()
        ]
        #: The sub-polygon chosen by the last command ("" before the first).
        self.sub_polygon = ""

    @property
    def follows_footprint(self) -> bool:
        return False

    def in_range(self, cmd: Twist, sub: VelocitySubPolygon) -> bool:
        """Whether `cmd` is in the sub-polygon's velocity (and, holonomic, direction) range."""
        if not sub.theta_min <= cmd.angular_z <= sub.theta_max:
            return False
        if not self.holonomic:
            return sub.linear_min <= cmd.linear_x <= sub.linear_max
        speed = float(fmath.hypot(cmd.linear_x, cmd.linear_y))
        if not sub.linear_min <= speed <= sub.linear_max:
            return False
        direction = float(fmath.arctan2(cmd.linear_y, cmd.linear_x)) if speed > 0.0 else 0.0
        start, end = sub.direction_start_angle, sub.direction_end_angle
        if start <= end:
            return start <= direction <= end
        return direction >= start or direction <= end

    def update_polygon(self, cmd: Twist) -> None:
        for name, sub, vertices in self.sub_polygons:
            if self.in_range(cmd, sub):
                self.vertices = vertices
                self.sub_polygon = name
                return
