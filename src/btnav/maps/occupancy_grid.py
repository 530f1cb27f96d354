"""The occupancy grid, as nav_msgs/OccupancyGrid holds it.

`data[row, col]` is int8: -1 unknown, 0 free .. 100 occupied. Row 0 is the row at
the map origin (the bottom of the picture, as in ROS), so cell (row, col) covers
world x in [ox + col*res, ox + (col+1)*res) when the origin yaw is 0.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..core.geometry import Pose2D

UNKNOWN = -1
FREE = 0
OCCUPIED = 100


@dataclass
class OccupancyGrid:
    data: NDArray[np.int8]
    resolution: float
    origin: Pose2D = field(default_factory=Pose2D)
    frame_id: str = "map"

    def __post_init__(self) -> None:
        self.data = np.asarray(self.data, dtype=np.int8)
        if self.data.ndim != 2:
            raise ValueError("an occupancy grid is a 2D array")
        if not (self.resolution > 0 and math.isfinite(self.resolution)):
            raise ValueError(f"resolution must be a positive number, got {self.resolution}")

    @property
    def height(self) -> int:
        return int(self.data.shape[0])

    @property
    def width(self) -> int:
        return int(self.data.shape[1])

    @property
    def size_m(self) -> tuple[float, float]:
        return self.width * self.resolution, self.height * self.resolution

    def world_to_cell(self, points: ArrayLike) -> NDArray[np.int64]:
        """(N, 2) world points -> (N, 2) integer (row, col) indices; may fall outside the grid."""
        local = self.origin.inverse_transform_points(np.asarray(points, dtype=float))
        cols = np.floor(local[..., 0] / self.resolution).astype(np.int64)
        rows = np.floor(local[..., 1] / self.resolution).astype(np.int64)
        return np.stack([rows, cols], axis=-1)

    def cell_to_world(self, cells: ArrayLike) -> NDArray[np.float64]:
        """(N, 2) (row, col) indices -> (N, 2) world coordinates of the cell centres."""
        rc = np.asarray(cells, dtype=float)
        local = np.stack(
            [(rc[..., 1] + 0.5) * self.resolution, (rc[..., 0] + 0.5) * self.resolution], -1
        )
        return self.origin.transform_points(local)

    def in_bounds(self, cells: ArrayLike) -> NDArray[np.bool_]:
        rc = np.asarray(cells)
        return (
            (rc[..., 0] >= 0)
            & (rc[..., 0] < self.height)
            & (rc[..., 1] >= 0)
            & (rc[..., 1] < self.width)
        )

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, OccupancyGrid):
            return NotImplemented
        return (
            self.resolution == other.resolution
            and self.origin == other.origin
            and self.frame_id == other.frame_id
            and np.array_equal(self.data, other.data)
        )
