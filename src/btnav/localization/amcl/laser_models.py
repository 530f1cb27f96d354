"""nav2_amcl's laser models: how well each particle explains a scan.

`LaserData.from_scan` does what AMCL's `updateFilter` does to a scan: range_max is
the scan's, lowered to `laser_max_range` if that is set (> 0); a reading at or below
range_min (the scan's, raised to `laser_min_range`) becomes range_max; bearings are
in the base frame (the laser's yaw added). Then `sensor_function(field, poses, data)`
gives each particle's weight factor (N,), as a whole (particles x beams) array:

- `LikelihoodFieldModel` (`likelihood_field`): beams from 0 in steps of
  (count - 1) // (max_beams - 1); max-range and NaN readings are skipped; a beam's end
  d metres from the nearest obstacle has pz = z_hit exp(-d^2 / 2 sigma_hit^2) +
  z_rand / range_max, and the factor is 1 + sum(pz^3) (nav2_amcl's ad-hoc sum). pz^3
  is tabulated per map cell, so a beam costs a gather.
- `LikelihoodFieldModelProb` (`likelihood_field_prob`): beams in steps of
  ceil(count / max_beams); the factor is prod(pz) (exp of a sum of tabulated logs).
  With `do_beamskip`, once the filter has converged, a beam counts only when more
  than `beam_skip_threshold` of the particles see its end within
  `beam_skip_distance` of an obstacle, unless at least `beam_skip_error_threshold`
  of the beams would be skipped (then the filter is probably lost and all count).
- `BeamModel` (`beam`): the expected range along each beam is cast through the map
  (cells that are not free stop it, as `map_calc_range`), and pz mixes a Gaussian
  hit, an exponential short reading (z_short, lambda_short), a max-range reading
  (z_max) and a uniform one; the factor is 1 + sum(pz^3). The casting marches each
  ray by the distance to the nearest non-free cell (a distance field again), all
  rays at once: tens of passes, where the other models need one.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
from numpy.typing import NDArray

from ...core import fmath
from ...core.kernel_switch import Method, default_method
from ...core.messages import LaserScan
from .beam_ends_kernel import beam_end_cells
from .likelihood_field import CellTable, MapField, gaussian_pz

#: How the likelihood-field models find their beam ends: beam_ends_kernel's compiled
#: loop, or numpy's passes (BTNAV_AMCL=numpy); the same indices either way.
DEFAULT_METHOD: Method = default_method("BTNAV_AMCL")

F64 = NDArray[np.float64]


@dataclass
class LaserData:
    """A scan as the laser models read it (nav2_amcl's LaserData), beams not yet thinned."""

    ranges: F64  # metres; short readings already moved to range_max
    bearings: F64  # radians in the base frame
    range_max: float
    laser_xy: tuple[float, float]  # the laser's position in the base frame

    @classmethod
    def from_scan(
        cls,
        scan: LaserScan,
        laser_pose: tuple[float, float, float],
        laser_min_range: float,
        laser_max_range: float,
    ) -> LaserData:
        range_max = float(scan.range_max)
        if laser_max_range > 0.0:
            range_max = min(range_max, laser_max_range)
        range_min = float(scan.range_min)
        if laser_min_range > 0.0:
            range_min = max(range_min, laser_min_range)
        ranges = np.asarray(scan.ranges, dtype=np.float64).copy()
        ranges[ranges <= range_min] = range_max  # NaN compares false and stays NaN
        bearings = laser_pose[2] + scan.angle_min + scan.angle_increment * np.arange(len(ranges))
        return cls(ranges, bearings, range_max, (laser_pose[0], laser_pose[1]))


def _endpoint_cells(
    table: CellTable,
    field: MapField,
    poses: F64,
    data: LaserData,
    ranges: F64,
    bearings: F64,
    sincos: tuple[F64, F64] | None,
    method: Method,
) -> NDArray[np.intp]:
    """(N, B) flat indices into `table` of the beams' ends for every particle.

    The beam ends are rotated by each particle's yaw with the angle-sum identity (one
    sincos per particle and one per beam, never per particle x beam); `method` "kernel"
    is beam_ends_kernel's loop, "numpy" the passes below (the same indices)."""
    cp = field.to_cells(poses)
    sb, cb = fmath.sincos(bearings)
    inv = 1.0 / field.resolution
    ex = (data.laser_xy[0] + ranges * cb) * inv  # beam ends in the base frame, in cells
    ey = (data.laser_xy[1] + ranges * sb) * inv
    if sincos is None or field.origin.yaw != 0.0:
        sincos = fmath.sincos(cp[:, 2])
    clip = not table.inside(cp)
    cp[:, :2] += table.pad
    if method == "kernel":
        out = np.empty((len(cp), len(ex)), np.intp)
        rows = len(table.data) // table.stride
        px, py, s, c = (np.ascontiguousarray(v) for v in (cp[:, 0], cp[:, 1], *sincos))
        clip = clip or table.always_clip
        beam_end_cells(px, py, s, c, ex, ey, table.stride, rows, clip, out)
        return out
    s, c = sincos[0][:, None], sincos[1][:, None]
    gx = c * ex
    tmp = s * ey
    gx -= tmp
    gx += cp[:, 0:1]
    gy = s * ex
    np.multiply(c, ey, out=tmp)
    gy += tmp
    gy += cp[:, 1:2]
    return table.index(gx, gy, clip)


def _reach(data: LaserData) -> float:
    """How far from a particle a beam end can be (m)."""
    return data.range_max + abs(data.laser_xy[0]) + abs(data.laser_xy[1])


class LaserModel:
    """Common parameters; `sensor_function` gives each particle's weight factor."""

    NAME: ClassVar[str] = ""

    def __init__(
        self,
        *,
        z_hit: float,
        z_rand: float,
        sigma_hit: float,
        max_beams: int,
        z_short: float = 0.0,
        z_max: float = 0.0,
        lambda_short: float = 0.1,
        do_beamskip: bool = False,
        beam_skip_distance: float = 0.5,
        beam_skip_threshold: float = 0.3,
        beam_skip_error_threshold: float = 0.9,
    ) -> None:
        self.z_hit, self.z_rand, self.sigma_hit = float(z_hit), float(z_rand), float(sigma_hit)
        self.z_short, self.z_max, self.lambda_short = float(z_short), float(z_max), lambda_short
        self.max_beams = int(max_beams)
        self.do_beamskip = bool(do_beamskip)
        self.beam_skip_distance = float(beam_skip_distance)
        self.beam_skip_threshold = float(beam_skip_threshold)
        self.beam_skip_error_threshold = float(beam_skip_error_threshold)
        self._tables: dict[tuple[int, float, float], tuple[CellTable, ...]] = {}
        #: Beams the last update skipped by beam skipping (likelihood_field_prob), for tests.
        self.skipped_beams = 0
        #: The beam ends' path: "kernel" (compiled) or "numpy" (the same bits).
        self.method: Method = DEFAULT_METHOD

    def beam_indices(self, count: int) -> NDArray[np.intp]:
        """Which readings the model reads: every step-th from the first."""
        step = max(1, (count - 1) // (self.max_beams - 1))
        return np.arange(0, count, step)

    def _table(self, field: MapField, data: LaserData) -> tuple[CellTable, ...]:
        # the laser's offset comes through the frame tree a few ulps off from scan to
        # scan: the reach is rounded so those scans share a table (its padding has two
        # cells to spare, and the values gathered do not depend on it)
        key = (id(field), data.range_max, round(_reach(data), 6))
        if key not in self._tables:
            self._tables = {key: self.make_tables(field, data)}  # one map at a time
        return self._tables[key]

    def make_tables(self, field: MapField, data: LaserData) -> tuple[CellTable, ...]:
        return ()

    def sensor_function(
        self,
        field: MapField,
        poses: F64,
        data: LaserData,
        converged: bool = False,
        sincos: tuple[F64, F64] | None = None,
    ) -> F64:
        """Each particle's weight factor; `converged` is the filter's (beam skipping) and
        `sincos` the particles' (sin, cos) of yaw if the caller has them."""
        raise NotImplementedError


class LikelihoodFieldModel(LaserModel):
    """nav2_amcl::LikelihoodFieldModel: 1 + sum of pz^3 over the beams."""

    NAME = "likelihood_field"

    def make_tables(self, field: MapField, data: LaserData) -> tuple[CellTable, ...]:
        pz, off = gaussian_pz(field, self.z_hit, self.z_rand, self.sigma_hit, data.range_max)
        return (field.table(pz * pz * pz, off * off * off, _reach(data)),)

    def sensor_function(
        self,
        field: MapField,
        poses: F64,
        data: LaserData,
        converged: bool = False,
        sincos: tuple[F64, F64] | None = None,
    ) -> F64:
        (pz3,) = self._table(field, data)
        idx = self.beam_indices(len(data.ranges))
        r = data.ranges[idx]
        ok = r < data.range_max  # also drops NaN
        if not ok.any():
            return np.ones(len(poses))
        cells = _endpoint_cells(
            pz3, field, poses, data, r[ok], data.bearings[idx][ok], sincos, self.method
        )
        p = pz3.data.take(cells).sum(axis=1)
        p += 1.0
        return p


class LikelihoodFieldModelProb(LaserModel):
    """nav2_amcl::LikelihoodFieldModelProb: the product of pz, with beam skipping."""

    NAME = "likelihood_field_prob"

    def beam_indices(self, count: int) -> NDArray[np.intp]:
        step = max(1, math.ceil(count / self.max_beams))
        return np.arange(0, count, step)

    def make_tables(self, field: MapField, data: LaserData) -> tuple[CellTable, ...]:
        pz, off = gaussian_pz(field, self.z_hit, self.z_rand, self.sigma_hit, data.range_max)
        reach = _reach(data)
        near = (field.occ_dist < self.beam_skip_distance).astype(float)
        return field.table(fmath.log(pz), fmath.log(off), reach), field.table(near, 0.0, reach)

    def sensor_function(
        self,
        field: MapField,
        poses: F64,
        data: LaserData,
        converged: bool = False,
        sincos: tuple[F64, F64] | None = None,
    ) -> F64:
        log_pz, near = self._table(field, data)
        idx = self.beam_indices(len(data.ranges))
        r = data.ranges[idx]
        ok = r < data.range_max
        self.skipped_beams = 0
        if not ok.any():
            return np.ones(len(poses))
        cells = _endpoint_cells(
            log_pz, field, poses, data, r[ok], data.bearings[idx][ok], sincos, self.method
        )
        logs = log_pz.data.take(cells)
        if self.do_beamskip and converged:
            agree = near.data.take(cells).sum(axis=0) / len(poses) > self.beam_skip_threshold
            skipped = len(idx) - int(agree.sum())  # max-range beams never agree
            self.skipped_beams = skipped
            if skipped < len(idx) * self.beam_skip_error_threshold:
                logs = logs[:, agree]
            else:  # most beams disagree: probably lost, so listen to all of them
                self.skipped_beams = 0
        return fmath.exp(logs.sum(axis=1))


class BeamModel(LaserModel):
    """nav2_amcl::BeamModel: expected ranges cast through the map."""

    NAME = "beam"

    def sensor_function(
        self,
        field: MapField,
        poses: F64,
        data: LaserData,
        converged: bool = False,
        sincos: tuple[F64, F64] | None = None,
    ) -> F64:
        idx = self.beam_indices(len(data.ranges))
        obs = data.ranges[idx]
        keep = ~np.isnan(obs)
        obs, bearings = np.minimum(obs[keep], data.range_max), data.bearings[idx][keep]
        if not obs.size:
            return np.ones(len(poses))
        rmax = data.range_max
        expected = cast_ranges(field, poses, data.laser_xy, bearings, rmax)
        z = obs[None, :] - expected
        pz = self.z_hit * fmath.exp(-(z * z) / (2.0 * self.sigma_hit * self.sigma_hit))
        short = self.z_short * self.lambda_short * fmath.exp(-self.lambda_short * obs)
        pz += np.where(z < 0.0, short[None, :], 0.0)
        pz += np.where(obs == rmax, self.z_max, self.z_rand / rmax)[None, :]
        return (pz * pz * pz).sum(axis=1) + 1.0


def cast_ranges(
    field: MapField, poses: F64, laser_xy: tuple[float, float], bearings: F64, range_max: float
) -> F64:
    """(N, B) ranges from each particle's laser along each bearing to the first cell that
    is not free (or off the map), at most `range_max` (nav2_amcl's map_calc_range).

    Sphere tracing on the distance to the nearest non-free cell centre: a ray at a
    point whose cell centre is D cells from one can go D - 1.5 cells without entering
    it; at least half a cell per step.
    """
    cp = field.to_cells(poses)
    inv = 1.0 / field.resolution
    s, c = fmath.sincos(cp[:, 2])
    ox = cp[:, 0] + (c * laser_xy[0] - s * laser_xy[1]) * inv
    oy = cp[:, 1] + (s * laser_xy[0] + c * laser_xy[1]) * inv
    sb, cb = fmath.sincos(bearings)
    dx = (c[:, None] * cb - s[:, None] * sb).ravel()
    dy = (s[:, None] * cb + c[:, None] * sb).ravel()
    n, b = len(poses), len(bearings)
    x0 = np.repeat(ox, b)
    y0 = np.repeat(oy, b)
    t_max = range_max * inv
    t = np.zeros(n * b)
    dist = field.nonfree_dist
    active = np.arange(n * b)
    for _ in range(int(2 * t_max) + 4):
        if not active.size:
            break
        ta = t[active]
        d = dist.at(x0[active] + ta * dx[active], y0[active] + ta * dy[active])
        moving = d > 0.0
        ta = ta[moving] + np.maximum(d[moving] - 1.5, 0.5)
        active = active[moving]
        t[active] = ta
        active = active[ta < t_max]
    np.minimum(t, t_max, out=t)
    return t.reshape(n, b) * field.resolution


LASER_MODELS: dict[str, type[LaserModel]] = {
    m.NAME: m for m in (LikelihoodFieldModel, LikelihoodFieldModelProb, BeamModel)
}
