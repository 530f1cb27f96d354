"""open_karto's correlative ScanMatcher, vectorised: the heart of slam_toolbox's Mapper.

slam_toolbox's sequential matcher and loop matcher are both this class with different
`MatcherParams`. `match` follows Karto's MatchScan: a smeared correlation grid of the
reference, a coarse search over translations and headings, response expansion, the mean
of tied poses with its covariance, then a fine search. Everything is integer lookups
summed exactly, trigonometry is `fmath`, no BLAS. Points come in the robot frame, so the
search and rotation centre is the robot's position (Karto's is the sensor's). The steps in
full: docs/decisions/0055.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from functools import partial

import numpy as np
from numpy.typing import NDArray

from btnav.core import fmath
from btnav.core.errors import ParamsError
from btnav.core.geometry import normalize_angle

from .correlation_grid import GRID_OCCUPIED, CorrelationGrid, karto_round

__all__ = [
    "COVARIANCE_WINDOW",
    "MatchResult",
    "MatcherParams",
    "ScanMatcher",
    "scan_reference_pose",
]

F64 = NDArray[np.float64]

#: Karto's constants (Mapper.cpp).
MAX_VARIANCE = 500.0
DISTANCE_PENALTY_GAIN = 0.2
ANGLE_PENALTY_GAIN = 0.2
KT_TOLERANCE = 1e-6
#: use_response_expansion widens the coarse angle window by this much, up to 3 times.
_EXPANSION_STEP = math.radians(20.0)
_EXPANSIONS = 3
#: responses within this much of the best count toward the covariances (Karto's
#: equally good poses).
COVARIANCE_WINDOW = 0.1


def _round(v: float) -> int:
    """`karto_round` of one Python float, without numpy's per-call cost."""
    return math.floor(v + 0.5) if v >= 0.0 else math.ceil(v - 0.5)


@dataclass(frozen=True)
class MatcherParams:
    """One matcher's slam_toolbox parameters (`correlation_search_space_*` for the
    sequential matcher, `loop_search_space_*` for the loop matcher, the rest shared)."""

    search_space_dimension: float  # m (0.5 sequential, 8.0 loop)
    search_space_resolution: float  # m (0.01 sequential, 0.05 loop)
    smear_deviation: float  # m (0.1 sequential, 0.03 loop)
    range_threshold: float  # m, slam_toolbox max_laser_range
    distance_variance_penalty: float = 0.5
    angle_variance_penalty: float = 1.0
    fine_search_angle_offset: float = 0.00349
    coarse_search_angle_offset: float = 0.349
    coarse_angle_resolution: float = 0.0349
    minimum_angle_penalty: float = 0.9
    minimum_distance_penalty: float = 0.05
    use_response_expansion: bool = True

    def __post_init__(self) -> None:
        positive = (
            "search_space_dimension",
            "search_space_resolution",
            "range_threshold",
            "distance_variance_penalty",
            "angle_variance_penalty",
            "fine_search_angle_offset",
            "coarse_search_angle_offset",
            "coarse_angle_resolution",
        )
        for key in positive:
            v = getattr(self, key)
            if not (math.isfinite(v) and v > 0.0):
                raise ParamsError(f"must be a positive number, got {v}", key=key)
        res = self.search_space_resolution
        cells = self.search_space_dimension / res
        if abs(cells - round(cells)) > 1e-6 * max(1.0, cells):
            raise ParamsError(
                f"the search space dimension {self.search_space_dimension} m is not a whole "
                f"number of cells of {res} m (Karto requires it)",
                key="search_space_dimension",
            )
        lo, hi = 0.5 * res, 10.0 * res
        if not (lo * (1 - 1e-9) <= self.smear_deviation <= hi * (1 + 1e-9)):
            raise ParamsError(
                f"smear deviation {self.smear_deviation} m must be between half a cell and "
                f"10 cells of the search space resolution ({lo:g} to {hi:g} m)",
                key="smear_deviation",
            )

    @classmethod
    def sequential(cls, range_threshold: float, **overrides: float | bool) -> MatcherParams:
        """slam_toolbox's defaults for the sequential (running scans) matcher."""
        kw: dict = dict(
            search_space_dimension=0.5, search_space_resolution=0.01, smear_deviation=0.1
        )
        return cls(range_threshold=range_threshold, **(kw | overrides))

    @classmethod
    def loop(cls, range_threshold: float, **overrides: float | bool) -> MatcherParams:
        """slam_toolbox's defaults for the loop-closure matcher."""
        kw: dict = dict(
            search_space_dimension=8.0, search_space_resolution=0.05, smear_deviation=0.03
        )
        return cls(range_threshold=range_threshold, **(kw | overrides))


@dataclass(frozen=True)
class MatchResult:
    """Karto's rMean, rCovariance and the returned response."""

    pose: F64  # (3,) x, y, yaw of the robot (base frame) in the map frame
    covariance: F64  # (3, 3)
    response: float  # 0..1 (after penalties when penalised)
    #: rad^2: the spread of the coarse search's headings whose best response is near the
    #: best (btnav's, see `ScanMatcher._heading_variance`); Karto's angular covariance
    #: (`covariance[2, 2]`, never above this) sees only the fine search's +-half a coarse
    #: step.
    heading_variance: float


@dataclass(frozen=True)
class _Search:
    """One CorrelateScan: responses over (angle, y, x) and where they were taken."""

    response: F64  # (A, T, T)
    xs: F64  # (T,) translation offsets from the centre, m
    ys: F64
    angles: F64  # (A,) absolute headings (not wrapped)
    centre: F64  # (3,) the search centre
    best: float
    mean: F64  # (3,) the mean of the tied best poses
    sums: NDArray[np.int64]  # (A, T, T) unpenalised grid sums
    first_cell: tuple[int, int]  # grid cell (row, col) of the lattice's first translation
    stride: int  # cells between translations


def scan_reference_pose(points_map: F64, pose: F64, use_scan_barycenter: bool) -> F64:
    """Karto's GetReferencePose: with `use_scan_barycenter`, the mean of the scan's end
    points (heading 0), else the scan's pose. Karto uses it only to measure distances
    between scans (which scans are near, which chain to match); the match itself
    always searches around the scan's pose."""
    pts = np.asarray(points_map, dtype=float).reshape(-1, 2)
    if not use_scan_barycenter or pts.shape[0] == 0:
        return np.asarray(pose, dtype=float).copy()
    return np.array([pts[:, 0].sum() / pts.shape[0], pts[:, 1].sum() / pts.shape[0], 0.0])


class ScanMatcher:
    """Karto's ScanMatcher for one set of `MatcherParams`."""

    def __init__(self, params: MatcherParams) -> None:
        self.params = params
        res = params.search_space_resolution
        #: half the search square in cells; the coarse lattice spans -half..half by 2
        self.half_cells = int(karto_round(params.search_space_dimension / res)) // 2
        #: Karto's grid: the search square plus the laser range each side
        self.roi_half_cells = self.half_cells + math.ceil(params.range_threshold / res - 1e-9)

    # -- public -------------------------------------------------------------------

    def match(
        self,
        points: F64,
        guess: F64,
        reference: Sequence[tuple[F64, F64]],
        *,
        penalize: bool = True,
        refine: bool = True,
        grid: CorrelationGrid | None = None,
    ) -> MatchResult:
        """The pose of the robot that best lays `points` ((N, 2), robot frame) onto the
        `reference` scans ((Mi, 2) map-frame end points in beam order, with the (3,) pose
        that saw them), searched around `guess` ((3,) map frame).

        Karto's matcher needs only the reference points (their order tells which way a
        surface faces); the poses ride along for the caller. Loop closure calls this
        with penalize=False, refine=False (slam_toolbox's TryCloseLoop).

        `grid`: a grid from `correlation_grid` to match many scans against the same
        reference without rebuilding it (`reference` is then ignored); the search lattice
        starts at the guess's cell of that grid instead of a grid centred on the guess."""
        p = self.params
        pts = np.asarray(points, dtype=float).reshape(-1, 2)
        g = np.asarray(guess, dtype=float).reshape(3)
        pts = pts[np.isfinite(pts).all(axis=1)]
        if pts.shape[0] == 0:
            cov = np.diag([MAX_VARIANCE, MAX_VARIANCE, 4.0 * p.coarse_angle_resolution**2])
            return MatchResult(g.copy(), cov, 0.0, math.pi**2)

        res = p.search_space_resolution
        if grid is None:
            far = float(np.sqrt((pts[:, 0] * pts[:, 0] + pts[:, 1] * pts[:, 1]).max()))
            grid = self.correlation_grid(reference, g[:2], g[:2], far)
            centre_cell = (0, 0)
        else:
            row, col = (int(v) for v in grid.world_to_cell(g[:2]))
            centre_cell = (row, col)

        # coarse: the whole search square at twice the resolution
        coarse = partial(
            self._correlate, grid, pts, g, centre_cell, self.half_cells * res, 2.0 * res,
            angle_step=p.coarse_angle_resolution, penalize=penalize,
        )  # fmt: skip
        angle_offset = p.coarse_search_angle_offset
        search = coarse(angle_offset=angle_offset)
        if p.use_response_expansion and abs(search.best) <= KT_TOLERANCE:
            for _ in range(_EXPANSIONS):
                angle_offset += _EXPANSION_STEP
                search = coarse(angle_offset=angle_offset)
                if abs(search.best) > KT_TOLERANCE:
                    break
        cov = self._positional_covariance(search, g, 2.0 * res)
        heading_variance = self._heading_variance(search)
        mean, best = search.mean, search.best

        if refine:
            # fine: +-1 cell around the coarse best, +-half a coarse angle step
            row, col = (int(v) for v in grid.world_to_cell(mean[:2]))
            fine = self._correlate(
                grid, pts, mean, (row, col), res, res,
                angle_offset=0.5 * p.coarse_angle_resolution,
                angle_step=p.fine_search_angle_offset, penalize=penalize,
            )  # fmt: skip
            cov[2, 2] = self._angular_covariance(grid, pts, fine)
            mean, best = fine.mean, fine.best
        return MatchResult(mean, cov, min(best, 1.0), max(heading_variance, float(cov[2, 2])))

    def correlation_grid(
        self,
        reference: Sequence[tuple[F64, F64]],
        viewpoint: F64,
        centre: F64,
        far: float,
    ) -> CorrelationGrid:
        """Karto's AddScans for this matcher: the reference scans' points that face
        `viewpoint` ((2,) map frame), smeared on a grid whose cell (0, 0) is centred on
        `centre`; it serves searches around guesses whose scan points lie within `far`
        metres of the centre (lookups stay within the coarse square, +1 cell for the
        fine search's centre and +1 for its window, plus that distance)."""
        p = self.params
        res = p.search_space_resolution
        return CorrelationGrid.from_scans(
            [np.asarray(s, dtype=float).reshape(-1, 2) for s, _ in reference],
            np.asarray(viewpoint, dtype=float)[:2],
            np.asarray(centre, dtype=float)[:2],
            resolution=res,
            smear_deviation=p.smear_deviation,
            roi_half_cells=self.roi_half_cells,
            pad=max(2 * self.half_cells, 2),
            reach_cells=self.half_cells + 3 + math.ceil(far / res),
        )

    # -- Karto's CorrelateScan ------------------------------------------------------

    def _correlate(
        self,
        grid: CorrelationGrid,
        pts: F64,
        centre: F64,
        centre_cell: tuple[int, int],
        offset: float,
        step: float,
        *,
        angle_offset: float,
        angle_step: float,
        penalize: bool,
    ) -> _Search:
        """Responses for translations -offset..offset by `step` (whole cells) around
        `centre` (its grid cell `centre_cell`) and headings within `angle_offset`."""
        p = self.params
        res = p.search_space_resolution
        count = _round(offset * 2.0 / step) + 1
        cells = _round(step / res)
        first = _round(-offset / res)
        xs = -offset + np.arange(count) * step
        n_angles = _round(angle_offset * 2.0 / angle_step) + 1
        angles = (centre[2] - angle_offset) + np.arange(n_angles) * angle_step

        sin_a, cos_a = fmath.sincos(angles)
        rows, cols = self._point_cells(pts, angles, (sin_a, cos_a))
        first_cell = (centre_cell[0] + first, centre_cell[1] + first)
        sums = grid.window_sums(rows + first_cell[0], cols + first_cell[1], count, cells)
        response = sums / float(pts.shape[0] * GRID_OCCUPIED)
        if penalize:
            sq = xs * xs
            dist = (
                1.0
                - DISTANCE_PENALTY_GAIN * (sq[:, None] + sq[None, :]) / p.distance_variance_penalty
            )
            dist = np.maximum(dist, p.minimum_distance_penalty)
            da = angles - centre[2]
            ang = 1.0 - ANGLE_PENALTY_GAIN * (da * da) / p.angle_variance_penalty
            ang = np.maximum(ang, p.minimum_angle_penalty)
            factor = dist[None, :, :] * ang[:, None, None]
            response = np.where(response > KT_TOLERANCE, response * factor, response)

        best = float(response.max())
        tied = np.flatnonzero(response.ravel() >= best - KT_TOLERANCE)
        a_i, rest = np.divmod(tied, count * count)
        y_i, x_i = np.divmod(rest, count)
        n = a_i.size
        # sin and cos per heading once, then picked per tied pose (many tie at 0); the
        # lookup's values serve when no heading needed wrapping (the same floats)
        wrapped = normalize_angle(angles)
        if np.array_equal(wrapped.view(np.int64), angles.view(np.int64)):
            s_a, c_a = sin_a, cos_a
        else:
            s_a, c_a = fmath.sincos(wrapped)
        mean = np.array(
            [
                (centre[0] + xs[x_i]).sum() / n,
                (centre[1] + xs[y_i]).sum() / n,
                float(fmath.arctan2(s_a[a_i].sum() / n, c_a[a_i].sum() / n)),
            ]
        )
        mean[2] = normalize_angle(float(mean[2]))
        return _Search(
            response, xs, xs, angles, np.asarray(centre, dtype=float), best, mean,
            sums, first_cell, cells,
        )  # fmt: skip

    def _point_cells(
        self, pts: F64, angles: F64, sincos: tuple[F64, F64] | None = None
    ) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
        """(A, N) cell offsets of the points rotated to each heading (Karto's
        GridIndexLookup::ComputeOffsets); `sincos`: the headings' sin and cos if known."""
        s, c = fmath.sincos(angles) if sincos is None else sincos
        x, y = pts[:, 0][None, :], pts[:, 1][None, :]
        c, s = c[:, None], s[:, None]
        inv = 1.0 / self.params.search_space_resolution
        cols = karto_round((c * x - s * y) * inv)
        rows = karto_round((s * x + c * y) * inv)
        return rows, cols

    # -- covariances ----------------------------------------------------------------

    def _positional_covariance(self, search: _Search, centre: F64, step: float) -> F64:
        """Karto's ComputePositionalCovariance from the coarse search: the spread of the
        translations whose best response over headings is near the best, inflated by
        1 / best response and floored at 0.1 step^2."""
        p = self.params
        cov = np.eye(3)
        best = search.best
        if best < KT_TOLERANCE:
            cov[0, 0] = cov[1, 1] = MAX_VARIANCE
            cov[2, 2] = 4.0 * p.coarse_angle_resolution**2
            return cov
        probs = search.response.max(axis=0)  # (T, T): y, x
        near = probs >= best - COVARIANCE_WINDOW
        w = probs[near]
        norm = w.sum()
        if norm > KT_TOLERANCE:
            yi, xi = np.nonzero(near)
            ex = search.xs[xi] - (search.mean[0] - centre[0])
            ey = search.ys[yi] - (search.mean[1] - centre[1])
            vxx = (ex * ex * w).sum() / norm
            vxy = (ex * ey * w).sum() / norm
            vyy = (ey * ey * w).sum() / norm
            floor = 0.1 * step * step
            k = 1.0 / best
            cov[0, 0] = max(vxx, floor) * k
            cov[0, 1] = cov[1, 0] = vxy * k
            cov[1, 1] = max(vyy, floor) * k
            cov[2, 2] = 4.0 * p.coarse_angle_resolution**2
        if abs(cov[0, 0]) <= KT_TOLERANCE:
            cov[0, 0] = MAX_VARIANCE
        if abs(cov[1, 1]) <= KT_TOLERANCE:
            cov[1, 1] = MAX_VARIANCE
        return cov

    def _heading_variance(self, search: _Search) -> float:
        """The coarse search's heading spread, as `_positional_covariance` takes the
        translations': the headings whose best response over translations is within
        0.1 of the best, weighted by it, about the mean heading, inflated by 1 / best
        response and floored at 0.1 step^2. A scan that matches about as well turned
        10 degrees either way (a corridor seen end-on, a room half in view) has a wide
        spread; Karto's angular covariance, over the fine search's +-1 degree, cannot
        say so."""
        p = self.params
        best = search.best
        if best < KT_TOLERANCE:
            return math.pi**2
        probs = search.response.max(axis=(1, 2))
        near = probs >= best - COVARIANCE_WINDOW
        w = probs[near]
        d = normalize_angle(search.angles[near] - search.mean[2])
        norm = w.sum()
        var = (d * d * w).sum() / norm if norm > KT_TOLERANCE else math.pi**2
        return max(float(var), 0.1 * p.coarse_angle_resolution**2) / best

    def _angular_covariance(self, grid: CorrelationGrid, pts: F64, fine: _Search) -> float:
        """Karto's ComputeAngularCovariance: the spread of the fine headings' responses
        (unpenalised, at the best pose's cell) that are near the best."""
        p = self.params
        angle_step = p.fine_search_angle_offset
        row, col = (int(v) for v in grid.world_to_cell(fine.mean[:2]))
        iy, ry = divmod(row - fine.first_cell[0], fine.stride)
        ix, rx = divmod(col - fine.first_cell[1], fine.stride)
        count = fine.sums.shape[1]
        if ry == 0 and rx == 0 and 0 <= iy < count and 0 <= ix < count:
            sums = fine.sums[:, iy, ix]  # that cell was a translation of the fine search
        else:
            rows, cols = self._point_cells(pts, fine.angles)
            sums = grid.window_sums(rows + row, cols + col, 1, 1)[:, 0, 0]
        response = sums / float(pts.shape[0] * GRID_OCCUPIED)
        centre_heading = float(fine.centre[2])
        best_angle = centre_heading + normalize_angle(fine.mean[2] - centre_heading)
        near = response >= fine.best - COVARIANCE_WINDOW
        norm = response[near].sum()
        if norm <= KT_TOLERANCE:
            return 1000.0 * angle_step * angle_step
        d = fine.angles[near] - best_angle
        acc = (d * d * response[near]).sum()
        if acc < KT_TOLERANCE:
            acc = angle_step * angle_step
        return float(acc / norm)
