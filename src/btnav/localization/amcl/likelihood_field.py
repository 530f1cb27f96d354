"""The map as AMCL sees it: occupancy states, the distance field, lookup tables.

nav2_amcl converts the OccupancyGrid into `map_t` (a cell is occupied at 100, free at
0, unknown otherwise) and `map_update_cspace` stores, per cell, the distance from its
centre to the nearest occupied cell's centre, capped at `laser_likelihood_max_dist`.
Here that is one `scipy.ndimage.distance_transform_edt` (exact Euclidean distance, where
AMCL's brushfire is exact too within its cap).

One departure: the distance is to the nearest occupied cell on a *surface* (one with a
non-occupied cell among its eight neighbours), so a cell deep inside a filled solid is
as far from a hit as its depth. A lidar beam stops at the first surface; nav2_amcl
scores a beam that ends inside a filled block (a map drawn from a plan, or `btnav map
from-world`) as a perfect hit, so every solid is a plateau of perfect scores that pulls
the cloud into it. In worlds/aisle_warehouse.yaml (solid 7 x 0.8 m shelf rows) that let
the cloud spread ~1.3 m across a 2.2 m aisle and jump into the next one: 5.8 m RMS with
Nav2's amcl section (seed 0), 15 cm with surfaces (tests/localization/test_aisle_warehouse.py).
A map made by SLAM, or walls and racks drawn as outlines, have no interior cells, and
their field is nav2_amcl's exactly.

Everything a laser model reads per beam is precomputed per cell, so an update is a
gather and not an `exp` per beam: `table(values, off_map, reach)` pads a per-cell array
with the off-map value (AMCL scores a beam end off the map as `max_occ_dist` away), wide
enough that beams from particles on the map stay inside it, so the common case needs
no clipping; when a particle is off the map every point is clipped onto the border.

Cells follow the OccupancyGrid (cell = floor((x - origin) / resolution)), as map_server
and the costmaps read them. nav2_amcl's MAP_GXWX comes to round((x - origin) /
resolution) whatever the map's size: it reads every cell half a cell low, so its
estimate sits half a cell off in x and in y (on the office tour, seeds 0-2, that took
the mean RMS from 5.5 to 6.7 cm on the drawn map and from 6.8 to 9.3 cm on the SLAM
map); not copied, and tests/localization/test_scan_to_map.py keeps it out. The map
origin's yaw is honoured (nav2_amcl ignores it): particles are moved into the origin's
frame first.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray
from scipy.ndimage import binary_erosion, distance_transform_edt

from ...core import fmath
from ...maps.occupancy_grid import FREE, OCCUPIED, OccupancyGrid

F64 = NDArray[np.float64]


class CellTable:
    """A per-cell array padded by `pad` cells of the off-map value, flat, for gathers."""

    def __init__(
        self, data: F64, pad: int, width: int, height: int, always_clip: bool = True
    ) -> None:
        self.data = data
        self.always_clip = always_clip
        self.pad = pad
        self.stride = width + 2 * pad
        self.width, self.height = width, height

    def inside(self, cells: F64) -> bool:
        """Whether every (x, y) in map-cell units lies on the map (then beams of the
        table's reach stay inside the padding and need no clipping)."""
        x, y = cells[:, 0], cells[:, 1]
        return bool(
            x.min() >= 0.0 and y.min() >= 0.0 and x.max() < self.width and y.max() < self.height
        )

    def index(self, gx: F64, gy: F64, clip: bool) -> NDArray[np.intp]:
        """Flat indices of points in padded cell units (`clip`: some may be off the table;
        they land on its border, off-map too). Clobbers gx, gy when clipping."""
        if clip or self.always_clip:
            np.clip(gx, 0.0, self.stride - 1.0, out=gx)
            np.clip(gy, 0.0, len(self.data) // self.stride - 1.0, out=gy)
        ix = gx.astype(np.intp)  # non-negative: truncation is floor
        iy = gy.astype(np.intp)
        iy *= self.stride
        iy += ix
        return iy

    def at(self, x: F64, y: F64) -> F64:
        """Values at points in map-cell units (any shape; clipped onto the border)."""
        gx, gy = x + self.pad, y + self.pad
        return self.data.take(self.index(gx, gy, True))


class MapField:
    """An OccupancyGrid with AMCL's per-cell distance to the nearest obstacle.

    `occ_dist` is (height, width) in metres to the nearest `surface` cell, at most
    `max_occ_dist`; `free` marks the cells AMCL may put a uniform particle in
    (occ_state -1: map value 0).
    """

    def __init__(self, grid: OccupancyGrid, max_occ_dist: float) -> None:
        self.grid = grid
        self.resolution = float(grid.resolution)
        self.origin = grid.origin
        self.height, self.width = grid.data.shape
        self.max_occ_dist = float(max_occ_dist)
        data = grid.data
        self.occupied = data == OCCUPIED
        self.free = data == FREE
        self.surface = surface_cells(self.occupied)
        if self.surface.any():
            dist = distance_transform_edt(~self.surface) * self.resolution
            self.occ_dist = np.minimum(dist, self.max_occ_dist)
        else:
            self.occ_dist = np.full(data.shape, self.max_occ_dist)
        self._nonfree_dist: CellTable | None = None

    # -- geometry -------------------------------------------------------------------------

    def to_cells(self, poses: F64) -> F64:
        """(N, 3) map poses -> (N, 3): x and y in cells from the map's corner (unpadded),
        yaw relative to the origin's."""
        o = self.origin
        out = np.empty_like(poses)
        dx, dy = poses[:, 0] - o.x, poses[:, 1] - o.y
        if o.yaw != 0.0:
            s, c = fmath.sincos(o.yaw)
            dx, dy = c * dx + s * dy, -s * dx + c * dy
        out[:, 0] = dx / self.resolution
        out[:, 1] = dy / self.resolution
        out[:, 2] = poses[:, 2] - o.yaw
        return out

    def table(self, values: F64, off_map: float, reach: float = 0.0) -> CellTable:
        """`values` per cell in a table padded with `off_map` wide enough that a beam of
        up to `reach` metres from a particle on the map never leaves it (so no clipping
        while every particle is on the map); at most ~4M cells, else a 1-cell ring."""
        pad = math.ceil(reach / self.resolution) + 2
        always_clip = (self.height + 2 * pad) * (self.width + 2 * pad) > 4_000_000
        if always_clip:
            pad = 1
        out = np.full((self.height + 2 * pad, self.width + 2 * pad), off_map)
        out[pad : pad + self.height, pad : pad + self.width] = values
        return CellTable(out.ravel(), pad, self.width, self.height, always_clip)

    def free_cell_centres(self, step: int = 1) -> F64:
        """(K, 2) map coordinates of the free cells' centres (every `step`-th row and column:
        nav2_amcl's `freespace_downsampling`)."""
        rows, cols = np.nonzero(self.free[::step, ::step])
        return self.grid.cell_to_world(np.stack([rows * step, cols * step], axis=-1))

    def occ_state_at(self, x: float, y: float) -> int | None:
        """-1 free, 0 unknown, +1 occupied at a map point; None off the map."""
        (r, c) = self.grid.world_to_cell([(x, y)])[0]
        if not (0 <= r < self.height and 0 <= c < self.width):
            return None
        if self.occupied[r, c]:
            return 1
        return -1 if self.free[r, c] else 0

    # -- the beam model's ray casting -------------------------------------------------------

    @property
    def nonfree_dist(self) -> CellTable:
        """Distance in cells from each cell's centre to the nearest cell that stops a ray
        in `map_calc_range` (occupied, unknown or off the map); 0 on those (1-cell ring)."""
        if self._nonfree_dist is None:
            free = np.zeros((self.height + 2, self.width + 2), bool)
            free[1:-1, 1:-1] = self.free
            dist = np.asarray(distance_transform_edt(free), float)
            self._nonfree_dist = CellTable(dist.ravel(), 1, self.width, self.height)
        return self._nonfree_dist


def surface_cells(occupied: NDArray[np.bool_]) -> NDArray[np.bool_]:
    """The occupied cells a beam can end in: those with a non-occupied cell (free,
    unknown, or off the map) among their eight neighbours."""
    inner = binary_erosion(occupied, structure=np.ones((3, 3), bool), border_value=0)
    return occupied & ~inner


def gaussian_pz(
    field: MapField, z_hit: float, z_rand: float, sigma_hit: float, range_max: float
) -> tuple[F64, float]:
    """Per cell: z_hit * exp(-d^2 / (2 sigma^2)) + z_rand / range_max (nav2_amcl's pz of a
    beam ending there); and the off-map value (d = max_occ_dist)."""
    denom = 2.0 * sigma_hit * sigma_hit
    rand = z_rand / range_max
    d = field.occ_dist
    pz = z_hit * fmath.exp(-(d * d) / denom) + rand
    m = field.max_occ_dist
    off = z_hit * fmath.exp(-(m * m) / denom) + rand
    return pz, float(off)
