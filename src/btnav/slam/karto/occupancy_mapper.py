"""Karto's occupancy grid: hit and pass counts of every scan, traced at its (optimised) pose.

slam_toolbox publishes open_karto's `OccupancyGrid::CreateFromScans`, not a probabilistic
map: per cell, the beams that passed through it and the beams that ended in it, and after
a loop closure the grid is rebuilt from every scan at its new pose. The rules (`AddScan`,
`RayTrace`, `UpdateCell`) are Karto's; the lattice is anchored at the first scan's pose so
a rebuild gives the same array whatever the order, and all beams of a block of scans are
traced in one vectorised Bresenham pass counted with `np.add.at`. Rules and block sizes:
docs/decisions/0055.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ...core import fmath
from ...core.errors import BtnavError
from ...core.geometry import Pose2D, compose_arrays
from ...maps.occupancy_grid import FREE, OCCUPIED, UNKNOWN, OccupancyGrid

I64 = NDArray[np.int64]
F64 = NDArray[np.float64]

#: Rays are counted in blocks of about this many traced cells (2 MB temporaries stay in cache).
_BLOCK_CELLS = 1 << 18
#: The count arrays grow by this many cells beyond what a scan needs, so growth is rare.
_GROW_CELLS = 256
#: Count arrays larger than this (cells, 2 GB of counts) are refused: 790 m square at 5 cm
#: holds the largest benchmark log (Freiburg's hospital, ~400 x 200 m of odometry and the
#: laser's reach around it); a pose farther out means a diverged graph or a map too fine.
MAX_CELLS = 250_000_000

#: One scan for `rebuild`: (ranges, beam angles in the sensor frame, sensor pose in base).
ScanEntry = tuple[ArrayLike, ArrayLike, ArrayLike]


class MapTooLargeError(BtnavError, ValueError):
    """A map beyond MAX_CELLS: one clear message (the CLI exits 2), not a memory error."""


def _pose_row(value: ArrayLike, what: str) -> F64:
    v = np.asarray(value, dtype=float).reshape(-1)
    if v.shape != (3,) or not np.isfinite(v).all():
        raise ValueError(f"{what} must be three finite numbers [x, y, yaw], got {value!r}")
    return v


def _beams(ranges: ArrayLike, angles: ArrayLike) -> tuple[F64, F64]:
    r = np.asarray(ranges, dtype=float).reshape(-1)
    a = np.asarray(angles, dtype=float).reshape(-1)
    if r.shape != a.shape:
        raise ValueError(f"ranges and angles differ in length ({r.size} and {a.size})")
    return r, a


class OccupancyMapper:
    """The map slam_toolbox publishes, as Karto counts it (see the module docstring)."""

    def __init__(
        self,
        resolution: float,
        max_laser_range: float,
        *,
        occupancy_threshold: float = 0.1,
        min_pass_through: int = 2,
    ) -> None:
        if not (math.isfinite(resolution) and resolution > 0):
            raise ValueError(f"resolution must be a positive number of metres, got {resolution}")
        if not (math.isfinite(max_laser_range) and max_laser_range > 0):
            raise ValueError(f"max_laser_range must be a positive number, got {max_laser_range}")
        if not 0.0 <= occupancy_threshold <= 1.0:
            raise ValueError(f"occupancy_threshold must be in [0, 1], got {occupancy_threshold}")
        if int(min_pass_through) != min_pass_through or min_pass_through < 0:
            raise ValueError(f"min_pass_through must be a count >= 0, got {min_pass_through}")
        self.resolution = float(resolution)
        self.max_laser_range = float(max_laser_range)
        self.occupancy_threshold = float(occupancy_threshold)
        self.min_pass_through = int(min_pass_through)
        self._anchor: tuple[float, float] | None = None
        self._passes = np.zeros((0, 0), np.int32)
        self._hits = np.zeros((0, 0), np.int32)
        self._row0 = 0  # lattice (row, col) of array cell [0, 0]
        self._col0 = 0
        self._touched: list[int] | None = None  # [row_min, row_max, col_min, col_max], lattice

    # -- input -------------------------------------------------------------------------

    def add_scan(
        self,
        pose: ArrayLike,
        ranges: NDArray[np.floating],
        angles: NDArray[np.floating],
        sensor_offset: ArrayLike = (0.0, 0.0, 0.0),
    ) -> None:
        """Count one scan taken at `pose` (base in map) by a sensor at `sensor_offset` (in base)."""
        base = _pose_row(pose, "pose")
        offset = _pose_row(sensor_offset, "sensor_offset")
        r, a = _beams(ranges, angles)
        if self._anchor is None:
            self._anchor = (float(base[0]), float(base[1]))
        sensor = compose_arrays(base[None, :], offset[None, :])
        self._trace(sensor, np.array([r.size]), r, a)

    def rebuild(self, poses: NDArray[np.floating], scans: Sequence[ScanEntry]) -> None:
        """Forget all counts and count every scan again at its new pose (after an optimisation).

        The lattice keeps its anchor, so unchanged poses give an unchanged grid.
        """
        p = np.asarray(poses, dtype=float)
        if p.ndim != 2 or p.shape[1] != 3 or len(p) != len(scans):
            raise ValueError(
                f"poses must be (K, 3) with one row per scan, got {p.shape} for {len(scans)} scans"
            )
        if not np.isfinite(p).all():
            raise ValueError("poses must be finite")
        self._passes.fill(0)
        self._hits.fill(0)
        self._touched = None
        if len(p) == 0:
            return
        if self._anchor is None:
            self._anchor = (float(p[0, 0]), float(p[0, 1]))
        # unpacking the caller's tuples is per scan; all the work after it is per block
        pairs = [_beams(r, a) for r, a, _ in scans]
        offsets = np.array([_pose_row(o, "sensor_offset") for _, _, o in scans]).reshape(-1, 3)
        counts = np.array([r.size for r, _ in pairs], dtype=np.int64)
        ranges = np.concatenate([r for r, _ in pairs]) if pairs else np.zeros(0)
        angles = np.concatenate([a for _, a in pairs]) if pairs else np.zeros(0)
        self._trace(compose_arrays(p, offsets), counts, ranges, angles)

    # -- output ------------------------------------------------------------------------

    def grid(self, frame_id: str = "map") -> OccupancyGrid:
        """The map (-1 unknown, 0 free, 100 occupied), cropped to the cells any ray reached."""
        res = self.resolution
        ax, ay = self._anchor if self._anchor is not None else (0.0, 0.0)
        if self._touched is None:
            return OccupancyGrid(np.full((1, 1), UNKNOWN, np.int8), res, Pose2D(ax, ay), frame_id)
        r_lo, r_hi, c_lo, c_hi = self._touched
        rows = slice(r_lo - self._row0, r_hi - self._row0 + 1)
        cols = slice(c_lo - self._col0, c_hi - self._col0 + 1)
        passes, hits = self._passes[rows, cols], self._hits[rows, cols]
        known = passes > self.min_pass_through
        ratio = hits / np.maximum(passes, 1)
        data = np.full(passes.shape, UNKNOWN, np.int8)
        data[known] = FREE
        data[known & (ratio > self.occupancy_threshold)] = OCCUPIED
        origin = Pose2D(ax + c_lo * res, ay + r_lo * res, 0.0)
        return OccupancyGrid(data, res, origin, frame_id)

    # -- tracing -----------------------------------------------------------------------

    def _cells(self, x: F64, y: F64) -> tuple[I64, I64]:
        """Lattice (row, col) of world points: whole cells from the anchor, whatever the extent."""
        assert self._anchor is not None
        ax, ay = self._anchor
        col = np.floor((x - ax) / self.resolution).astype(np.int64)
        row = np.floor((y - ay) / self.resolution).astype(np.int64)
        return row, col

    def _trace(self, sensors: F64, beam_counts: I64, ranges: F64, angles: F64) -> None:
        """Count the rays of scans taken from `sensors` (K, 3), `beam_counts[k]` beams each."""
        scan_of = np.repeat(np.arange(len(sensors)), beam_counts)
        valid = np.isfinite(ranges) & (ranges > 0.0)
        if not valid.any():
            return
        scan_of, r, a = scan_of[valid], ranges[valid], angles[valid]
        hit = r < self.max_laser_range
        length = np.minimum(r, self.max_laser_range)
        s, c = fmath.sincos(sensors[scan_of, 2] + a)
        sx, sy = sensors[scan_of, 0], sensors[scan_of, 1]
        r_end, c_end = self._cells(sx + length * c, sy + length * s)
        r_scan, c_scan = self._cells(sensors[:, 0], sensors[:, 1])
        r_start, c_start = r_scan[scan_of], c_scan[scan_of]

        lo_r = int(min(r_start.min(), r_end.min()))
        hi_r = int(max(r_start.max(), r_end.max()))
        lo_c = int(min(c_start.min(), c_end.min()))
        hi_c = int(max(c_start.max(), c_end.max()))
        self._grow(lo_r, hi_r, lo_c, hi_c)
        if self._touched is None:
            self._touched = [lo_r, hi_r, lo_c, hi_c]
        else:
            t = self._touched
            self._touched = [min(t[0], lo_r), max(t[1], hi_r), min(t[2], lo_c), max(t[3], hi_c)]

        # array coordinates from here on
        r_start, r_end = r_start - self._row0, r_end - self._row0
        c_start, c_end = c_start - self._col0, c_end - self._col0
        dr, dc = r_end - r_start, c_end - c_start
        n = np.maximum(np.abs(dr), np.abs(dc))
        # blocks of whole rays with at most _BLOCK_CELLS cells (a ray longer than that alone)
        ends = np.cumsum(n + 1)
        cuts = np.searchsorted(ends, np.arange(_BLOCK_CELLS, int(ends[-1]), _BLOCK_CELLS))
        bounds = np.unique(np.concatenate([[0], cuts, [len(n)]]))
        for i0, i1 in zip(bounds[:-1].tolist(), bounds[1:].tolist(), strict=True):
            self._count_block(
                r_start[i0:i1], c_start[i0:i1], r_end[i0:i1], c_end[i0:i1], hit[i0:i1]
            )

    def _count_block(self, r0: I64, c0: I64, r1: I64, c1: I64, hit: NDArray[np.bool_]) -> None:
        """Count the Bresenham cells of a block of rays (array coordinates) as passes, and
        the end cells of the rays that hit once more as passes and as hits."""
        width = self._passes.shape[1]
        dr, dc = r1 - r0, c1 - c0
        adr, adc = np.abs(dr), np.abs(dc)
        steep = adr > adc
        n = np.maximum(adr, adc)
        # one step along the major axis, and one along the minor axis, as flat offsets
        major = np.where(steep, np.sign(dr) * width, np.sign(dc))
        minor = np.where(steep, np.sign(dc), np.sign(dr) * width)
        slope = np.where(steep, adc, adr) / np.maximum(n, 1)
        start = r0 * width + c0

        cells = n + 1
        first = np.cumsum(cells) - cells
        k = np.arange(int(cells.sum()), dtype=np.intp)
        k -= np.repeat(first, cells)
        # round(k * slope), ties up: Bresenham's minor-axis offset (k * slope + 0.5 >= 0)
        m = k * np.repeat(slope, cells)
        m += 0.5
        flat = m.astype(np.intp)
        flat *= np.repeat(minor, cells)
        k *= np.repeat(major, cells)
        flat += k
        flat += np.repeat(start, cells)
        one = np.int32(1)
        np.add.at(self._passes.reshape(-1), flat, one)
        ends = (r1 * width + c1)[hit]
        np.add.at(self._passes.reshape(-1), ends, one)
        np.add.at(self._hits.reshape(-1), ends, one)

    def _grow(self, lo_r: int, hi_r: int, lo_c: int, hi_c: int) -> None:
        """Make the count arrays cover lattice rows lo_r..hi_r and cols lo_c..hi_c (inclusive)."""
        h, w = self._passes.shape
        rows_fit = self._row0 <= lo_r and hi_r < self._row0 + h
        if h and rows_fit and self._col0 <= lo_c and hi_c < self._col0 + w:
            return
        if h == 0:
            new_r0, new_r1 = lo_r - _GROW_CELLS, hi_r + 1 + _GROW_CELLS
            new_c0, new_c1 = lo_c - _GROW_CELLS, hi_c + 1 + _GROW_CELLS
        else:
            new_r0 = self._row0 if lo_r >= self._row0 else lo_r - _GROW_CELLS
            new_r1 = self._row0 + h if hi_r < self._row0 + h else hi_r + 1 + _GROW_CELLS
            new_c0 = self._col0 if lo_c >= self._col0 else lo_c - _GROW_CELLS
            new_c1 = self._col0 + w if hi_c < self._col0 + w else hi_c + 1 + _GROW_CELLS
        shape = (new_r1 - new_r0, new_c1 - new_c0)
        if shape[0] * shape[1] > MAX_CELLS:
            raise MapTooLargeError(
                f"the SLAM map would need {shape[1]} x {shape[0]} cells at {self.resolution:g} m "
                f"(more than {MAX_CELLS:,}): a scan pose lies "
                f"{max(abs(lo_r), abs(hi_r), abs(lo_c), abs(hi_c)) * self.resolution:.0f} m "
                "from the first one; the pose graph has diverged, or the area needs a "
                "coarser resolution",
                key="resolution",
            )
        passes = np.zeros(shape, np.int32)
        hits = np.zeros(shape, np.int32)
        if h:
            rows = slice(self._row0 - new_r0, self._row0 - new_r0 + h)
            cols = slice(self._col0 - new_c0, self._col0 - new_c0 + w)
            passes[rows, cols] = self._passes
            hits[rows, cols] = self._hits
        self._passes, self._hits = passes, hits
        self._row0, self._col0 = new_r0, new_c0
