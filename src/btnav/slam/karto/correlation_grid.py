"""Karto's CorrelationGrid: reference scans rasterised and smeared, ready for correlation.

open_karto scores a candidate pose by summing, over the scan's end points, a grid in which
the reference scans' end points are occupied and smeared by a Gaussian kernel. This module
builds that grid (Karto's FindValidPoints, AddScans, SmearPoint; the smear as exact
integer min-plus passes, or per-cell stamping where the occupied cells are few, both
Karto's grid cell for cell) and sums it for every translation and angle at once through an
`as_strided` view. Cells are indexed relative to the search centre, as Karto centres its
grid on the scan pose. Details: docs/decisions/0055.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.lib.stride_tricks import as_strided
from numpy.typing import NDArray

from btnav.core import fmath

__all__ = [
    "GRID_OCCUPIED",
    "CorrelationGrid",
    "find_valid_points",
    "half_kernel_size",
    "karto_round",
    "smear_kernel",
]

#: Karto's GridStates_Occupied: the value of a cell holding a reference end point.
GRID_OCCUPIED = 100
#: FindValidPoints compares directions only between points at least 10 cm apart.
_MIN_SQUARE_DISTANCE = 0.1 * 0.1
_I64 = np.int64
#: Rows smeared at a time: a band's operands (uint16) stay in cache.
_SMEAR_BAND = 64
#: Cost of stamping one kernel cell (a scattered max) over one cell-pass of the
#: separable smear (a streamed add or min): about 45 on x86-64 numpy 2.x.
_STAMP_COST = 45
#: Grid values gathered at once by `window_sums` (more spills out of cache).
_GATHER_BYTES = 1 << 20
#: Kernel cells stamped per block (bounds the index arrays to a few MB).
_STAMP_BLOCK = 1 << 18


def karto_round(v: NDArray[np.float64] | float) -> NDArray[np.int64]:
    """Karto's math::Round (half away from zero) as integers: grid indices must round as
    Karto's do, not to even as np.round does."""
    a = np.asarray(v, dtype=float)
    # a + 0.5 (a - 0.5 below zero) truncated: floor(a + 0.5) or ceil(a - 0.5), one pass
    return np.trunc(a + np.copysign(0.5, a)).astype(_I64)


def half_kernel_size(smear_deviation: float, resolution: float) -> int:
    """Karto smears for two standard deviations each side (the 95% region)."""
    return int(karto_round(2.0 * smear_deviation / resolution))


def _kernel_by_square_distance(
    half: int, smear_deviation: float, resolution: float
) -> NDArray[np.uint8]:
    """Kernel value per squared cell distance 0..2 half^2, and 0 for 'no occupied cell'
    (index 2 half^2 + 1), so a min-distance map turns into grid values by one take."""
    d2 = np.arange(2 * half * half + 1, dtype=float)
    z = fmath.exp(-0.5 * (d2 * (resolution * resolution)) / (smear_deviation * smear_deviation))
    table = np.zeros(d2.size + 1, np.uint8)
    table[:-1] = karto_round(z * GRID_OCCUPIED)
    return table


def smear_kernel(smear_deviation: float, resolution: float) -> NDArray[np.uint8]:
    """Karto's (2h+1, 2h+1) smear kernel, for inspection and tests (the grid never
    stamps it)."""
    h = half_kernel_size(smear_deviation, resolution)
    i = np.arange(-h, h + 1)
    d2 = i[:, None] * i[:, None] + i[None, :] * i[None, :]
    return _kernel_by_square_distance(h, smear_deviation, resolution)[d2]


# -- FindValidPoints ------------------------------------------------------------------


def _next_far_point(points: NDArray[np.float64], end: NDArray[np.int64]) -> NDArray[np.int64]:
    """For each point, the first later point of its scan more than 10 cm away (len if
    none): Karto's comparison step. Windows double in size, so a long run of close
    points costs a few passes, not one per point."""
    m = len(points)
    nxt = np.full(m, m, dtype=_I64)
    active = np.arange(m, dtype=_I64)
    lo, width = 0, 4
    while active.size:
        cand = active[:, None] + (lo + 1 + np.arange(width, dtype=_I64))[None, :]
        inside = cand < end[active][:, None]
        c = np.minimum(cand, m - 1)
        dx = points[active, 0][:, None] - points[c, 0]
        dy = points[active, 1][:, None] - points[c, 1]
        far = inside & (dx * dx + dy * dy > _MIN_SQUARE_DISTANCE)
        hit = far.any(axis=1)
        rows = np.flatnonzero(hit)
        nxt[active[rows]] = cand[rows, far[rows].argmax(axis=1)]
        active = active[~hit & inside[:, -1]]
        lo += width
        width *= 2
    return nxt


def find_valid_points(
    scans: Sequence[NDArray[np.float64]], viewpoint: NDArray[np.float64]
) -> NDArray[np.bool_]:
    """Which reference end points face `viewpoint` (Karto's FindValidPoints), over the
    concatenation of `scans` (each (Mi, 2), map frame, in beam order).

    Karto walks each scan keeping an anchor point; at every point more than 10 cm from
    the anchor it takes the sign of (anchor - v) x (point - v): counter-clockwise keeps
    the points from the anchor up to (not including) this one, clockwise drops them;
    either way this point becomes the anchor. Points after the last anchor are dropped.
    The anchors form a chain through `_next_far_point`, found by pointer doubling.
    """
    lengths = np.array([len(s) for s in scans], dtype=_I64)
    m = int(lengths.sum())
    if m == 0:
        return np.zeros(0, dtype=bool)
    pts = np.concatenate([np.asarray(s, dtype=float).reshape(-1, 2) for s in scans])
    ends = np.cumsum(lengths)
    starts = (ends - lengths)[lengths > 0]
    scan_of = np.repeat(np.arange(len(scans)), lengths)
    nxt = _next_far_point(pts, ends[scan_of])

    # anchors: every point reachable from a scan's first point along nxt
    jump = np.append(nxt, m)
    reach = np.zeros(m + 1, dtype=bool)
    reach[starts] = True
    for _ in range(int(lengths.max()).bit_length()):
        reach[jump[np.flatnonzero(reach)]] = True
        jump = jump[jump]
    anchors = np.flatnonzero(reach[:m])

    first, cur = pts[anchors[:-1]], pts[anchors[1:]]
    vx, vy = float(viewpoint[0]), float(viewpoint[1])
    a = vy - first[:, 1]
    b = first[:, 0] - vx
    c = first[:, 1] * vx - first[:, 0] * vy
    ss = cur[:, 0] * a + cur[:, 1] * b + c
    pair_ok = np.zeros(anchors.size, dtype=bool)
    pair_ok[:-1] = (scan_of[anchors[:-1]] == scan_of[anchors[1:]]) & (ss >= 0.0)
    seg = np.searchsorted(anchors, np.arange(m), side="right") - 1
    return pair_ok[seg]


# -- the grid -------------------------------------------------------------------------


@dataclass(frozen=True)
class CorrelationGrid:
    """Smeared reference end points around a search centre, in cells of `resolution`."""

    data: NDArray[np.uint8]  # (H, W); Karto's grid values 0..100
    resolution: float
    centre: tuple[float, float]  # world position of the centre of cell (0, 0)
    row0: int  # cell (row, col) of data[0, 0]; rows follow y, columns x
    col0: int
    core: tuple[int, int, int, int]  # row_lo, row_hi, col_lo, col_hi (inclusive) of non-zero cells
    pad: int  # zero cells around the core: lookup windows up to pad + 1 cells wide fit
    _views: dict[tuple[int, int], NDArray[np.uint8]] = field(
        default_factory=dict, init=False, repr=False, compare=False
    )

    @property
    def empty(self) -> bool:
        return self.core[0] > self.core[1]

    def world_to_cell(self, xy: NDArray[np.float64]) -> NDArray[np.int64]:
        """(..., 2) world x, y to (..., 2) cell (row, col), rounding as Karto's WorldToGrid."""
        xy = np.asarray(xy, dtype=float)
        scale = 1.0 / self.resolution
        col = karto_round((xy[..., 0] - self.centre[0]) * scale)
        row = karto_round((xy[..., 1] - self.centre[1]) * scale)
        return np.stack([row, col], axis=-1)

    @classmethod
    def from_scans(
        cls,
        scans: Sequence[NDArray[np.float64]],
        viewpoint: NDArray[np.float64],
        centre: NDArray[np.float64],
        *,
        resolution: float,
        smear_deviation: float,
        roi_half_cells: int,
        pad: int,
        reach_cells: int | None = None,
    ) -> CorrelationGrid:
        """Karto's AddScans: the facing points of `scans` within `roi_half_cells` of the
        centre cell (Karto's grid is the search area plus the laser range each side)
        marked 100 and smeared; `pad` zero cells around for lookup windows. With
        `reach_cells`, cells farther from the centre than that are never looked up, so
        points that cannot smear into that square are left out."""
        cx, cy = float(centre[0]), float(centre[1])
        if len(scans):
            valid = find_valid_points(scans, viewpoint)
            pts = np.concatenate([np.asarray(s, dtype=float).reshape(-1, 2) for s in scans])[valid]
        else:
            pts = np.zeros((0, 2))
        h = half_kernel_size(smear_deviation, resolution)
        scale = 1.0 / resolution
        col = karto_round((pts[:, 0] - cx) * scale)
        row = karto_round((pts[:, 1] - cy) * scale)
        limit = roi_half_cells if reach_cells is None else min(roi_half_cells, reach_cells + h)
        keep = (np.abs(col) <= limit) & (np.abs(row) <= limit)
        row, col = row[keep], col[keep]
        if row.size == 0:
            return cls(np.zeros((1, 1), np.uint8), resolution, (cx, cy), 0, 0, (0, -1, 0, -1), 0)
        r_lo, r_hi = int(row.min()) - h, int(row.max()) + h
        c_lo, c_hi = int(col.min()) - h, int(col.max()) + h
        height, width = r_hi - r_lo + 1, c_hi - c_lo + 1
        data = np.zeros((height + 2 * pad, width + 2 * pad), np.uint8)
        core = data[pad : pad + height, pad : pad + width]
        table = _kernel_by_square_distance(h, smear_deviation, resolution)
        occupied = np.unique((row - r_lo) * width + (col - c_lo))
        if occupied.size * (2 * h + 1) ** 2 * _STAMP_COST < height * width * (4 * h + 3):
            _smear_stamped(occupied, core, h, table)
        else:
            _smear_separable(occupied, core, h, table)
        return cls(
            data, resolution, (cx, cy), r_lo - pad, c_lo - pad, (r_lo, r_hi, c_lo, c_hi), pad
        )

    def window_sums(
        self,
        rows: NDArray[np.int64],
        cols: NDArray[np.int64],
        count: int,
        stride: int,
    ) -> NDArray[np.int64]:
        """GetResponse's sums for a lattice of translations, for every angle.

        `rows`, `cols` (A, N): cell of each rotated point for the lattice's first
        translation; the lattice has `count` x `count` translations `stride` cells apart.
        Returns (A, count, count) sums of grid values (points off the grid count 0).
        One fancy index gathers the blocks of grid values of every point of a chunk of
        angles from the phase sub-grids (see `_phase_blocks`) and one reduction sums the
        points: a small lattice takes all angles at once, a large one an angle at a time
        (the chunk's values stay in cache)."""
        n_angles, n_points = rows.shape
        if self.empty or n_points == 0:
            return np.zeros((n_angles, count, count), dtype=_I64)
        span = (count - 1) * stride
        if span > self.pad:
            raise ValueError(f"CorrelationGrid: a window of {span + 1} cells needs pad >= {span}")
        r_lo, r_hi, c_lo, c_hi = self.core
        touches = (rows <= r_hi) & (rows + span >= r_lo) & (cols <= c_hi) & (cols + span >= c_lo)
        blocks = self._phase_blocks(count, stride)
        r, c = rows - self.row0, cols - self.col0
        phase = (r % stride) * stride + (c % stride)  # 0 everywhere for stride 1
        # a point whose window misses the core reads the all-zero sub-grid at (0, 0)
        zero = stride * stride
        phase = np.where(touches, phase, zero).ravel()
        r = np.where(touches, r // stride, 0).ravel()
        c = np.where(touches, c // stride, 0).ravel()
        acc = np.uint16 if n_points * GRID_OCCUPIED <= np.iinfo(np.uint16).max else np.uint32
        sums = np.empty((n_angles, count * count), dtype=acc)
        # angles in chunks whose gathered values stay in cache
        chunk = max(1, _GATHER_BYTES // (n_points * count * count))
        for a in range(0, n_angles, chunk):
            k = slice(a * n_points, min(a + chunk, n_angles) * n_points)
            values = blocks[phase[k], r[k], c[k]].reshape(-1, n_points, count * count)
            values.sum(axis=1, dtype=acc, out=sums[a : a + chunk])
        return sums.reshape(n_angles, count, count).astype(_I64)

    def _phase_blocks(self, count: int, stride: int) -> NDArray[np.uint8]:
        """For a lattice `stride` cells apart, the grid split by (row, col) phase into
        stride^2 sub-grids (plus one of zeros), stacked and viewed as (phase, row, col,
        count, count) blocks: a point's values over the whole lattice are then one
        block of one array, and all points of all angles are gathered in one index."""
        key = (count, stride)
        cached = self._views.get(key)
        if cached is not None:
            return cached
        height, width = self.data.shape
        if stride == 1 and self.pad > count - 1 and height >= count and width >= count:
            # one phase: the grid itself, whose block at (0, 0) lies in the zero padding;
            # viewed without a copy (phase index 0 or 1 reads the same array)
            s0, s1 = self.data.strides
            view = as_strided(
                self.data,
                shape=(2, height - count + 1, width - count + 1, count, count),
                strides=(0, s0, s1, s0, s1),
                writeable=False,
            )
            self._views[key] = view
            return view
        h2, w2 = -(-height // stride), -(-width // stride)
        stack = np.zeros((stride * stride + 1, max(h2, count), max(w2, count)), np.uint8)
        for pr in range(stride):
            for pc in range(stride):
                sub = self.data[pr::stride, pc::stride]
                stack[pr * stride + pc, : sub.shape[0], : sub.shape[1]] = sub
        s0, s1, s2 = stack.strides
        blocks = as_strided(
            stack,
            shape=(
                stack.shape[0],
                stack.shape[1] - count + 1,
                stack.shape[2] - count + 1,
                count,
                count,
            ),
            strides=(s0, s1, s2, s1, s2),
            writeable=False,
        )
        self._views[key] = blocks
        return blocks


def _smear_stamped(
    occupied: NDArray[np.int64], out: NDArray[np.uint8], half: int, table: NDArray[np.uint8]
) -> None:
    """Karto's way: the kernel stamped (max) around every occupied cell (flat indices
    into `out`), in blocks of cells. Cheaper than `_smear_separable` when the occupied
    cells are few for the grid's area (a large open space)."""
    height, width = out.shape
    i = np.arange(-half, half + 1, dtype=_I64)
    offsets = (i[:, None] * width + i[None, :]).ravel()
    values = table[(i[:, None] * i[:, None] + i[None, :] * i[None, :]).ravel()]
    flat = np.zeros(height * width, np.uint8)
    block = max(1, _STAMP_BLOCK // offsets.size)
    for b in range(0, occupied.size, block):
        cells = occupied[b : b + block]
        np.maximum.at(
            flat,
            (cells[:, None] + offsets[None, :]).ravel(),
            np.broadcast_to(values, (cells.size, values.size)).ravel(),
        )
    out[...] = flat.reshape(height, width)


def _smear_separable(
    occupied: NDArray[np.int64], out: NDArray[np.uint8], half: int, table: NDArray[np.uint8]
) -> None:
    """Write into `out` (H, W) the max of Karto's square kernel over the occupied cells
    (flat indices), as table[min over occupied cells within the square of
    (di^2 + dj^2)]: min-plus along rows by scattering j^2 from each occupied cell, then
    along columns by 2 half shifted minimums of whole rows, in bands of `_SMEAR_BAND`
    rows so that the operands stay in cache."""
    height, width = out.shape
    inf = 2 * half * half + 1  # table[inf] == 0; inf + half^2 fits in uint16 for half <= 147
    d1 = np.full((height, width), inf, dtype=np.uint16)
    j = np.arange(-half, half + 1, dtype=_I64)
    np.minimum.at(
        d1.ravel(),
        (occupied[:, None] + j[None, :]).ravel(),
        np.broadcast_to((j * j).astype(np.uint16), (occupied.size, j.size)).ravel(),
    )
    band = np.empty((_SMEAR_BAND, width), dtype=np.uint16)
    tmp = np.empty_like(band)
    values = np.empty((_SMEAR_BAND, width), dtype=np.uint8)
    for r0 in range(0, height, _SMEAR_BAND):
        r1 = min(height, r0 + _SMEAR_BAND)
        dist = band[: r1 - r0]
        dist[...] = d1[r0:r1]
        for i in range(1, min(half, height - 1) + 1):
            sq = np.uint16(i * i)
            lo = max(r0, i)  # rows r take d1[r - i] + i^2
            if lo < r1:
                t = tmp[: r1 - lo]
                np.add(d1[lo - i : r1 - i], sq, out=t)
                np.minimum(dist[lo - r0 :], t, out=dist[lo - r0 :])
            hi = min(r1, height - i)  # rows r take d1[r + i] + i^2
            if hi > r0:
                t = tmp[: hi - r0]
                np.add(d1[r0 + i : hi + i], sq, out=t)
                np.minimum(dist[: hi - r0], t, out=dist[: hi - r0])
        np.take(table, dist, out=values[: r1 - r0], mode="clip")
        out[r0:r1] = values[: r1 - r0]
