"""How SLAM is judged: relation errors against ground truth, pose RMS, and map quality.

Real logs have no ground-truth trajectory, only ground-truth *relations* between pairs
of poses (Kümmerle et al., "On measuring the accuracy of SLAM algorithms", 2009), so
the standard score compares the estimated relative motion between two stamps with the
true one; it does not punish a map for being anchored or bent elsewhere. In simulation
the true trajectory and the true map are known, so `ate_rms` and `map_quality` judge
the result directly (no alignment: btnav's SLAM map is anchored at the start pose).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from os import PathLike
from pathlib import Path

import numpy as np
from numpy.typing import NDArray
from scipy.ndimage import distance_transform_edt

from ..core import fmath
from ..core.errors import BtnavError
from ..core.geometry import normalize_angle
from ..maps.occupancy_grid import FREE, OCCUPIED, OccupancyGrid

F64 = NDArray[np.float64]

#: Fields of a relations line: t1 t2 x y z roll pitch yaw.
_RELATION_FIELDS = 8


class RelationsError(BtnavError):
    """A ground-truth relations file that cannot be read."""


# -- ground-truth relations ------------------------------------------------------------


def relations(path: str | PathLike[str]) -> F64:
    """Read a Freiburg relations file: rows (t1, t2, x, y, yaw), the pose at t2 seen from t1.

    Lines are `t1 t2 x y z roll pitch yaw`; blank lines and lines starting with `#` are
    skipped (z, roll and pitch are read and dropped: the data sets are planar).
    """
    p = Path(path)
    try:
        text = p.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as err:
        reason = err.strerror if isinstance(err, OSError) and err.strerror else str(err)
        raise RelationsError(f"cannot read the relations file: {reason}", file=p) from None
    rows: list[list[float]] = []
    for number, line in enumerate(text.splitlines(), start=1):  # a file's lines: parsing
        fields = line.split()
        if not fields or fields[0].startswith("#"):
            continue
        if len(fields) != _RELATION_FIELDS:
            raise RelationsError(
                f"expected {_RELATION_FIELDS} numbers (t1 t2 x y z roll pitch yaw), "
                f"got {len(fields)}",
                file=p,
                line=number,
            )
        try:
            values = [float(f) for f in fields]
        except ValueError:
            bad = next(f for f in fields if not _is_float(f))
            raise RelationsError(f"'{bad}' is not a number", file=p, line=number) from None
        if not all(math.isfinite(v) for v in values):
            raise RelationsError("every field must be a finite number", file=p, line=number)
        t1, t2, x, y, _z, _roll, _pitch, yaw = values
        rows.append([t1, t2, x, y, yaw])
    return np.array(rows, dtype=float).reshape(-1, 5)


def _is_float(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


@dataclass(frozen=True)
class RelationErrors:
    """Kümmerle's statistics: means and (population) standard deviations of the absolute
    and of the squared errors, translation in metres, rotation in radians."""

    trans_mean: float
    trans_std: float
    trans_sq_mean: float
    trans_sq_std: float
    rot_mean: float
    rot_std: float
    rot_sq_mean: float
    rot_sq_std: float
    used: int
    skipped: int

    @property
    def rot_mean_deg(self) -> float:
        return math.degrees(self.rot_mean)


def _nearest(
    sorted_stamps: F64, t: F64, max_dt: float
) -> tuple[NDArray[np.intp], NDArray[np.bool_]]:
    """Index of the stamp nearest each t (the earlier one on a tie), and whether it is close enough."""
    j = np.searchsorted(sorted_stamps, t)
    before = np.clip(j - 1, 0, len(sorted_stamps) - 1)
    after = np.clip(j, 0, len(sorted_stamps) - 1)
    d_before = np.abs(t - sorted_stamps[before])
    d_after = np.abs(sorted_stamps[after] - t)
    idx = np.where(d_after < d_before, after, before)
    return idx, np.minimum(d_before, d_after) <= max_dt


def relation_errors(
    stamps: NDArray[np.floating],
    poses: NDArray[np.floating],
    rel: NDArray[np.floating],
    *,
    max_dt: float = 0.05,
) -> RelationErrors:
    """Score a trajectory (stamps (K,), poses (K, 3)) against relations (R, 5) from `relations`.

    Each relation takes the trajectory's poses nearest t1 and t2 (within `max_dt`, else it
    is skipped and counted), forms delta = x1^-1 (+) x2 and compares it with the true
    delta: |t(delta) - t(delta*)| (both in the frame at t1) and |wrap(yaw - yaw*)|.
    """
    s = np.asarray(stamps, dtype=float).reshape(-1)
    x = np.asarray(poses, dtype=float)
    r = np.asarray(rel, dtype=float)
    if x.ndim != 2 or x.shape != (len(s), 3):
        raise ValueError(f"poses must be (K, 3) with one row per stamp, got {x.shape} for {len(s)}")
    if r.ndim != 2 or r.shape[1] != 5:
        raise ValueError(f"relations must be (R, 5) rows t1 t2 x y yaw, got {r.shape}")
    if len(s) == 0 or len(r) == 0:
        used = np.zeros(len(r), bool)
        i1 = i2 = np.zeros(len(r), np.intp)
    else:
        order = np.argsort(s, kind="stable")
        s_sorted, x = s[order], x[order]
        i1, ok1 = _nearest(s_sorted, r[:, 0], max_dt)
        i2, ok2 = _nearest(s_sorted, r[:, 1], max_dt)
        used = ok1 & ok2
    a, b, truth = x[i1[used]], x[i2[used]], r[used]
    dx, dy = b[:, 0] - a[:, 0], b[:, 1] - a[:, 1]
    sin_a, cos_a = fmath.sincos(a[:, 2])
    tx = cos_a * dx + sin_a * dy
    ty = cos_a * dy - sin_a * dx
    trans = fmath.hypot(tx - truth[:, 2], ty - truth[:, 3])
    rot = np.abs(normalize_angle(b[:, 2] - a[:, 2] - truth[:, 4]))
    n_used = int(used.sum())

    def mean_std(v: F64) -> tuple[float, float]:
        if not len(v):
            return math.nan, math.nan
        return float(v.mean()), float(v.std())

    tm, ts = mean_std(trans)
    tsm, tss = mean_std(trans * trans)
    rm, rs = mean_std(rot)
    rsm, rss = mean_std(rot * rot)
    return RelationErrors(tm, ts, tsm, tss, rm, rs, rsm, rss, n_used, len(r) - n_used)


# -- trajectories against ground truth -------------------------------------------------


def ate_rms(estimate: NDArray[np.floating], truth: NDArray[np.floating]) -> tuple[float, float]:
    """RMS position error (m) and RMS yaw error (rad) of matching rows, no alignment."""
    e = np.asarray(estimate, dtype=float)
    t = np.asarray(truth, dtype=float)
    if e.ndim != 2 or e.shape[1] != 3 or e.shape != t.shape or not len(e):
        raise ValueError(
            f"estimate and truth must be the same (K, 3) shape, got {e.shape}, {t.shape}"
        )
    dx, dy = e[:, 0] - t[:, 0], e[:, 1] - t[:, 1]
    dyaw = normalize_angle(e[:, 2] - t[:, 2])
    return math.sqrt(float(np.mean(dx * dx + dy * dy))), math.sqrt(float(np.mean(dyaw * dyaw)))


# -- maps against the true map ---------------------------------------------------------


@dataclass(frozen=True)
class MapQuality:
    """How a SLAM map matches the true one.

    occupied_near_surface: fraction of the SLAM map's occupied cells within the tolerance
    of a truly occupied cell (walls drawn where walls are); free_is_free: fraction of its
    free cells that are free in truth (no free space drawn through walls or outside);
    coverage: its free area over the true free area (how much it has explored; can
    exceed 1 when it marks free what truth does not know).
    """

    occupied_near_surface: float
    free_is_free: float
    coverage: float
    slam_free_m2: float
    truth_free_m2: float


def _cells_of(grid: OccupancyGrid, value: int) -> NDArray[np.intp]:
    return np.argwhere(grid.data == value)


def _truth_cells(truth: OccupancyGrid, points: F64) -> tuple[NDArray[np.int64], NDArray[np.bool_]]:
    """The truth cells holding world points, clamped to the grid, and which were inside it."""
    rc = truth.world_to_cell(points)
    inside = truth.in_bounds(rc)
    rc[:, 0] = np.clip(rc[:, 0], 0, truth.height - 1)
    rc[:, 1] = np.clip(rc[:, 1], 0, truth.width - 1)
    return rc, inside


def map_quality(
    slam: OccupancyGrid, truth: OccupancyGrid, *, tolerance: float = 0.10
) -> MapQuality:
    """Compare a SLAM map with the true map (any origins and resolutions, one world frame).

    The distance of a SLAM occupied cell's centre to the nearest truly occupied cell is
    measured to the centre of the occupied cell nearest the truth cell that holds it (one
    distance transform of truth, scipy's `distance_transform_edt` with its indices), so
    it can overestimate by at most one truth cell's half-diagonal.
    """
    if not (math.isfinite(tolerance) and tolerance >= 0):
        raise ValueError(f"tolerance must be a non-negative number of metres, got {tolerance}")
    occupied = _cells_of(slam, OCCUPIED)
    truth_occupied = truth.data == OCCUPIED
    if len(occupied) and truth_occupied.any():
        nearest = distance_transform_edt(
            ~truth_occupied, return_distances=False, return_indices=True
        )
        centres = slam.cell_to_world(occupied)
        rc, _ = _truth_cells(truth, centres)
        q = truth.cell_to_world(nearest[:, rc[:, 0], rc[:, 1]].T)
        dist = fmath.hypot(centres[:, 0] - q[:, 0], centres[:, 1] - q[:, 1])
        # a hair of slack so a tolerance of exactly n cells is not lost to rounding
        near = float(np.mean(dist <= tolerance + 1e-9))
    else:
        near = 0.0

    free = _cells_of(slam, FREE)
    if len(free):
        rc, inside = _truth_cells(truth, slam.cell_to_world(free))
        is_free = inside & (truth.data[rc[:, 0], rc[:, 1]] == FREE)
        free_is_free = float(np.mean(is_free))
    else:
        free_is_free = 0.0

    slam_free_m2 = len(free) * slam.resolution**2
    truth_free_m2 = int(np.count_nonzero(truth.data == FREE)) * truth.resolution**2
    coverage = slam_free_m2 / truth_free_m2 if truth_free_m2 > 0 else 0.0
    return MapQuality(near, free_is_free, coverage, slam_free_m2, truth_free_m2)
