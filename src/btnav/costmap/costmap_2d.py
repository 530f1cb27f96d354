"""Costmap2D: a grid of uint8 costs in Nav2's cost values, axis-aligned in its frame.

`costs[my, mx]` as Nav2 indexes (mx along x, my along y); row 0 is at `origin_y`
(the bottom, as in an OccupancyGrid). Cell (mx, my) covers x in
[origin_x + mx*res, origin_x + (mx+1)*res).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..core.geometry import Pose2D
from .cost_values import NO_INFORMATION


@dataclass
class Costmap2D:
    costs: NDArray[np.uint8]
    resolution: float
    origin_x: float = 0.0
    origin_y: float = 0.0
    frame_id: str = "map"
    default_value: int = 0

    def __post_init__(self) -> None:
        self.costs = np.asarray(self.costs, dtype=np.uint8)
        if self.costs.ndim != 2:
            raise ValueError("a costmap is a 2D array")
        if not self.resolution > 0:
            raise ValueError(f"resolution must be positive, got {self.resolution}")

    @classmethod
    def empty(
        cls,
        size_x: int,
        size_y: int,
        resolution: float,
        origin_x: float = 0.0,
        origin_y: float = 0.0,
        frame_id: str = "map",
        default_value: int = 0,
    ) -> Costmap2D:
        costs = np.full((size_y, size_x), default_value, dtype=np.uint8)
        return cls(costs, resolution, origin_x, origin_y, frame_id, default_value)

    @property
    def size_x(self) -> int:
        """Cells along x (Nav2's getSizeInCellsX)."""
        return int(self.costs.shape[1])

    @property
    def size_y(self) -> int:
        return int(self.costs.shape[0])

    @property
    def size_in_meters(self) -> tuple[float, float]:
        return self.size_x * self.resolution, self.size_y * self.resolution

    @property
    def origin(self) -> Pose2D:
        return Pose2D(self.origin_x, self.origin_y, 0.0)

    def world_to_map(self, xy: ArrayLike) -> tuple[NDArray[np.int64], NDArray[np.bool_]]:
        """(..., 2) world points -> (..., 2) integer (mx, my) and whether each is on the map."""
        p = np.asarray(xy, dtype=float)
        m = np.floor((p - (self.origin_x, self.origin_y)) / self.resolution).astype(np.int64)
        inside = (
            (m[..., 0] >= 0)
            & (m[..., 0] < self.size_x)
            & (m[..., 1] >= 0)
            & (m[..., 1] < self.size_y)
        )
        return m, inside

    def map_to_world(self, mxy: ArrayLike) -> NDArray[np.float64]:
        """(..., 2) cell indices (mx, my) -> world coordinates of the cell centres."""
        m = np.asarray(mxy, dtype=float)
        return (m + 0.5) * self.resolution + (self.origin_x, self.origin_y)

    def cost_at(self, xy: ArrayLike) -> NDArray[np.uint8]:
        """Costs at world points; NO_INFORMATION off the map."""
        m, inside = self.world_to_map(xy)
        out = np.full(inside.shape, NO_INFORMATION, dtype=np.uint8)
        out[inside] = self.costs[m[..., 1][inside], m[..., 0][inside]]
        return out

    def copy(self) -> Costmap2D:
        return Costmap2D(
            self.costs.copy(),
            self.resolution,
            self.origin_x,
            self.origin_y,
            self.frame_id,
            self.default_value,
        )
