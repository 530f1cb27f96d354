"""Cartographer's 2D submaps: probability grids that range data is inserted into, two at a time.

A submap is a small map built from consecutive range data and never changed once
finished: local SLAM matches scans against one, global SLAM closes loops against finished
ones. Cells store probabilities as Cartographer does, in 15 bits updated through an odds
table (integer lookups, the same bits everywhere); rays are traced exactly as
Cartographer's sub-pixel `RayToPixelMask`, in one vectorised pass; `ActiveSubmaps` keeps
two. All submaps of a trajectory share one lattice, so a ray is traced once for both.
Details: docs/decisions/0070.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from ...core import fmath
from ...core.geometry import Pose2D, compose_arrays
from ...core.messages import LaserScan
from ...maps.occupancy_grid import OccupancyGrid

F64 = NDArray[np.float64]
I64 = NDArray[np.int64]

MIN_PROBABILITY, MAX_PROBABILITY = 0.1, 0.9
#: The largest cell value; values 1..MAX_VALUE spread [MIN_PROBABILITY, MAX_PROBABILITY].
MAX_VALUE = 32767
#: The narrowest border `Submap.scoring` pads with (the matchers ask for 4 and 2 n + 1).
SCORING_BORDER = 8
UNKNOWN = 0
#: Cells added around a grid when it grows, so that growth is rare.
_GROW = 64


def probability_to_value(p: F64 | float) -> NDArray[np.uint16]:
    """Cartographer's BoundedFloatToValue: clamp to [0.1, 0.9], round to the 15-bit lattice."""
    q = np.clip(np.asarray(p, float), MIN_PROBABILITY, MAX_PROBABILITY)
    scale = (MAX_VALUE - 1) / (MAX_PROBABILITY - MIN_PROBABILITY)
    return (np.floor((q - MIN_PROBABILITY) * scale + 0.5) + 1).astype(np.uint16)


def value_to_probability(v: NDArray[np.integer]) -> F64:
    """The probability of cell values (unknown reads as MIN_PROBABILITY, as Cartographer's)."""
    v = np.maximum(np.asarray(v, np.int64), 1)
    return MIN_PROBABILITY + (v - 1) * ((MAX_PROBABILITY - MIN_PROBABILITY) / (MAX_VALUE - 1))


@functools.lru_cache(maxsize=8)
def odds_update_table(probability: float) -> NDArray[np.uint16]:
    """value -> value after one observation of `probability` (a hit or a miss)."""
    odds = probability / (1.0 - probability)
    p = value_to_probability(np.arange(MAX_VALUE + 1))
    o = p / (1.0 - p) * odds
    table = probability_to_value(o / (1.0 + o))
    table[UNKNOWN] = probability_to_value(probability)
    table.flags.writeable = False
    return table


@dataclass
class RangeData:
    """One insertion, in the local SLAM frame: the sensor origin, end points that hit
    something (`returns`) and end points of rays that did not (`misses`)."""

    origin: F64  # (2,)
    returns: F64  # (N, 2)
    misses: F64  # (M, 2)

    @classmethod
    def from_scan(
        cls, scan: LaserScan, laser: F64, min_range: float, max_range: float, missing_ray: float
    ) -> RangeData:
        """A scan as Cartographer reads it, in the frame `laser` (the sensor's pose) is
        given in: readings within [min_range, max_range] are returns; longer ones, and
        btnav's +inf "no return" (which cartographer_ros would drop), are misses
        `missing_ray` long: free space out to there."""
        r = np.asarray(scan.ranges, dtype=float)
        hit = np.isfinite(r) & (r >= min_range) & (r <= max_range)
        miss = r > max_range
        s, c = fmath.sincos(scan.angles)
        length = np.where(hit, r, missing_ray)
        ends = compose_arrays(laser, np.column_stack([length * c, length * s, np.zeros(len(r))]))
        return cls(np.asarray(laser[:2], float), ends[hit, :2], ends[miss, :2])

    def transformed(self, pose: F64) -> RangeData:
        """This range data, given in `pose`'s own frame, in the frame `pose` is given in."""
        p = np.asarray(pose, float)

        def move(xy: F64) -> F64:
            if not len(xy):
                return np.zeros((0, 2))
            return compose_arrays(p, np.column_stack([xy, np.zeros(len(xy))]))[:, :2]

        return RangeData(move(self.origin[None, :])[0], move(self.returns), move(self.misses))


@dataclass(frozen=True)
class Lattice:
    """The cell lattice of a trajectory's submaps: cell (row, col) is centred on
    (x0 + col * resolution, y0 + row * resolution)."""

    resolution: float
    x0: float
    y0: float

    def coordinates(self, xy: F64) -> tuple[F64, F64]:
        """Continuous (row, col) in which cell k spans [k, k + 1)."""
        inv = 1.0 / self.resolution
        return (xy[:, 1] - self.y0) * inv + 0.5, (xy[:, 0] - self.x0) * inv + 0.5

    def cells(self, xy: F64) -> tuple[I64, I64]:
        r, c = self.coordinates(xy)
        return np.floor(r).astype(np.int64), np.floor(c).astype(np.int64)

    def centres(self, rows: I64, cols: I64) -> F64:
        return np.column_stack([self.x0 + cols * self.resolution, self.y0 + rows * self.resolution])


def _crossings(a0: F64, a1: F64, b0: F64, b1: F64) -> tuple[I64, I64, I64]:
    """Every crossing of a grid line `a = k` by the segments (a0, b0) -> (a1, b1): the
    cells on both sides of it (a index below and above) and the b index there."""
    fa0, fa1 = np.floor(a0).astype(np.int64), np.floor(a1).astype(np.int64)
    n = np.abs(fa1 - fa0)
    total = int(n.sum())
    if total == 0:
        empty = np.zeros(0, np.int64)
        return empty, empty, empty
    ray = np.repeat(np.arange(len(n)), n)
    k = np.arange(total) - np.repeat(np.cumsum(n) - n, n)
    up = fa1[ray] > fa0[ray]
    line = np.where(up, fa0[ray] + 1 + k, fa0[ray] - k)
    t = (line - a0[ray]) / (a1[ray] - a0[ray])
    b = np.floor(b0[ray] + t * (b1[ray] - b0[ray])).astype(np.int64)
    return line - 1, line, b


def ray_cells(r0: float, c0: float, r1: F64, c1: F64) -> tuple[I64, I64]:
    """(rows, cols) of every cell the rays from (r0, c0) to each (r1, c1) pass through
    (continuous lattice coordinates), start and end cells included, with repeats."""
    n = len(r1)
    ra, rb = np.full(n, r0), np.full(n, c0)
    lo, hi, b = _crossings(rb, c1, ra, r1)  # vertical grid lines: columns change
    lo2, hi2, b2 = _crossings(ra, r1, rb, c1)  # horizontal grid lines: rows change
    start_r, start_c = np.floor([r0, c0]).astype(np.int64)
    rows = np.concatenate([[start_r], b, b, lo2, hi2, np.floor(r1).astype(np.int64)])
    cols = np.concatenate([[start_c], lo, hi, b2, b2, np.floor(c1).astype(np.int64)])
    return rows, cols


class Submap:
    """One submap: a probability grid on the trajectory's lattice and where it began."""

    def __init__(self, index: int, local_pose: F64, lattice: Lattice) -> None:
        self.index = index
        self.local_pose = np.asarray(local_pose, float)  # origin, in the local SLAM frame
        self.lattice = lattice
        self.values = np.zeros((0, 0), np.uint16)
        self.row0 = self.col0 = 0  # lattice cell of values[0, 0]
        self.num_range_data = 0
        self.finished = False
        self.revision = 0  # bumped on every insertion: cached views of the grid go stale
        self.node_ids: list[int] = []
        self._scoring_cache: dict[int, tuple[int, NDArray[np.uint16]]] = {}

    def grow(self, lo_r: int, hi_r: int, lo_c: int, hi_c: int) -> None:
        """Cover lattice rows lo_r..hi_r and cols lo_c..hi_c (inclusive)."""
        h, w = self.values.shape
        if h and self.row0 <= lo_r and hi_r < self.row0 + h and self.col0 <= lo_c and hi_c < self.col0 + w:  # fmt: skip
            return
        r0 = min(lo_r, self.row0) - _GROW if h else lo_r - _GROW
        c0 = min(lo_c, self.col0) - _GROW if h else lo_c - _GROW
        r1 = max(hi_r + 1, self.row0 + h) + _GROW if h else hi_r + 1 + _GROW
        c1 = max(hi_c + 1, self.col0 + w) + _GROW if h else hi_c + 1 + _GROW
        values = np.zeros((r1 - r0, c1 - c0), np.uint16)
        if h:
            values[self.row0 - r0 : self.row0 - r0 + h, self.col0 - c0 : self.col0 - c0 + w] = self.values  # fmt: skip
        self.values, self.row0, self.col0 = values, r0, c0

    def apply(self, rows: I64, cols: I64, table: NDArray[np.uint16]) -> None:
        """One table update of each (distinct) lattice cell."""
        flat = (rows - self.row0) * self.values.shape[1] + (cols - self.col0)
        v = self.values.reshape(-1)
        v[flat] = table[v[flat]]

    def known_bounds(self) -> tuple[int, int, int, int] | None:
        """Lattice row_lo, row_hi, col_lo, col_hi (inclusive) of the known cells."""
        rows = np.flatnonzero(self.values.any(axis=1))
        cols = np.flatnonzero(self.values.any(axis=0))
        if not rows.size:
            return None
        return (self.row0 + int(rows[0]), self.row0 + int(rows[-1]), self.col0 + int(cols[0]), self.col0 + int(cols[-1]))  # fmt: skip

    def scoring(self, border: int) -> tuple[NDArray[np.uint16], int, int]:
        """The grid for matching: unknown read as the lowest value (probability 0.1, as
        Cartographer scores it), inside a border of `border` such cells (lookups that
        fall off the grid are clipped into it); and the lattice cell of its [0, 0]. The
        border is at least `SCORING_BORDER`, so the real-time matcher and the Ceres
        matcher share one copy per insertion (a wider border of the lowest value reads
        the same: a clipped lookup lands in it either way)."""
        border = max(border, SCORING_BORDER)
        cached = self._scoring_cache.get(border)
        if cached is None or cached[0] != self.revision:
            padded = np.pad(np.maximum(self.values, 1), border, constant_values=1)
            self._scoring_cache[border] = cached = (self.revision, padded)
        return cached[1], self.row0 - border, self.col0 - border


@dataclass
class ActiveSubmaps:
    """Cartographer's ActiveSubmaps2D: range data goes into the (at most) two newest submaps."""

    num_range_data: int
    resolution: float
    hit_probability: float
    miss_probability: float
    submaps: list[Submap] = field(default_factory=list)
    lattice: Lattice | None = None

    @property
    def active(self) -> list[Submap]:
        return [s for s in self.submaps[-2:] if not s.finished]

    @property
    def matching(self) -> Submap | None:
        """The submap local SLAM matches against: the older active one."""
        active = self.active
        return active[0] if active else None

    def insert(self, data: RangeData, local_pose: F64) -> tuple[list[Submap], Submap | None]:
        """Insert one range data (local frame); the submaps it went into and the submap
        this insertion finished, if any."""
        if self.lattice is None:
            self.lattice = Lattice(self.resolution, float(data.origin[0]), float(data.origin[1]))
        if not self.submaps or self.submaps[-1].num_range_data == self.num_range_data:
            self.submaps.append(Submap(len(self.submaps), local_pose, self.lattice))
        targets = self.active
        hits, misses = self._cells(data)
        for submap in targets:
            if hits[0].size or misses[0].size:
                bounds = [np.concatenate([hits[k], misses[k]]) for k in (0, 1)]
                submap.grow(int(bounds[0].min()), int(bounds[0].max()), int(bounds[1].min()), int(bounds[1].max()))  # fmt: skip
                submap.apply(*hits, odds_update_table(self.hit_probability))
                submap.apply(*misses, odds_update_table(self.miss_probability))
            submap.num_range_data += 1
            submap.revision += 1
        finished = None
        front = targets[0]
        if front.num_range_data == 2 * self.num_range_data:
            front.finished = finished = front
        return targets, finished

    def _cells(self, data: RangeData) -> tuple[tuple[I64, I64], tuple[I64, I64]]:
        """The distinct hit cells and the distinct miss cells (hits excluded) of one insertion."""
        lat = self.lattice
        assert lat is not None
        o_r, o_c = lat.coordinates(data.origin[None, :])
        h_r, h_c = lat.coordinates(data.returns)
        m_r, m_c = lat.coordinates(data.misses)
        ends_r, ends_c = np.concatenate([h_r, m_r]), np.concatenate([h_c, m_c])
        if not ends_r.size:
            empty = np.zeros(0, np.int64)
            return (empty, empty), (empty, empty)
        rows, cols = ray_cells(float(o_r[0]), float(o_c[0]), ends_r, ends_c)
        hit_r, hit_c = np.floor(h_r).astype(np.int64), np.floor(h_c).astype(np.int64)
        lo_r, lo_c = int(rows.min()), int(cols.min())
        shape = (int(rows.max()) - lo_r + 1, int(cols.max()) - lo_c + 1)
        hit = np.zeros(shape, bool)
        hit[hit_r - lo_r, hit_c - lo_c] = True
        miss = np.zeros(shape, bool)
        miss[rows - lo_r, cols - lo_c] = True
        miss &= ~hit
        hr, hc = np.nonzero(hit)
        mr, mc = np.nonzero(miss)
        return (hr + lo_r, hc + lo_c), (mr + lo_r, mc + lo_c)


def assemble_map(
    submaps: list[Submap],
    global_poses: F64,
    anchor: F64,
    frame_id: str,
    occupied: float = 0.65,
    free: float = 0.25,
) -> OccupancyGrid:
    """The map of all submaps at their global poses (cartographer_ros's /map), as map_saver
    would save it: each map cell sums the log-odds of the submaps that know it (their
    evidence taken as independent), then occupied above `occupied`, free below `free`,
    unknown between. Cells lie a whole number of cells from `anchor` (x, y)."""
    res = submaps[0].lattice.resolution if submaps else 0.05
    lattice = Lattice(res, float(anchor[0]), float(anchor[1]))
    boxes = []
    for submap, pose in zip(submaps, global_poses, strict=True):
        known = submap.known_bounds()
        if known is None:
            continue
        r_lo, r_hi, c_lo, c_hi = known
        corners = submap.lattice.centres(
            np.array([r_lo, r_lo, r_hi, r_hi]), np.array([c_lo, c_hi, c_lo, c_hi])
        )
        world = compose_arrays(_to_global(submap, pose), np.column_stack([corners, np.zeros(4)]))[
            :, :2
        ]
        rows, cols = lattice.cells(world)
        boxes.append(
            (
                submap,
                pose,
                int(rows.min()) - 1,
                int(rows.max()) + 1,
                int(cols.min()) - 1,
                int(cols.max()) + 1,
            )
        )
    if not boxes:
        return OccupancyGrid(
            np.full((1, 1), -1, np.int8), res, Pose2D(float(anchor[0]), float(anchor[1])), frame_id
        )
    lo_r, hi_r = min(b[2] for b in boxes), max(b[3] for b in boxes)
    lo_c, hi_c = min(b[4] for b in boxes), max(b[5] for b in boxes)
    total = np.zeros((hi_r - lo_r + 1, hi_c - lo_c + 1))
    seen = np.zeros(total.shape, bool)
    for submap, pose, r0, r1, c0, c1 in boxes:  # a handful of submaps; all cells at once
        rr, cc = np.meshgrid(np.arange(r0, r1 + 1), np.arange(c0, c1 + 1), indexing="ij")
        odds = submap_log_odds(submap, pose, rr.ravel(), cc.ravel(), lattice).reshape(rr.shape)
        total[r0 - lo_r : r1 - lo_r + 1, c0 - lo_c : c1 - lo_c + 1] += odds
        seen[r0 - lo_r : r1 - lo_r + 1, c0 - lo_c : c1 - lo_c + 1] |= odds != 0.0
    data = np.full(total.shape, -1, np.int8)
    data[seen & (total < log_odds_threshold(free))] = 0
    data[seen & (total > log_odds_threshold(occupied))] = 100
    known_r = np.flatnonzero((data >= 0).any(axis=1))
    known_c = np.flatnonzero((data >= 0).any(axis=0))
    if known_r.size:
        data = data[known_r[0] : known_r[-1] + 1, known_c[0] : known_c[-1] + 1]
        lo_r, lo_c = lo_r + int(known_r[0]), lo_c + int(known_c[0])
    # a cell's corner, half a cell below its centre
    origin = Pose2D(lattice.x0 + (lo_c - 0.5) * res, lattice.y0 + (lo_r - 0.5) * res, 0.0)
    return OccupancyGrid(data, res, origin, frame_id)


def _to_global(submap: Submap, global_pose: F64) -> F64:
    """The transform taking the submap's local-frame coordinates to the map frame."""
    g = np.asarray(global_pose, float)
    lp = submap.local_pose
    s, c = fmath.sincos(float(lp[2]))
    inv = np.array([-(c * lp[0] + s * lp[1]), s * lp[0] - c * lp[1], -lp[2]])
    return compose_arrays(g[None, :], inv[None, :])[0]


def submap_log_odds(
    submap: Submap, global_pose: F64, rows: I64, cols: I64, map_lattice: Lattice
) -> F64:
    """The log-odds a submap at `global_pose` gives map cells (rows, cols) of `map_lattice`
    (0 where it knows nothing): each map cell reads the submap cell under its centre."""
    centres = map_lattice.centres(rows, cols)
    t = _to_global(submap, global_pose)  # local -> map; its inverse takes map cells home
    s, c = fmath.sincos(float(t[2]))
    dx, dy = centres[:, 0] - t[0], centres[:, 1] - t[1]
    r, q = submap.lattice.cells(np.column_stack([c * dx + s * dy, -s * dx + c * dy]))
    r, q = r - submap.row0, q - submap.col0
    h, w = submap.values.shape
    inside = (r >= 0) & (r < h) & (q >= 0) & (q < w)
    v = np.zeros(len(r), np.uint16)
    v[inside] = submap.values[r[inside], q[inside]]
    return _log_odds_table()[v]


@functools.lru_cache(maxsize=1)
def _log_odds_table() -> F64:
    p = value_to_probability(np.arange(MAX_VALUE + 1))
    table = fmath.log(p / (1.0 - p))
    table[UNKNOWN] = 0.0
    table.flags.writeable = False
    return table


def log_odds_threshold(probability: float) -> float:
    """The log-odds of a probability, for thresholds (map_saver's 0.65 and 0.25)."""
    return float(fmath.log(probability / (1.0 - probability)))
