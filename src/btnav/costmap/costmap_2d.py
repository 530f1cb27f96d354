"""Costmap2D: a grid of uint8 costs in Nav2's cost values, axis-aligned in its frame.

`costs[my, mx]` as Nav2 indexes (mx along x, my along y); row 0 is at `origin_y`
(the bottom, as in an OccupancyGrid). Cell (mx, my) covers x in
[origin_x + mx*res, origin_x + (mx+1)*res).
"""

from __future__ import annotations

import math
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
        ny, nx = self.costs.shape
        # 0 <= m < size as one unsigned test (a negative index wraps to a huge one)
        inside = m[..., 0].view(np.uint64) < nx
        inside &= m[..., 1].view(np.uint64) < ny
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

    def cost_at_point(self, x: float, y: float) -> int:
        """`cost_at` for one world point, without arrays (the same cell arithmetic)."""
        mx = math.floor((x - self.origin_x) / self.resolution)
        my = math.floor((y - self.origin_y) / self.resolution)
        ny, nx = self.costs.shape
        if 0 <= mx < nx and 0 <= my < ny:
            return int(self.costs[my, mx])
        return NO_INFORMATION

    def copy(self) -> Costmap2D:
        return Costmap2D(
            self.costs.copy(),
            self.resolution,
            self.origin_x,
            self.origin_y,
            self.frame_id,
            self.default_value,
        )

    # -- Nav2 Costmap2D helpers ------------------------------------------------------

    def world_to_map_enforce_bounds(self, x: float, y: float) -> tuple[int, int]:
        """The cell of a world point, clamped onto the map (Nav2's worldToMapEnforceBounds)."""
        mx = math.floor((x - self.origin_x) / self.resolution)
        my = math.floor((y - self.origin_y) / self.resolution)
        return min(max(mx, 0), self.size_x - 1), min(max(my, 0), self.size_y - 1)

    def cell_distance(self, world_dist: float) -> int:
        """A distance in cells, rounded up (Nav2's cellDistance)."""
        return max(0, math.ceil(world_dist / self.resolution))

    def reset_map(
        self, x0: int = 0, y0: int = 0, xn: int | None = None, yn: int | None = None
    ) -> None:
        """Cells [x0, xn) x [y0, yn) back to `default_value` (Nav2's resetMap); all by default."""
        xn = self.size_x if xn is None else xn
        yn = self.size_y if yn is None else yn
        self.costs[max(y0, 0) : max(yn, 0), max(x0, 0) : max(xn, 0)] = self.default_value

    def resize_map(
        self, size_x: int, size_y: int, resolution: float, origin_x: float, origin_y: float
    ) -> None:
        """A new geometry, every cell at `default_value` (Nav2's resizeMap)."""
        if not resolution > 0:
            raise ValueError(f"resolution must be positive, got {resolution}")
        self.costs = np.full((max(size_y, 1), max(size_x, 1)), self.default_value, np.uint8)
        self.resolution = float(resolution)
        self.origin_x = float(origin_x)
        self.origin_y = float(origin_y)

    def update_origin(self, new_origin_x: float, new_origin_y: float) -> None:
        """Move the map to a new origin, keeping the cells that stay on it (rolling windows).

        As Nav2's updateOrigin: the move is a whole number of cells (truncated), so
        kept cells keep their exact world position; new cells get `default_value`.
        """
        cell_ox = int((new_origin_x - self.origin_x) / self.resolution)
        cell_oy = int((new_origin_y - self.origin_y) / self.resolution)
        if cell_ox == 0 and cell_oy == 0:
            return
        sx, sy = self.size_x, self.size_y
        out = np.full_like(self.costs, self.default_value)
        # Overlap in old-map cells: [lx, ux) x [ly, uy).
        lx, ly = max(cell_ox, 0), max(cell_oy, 0)
        ux, uy = min(cell_ox + sx, sx), min(cell_oy + sy, sy)
        if lx < ux and ly < uy:
            out[ly - cell_oy : uy - cell_oy, lx - cell_ox : ux - cell_ox] = self.costs[ly:uy, lx:ux]
        self.costs = out
        self.origin_x += cell_ox * self.resolution
        self.origin_y += cell_oy * self.resolution

    def grown_to_include(self, points: ArrayLike, margin: float) -> Costmap2D:
        """This map, or a larger copy whose new cells are NO_INFORMATION, that holds every
        world point with `margin` metres round it; the old cells keep their world places
        (the growth is whole cells), so a plan on the copy is a plan on this map."""
        xy = np.asarray(points, dtype=np.float64).reshape(-1, 2)
        r = self.resolution
        lo = np.floor((xy.min(axis=0) - margin - (self.origin_x, self.origin_y)) / r)
        hi = np.ceil((xy.max(axis=0) + margin - (self.origin_x, self.origin_y)) / r)
        grow_lo = np.maximum(-lo, 0).astype(int)  # cells added left / below
        grow_hi = np.maximum(hi - (self.size_x, self.size_y), 0).astype(int)
        if not (grow_lo.any() or grow_hi.any()):
            return self
        costs = np.pad(
            self.costs,
            ((grow_lo[1], grow_hi[1]), (grow_lo[0], grow_hi[0])),
            constant_values=NO_INFORMATION,
        )
        return Costmap2D(
            costs,
            r,
            self.origin_x - grow_lo[0] * r,
            self.origin_y - grow_lo[1] * r,
            self.frame_id,
            self.default_value,
        )

    def same_geometry(self, other: Costmap2D) -> bool:
        return (
            self.costs.shape == other.costs.shape
            and self.resolution == other.resolution
            and self.origin_x == other.origin_x
            and self.origin_y == other.origin_y
        )

    def cell_centers(
        self, x0: int = 0, y0: int = 0, xn: int | None = None, yn: int | None = None
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """World x (1, n) and y (m, 1) of the centres of cells [x0, xn) x [y0, yn), broadcastable."""
        xn = self.size_x if xn is None else xn
        yn = self.size_y if yn is None else yn
        xs = self.origin_x + (np.arange(x0, xn) + 0.5) * self.resolution
        ys = self.origin_y + (np.arange(y0, yn) + 0.5) * self.resolution
        return xs[None, :], ys[:, None]
