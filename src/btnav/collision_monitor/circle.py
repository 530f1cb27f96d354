"""A round zone centred on the robot (nav2_collision_monitor's Circle): strictly inside
when x^2 + y^2 < radius^2, drawn as a 16-gon; never the footprint."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from ..core.messages import Twist
from ..params.collision_monitor import CollisionPolygon
from .polygon import Polygon
from .shapes import circle_outline, points_in_circle


class Circle(Polygon):
    """A `circle` zone: `radius` from the params, or `set_radius` at run time."""

    def __init__(
        self,
        name: str,
        params: CollisionPolygon,
        sources: list[str],
        footprint: Callable[[], NDArray[np.float64]] | None = None,
    ) -> None:
        super().__init__(name, params, sources, footprint=None)  # Nav2: no footprint here
        self.radius: float | None = params.radius

    @property
    def follows_footprint(self) -> bool:
        return False

    def set_radius(self, radius: float) -> None:
        """A radius given at run time (Nav2's polygon_sub_topic Float32 message)."""
        self.radius = float(radius)

    def is_shape_set(self) -> bool:
        return self.radius is not None

    def update_polygon(self, cmd: Twist) -> None:
        return None

    def outline(self) -> NDArray[np.float64]:
        return np.zeros((0, 2)) if self.radius is None else circle_outline(self.radius)

    def reach(self) -> float:
        return 0.0 if self.radius is None else self.radius

    def inside(self, points: NDArray[np.float64]) -> NDArray[np.bool_]:
        if self.radius is None:
            return np.zeros(points.shape[:-1], dtype=bool)
        return points_in_circle(points, self.radius)
