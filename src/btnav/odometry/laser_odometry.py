"""Laser odometry (rf2o_laser_odometry's role): odom -> base_footprint from scans alone.

A robot without good wheel encoders can still publish `odom` by matching scans. Each scan
is matched against the last *keyframe*, not the previous scan, and a new keyframe starts
only after `keyframe_distance` or `keyframe_angle`, so a crawling or standing robot does not
random-walk. A match is the constant-velocity prediction, Karto's correlative matcher over
a small window, then a point-to-line (PL-ICP) refinement that removes the grid's
quantisation; a weak match keeps the prediction, as rf2o coasts. fmath and explicit sums
only, so runs repeat bit for bit. Steps, defaults and drift: docs/decisions/0099.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray
from pydantic import Field

from ..core import fmath
from ..core.geometry import Pose2D, normalize_angle
from ..core.messages import LaserScan, Odometry, Twist
from ..core.validation import StrictModel
from ..slam.karto.correlation_grid import CorrelationGrid, karto_round
from ..slam.karto.scan_matcher import MatcherParams, ScanMatcher
from ..slam.karto.scan_points import scan_points

__all__ = ["LaserOdometry", "LaserOdometryParams", "OdometryWithCovariance"]

F64 = NDArray[np.float64]

#: Fewer paired points than this: the refinement is not trusted (the correlative pose stays).
MIN_CORRESPONDENCES = 20
#: A refinement moving the correlative pose farther than this is a wrong pairing, not a fix.
MAX_REFINE_SHIFT = 0.05  # m
MAX_REFINE_TURN = 0.05  # rad
#: The residual (m) a paired point is trusted to: the refinement's final Cauchy scale.
RESIDUAL_SCALE = 0.02
#: Gauss-Newton stops when a step moves less than this (m, and rad): far below the noise.
REFINE_TOLERANCE = 1e-4
#: The covariance a coasting (unmatched) scan adds: a prediction from 0.1 s of old velocity.
COAST_VARIANCE = (0.01, 0.01, 0.003)


class LaserOdometryParams(StrictModel):
    """What the laser odometry may be tuned by (defaults in the module doc)."""

    keyframe_distance: float = Field(0.5, gt=0, le=10, description="m moved: new keyframe")
    keyframe_angle: float = Field(0.5, gt=0, le=math.pi, description="rad turned: new keyframe")
    search_space_dimension: float = Field(0.3, gt=0, le=4, description="search square side (m)")
    search_space_resolution: float = Field(0.02, gt=0, le=0.5, description="grid cell (m)")
    smear_deviation: float = Field(0.04, gt=0, le=1, description="reference smear (m)")
    coarse_search_angle_offset: float = Field(0.1745, gt=0, le=math.pi, description="rad")
    coarse_angle_resolution: float = Field(0.0349, gt=0, le=0.5, description="rad")
    fine_search_angle_offset: float = Field(0.00349, gt=0, le=0.5, description="rad")
    max_laser_range: float | None = Field(None, gt=0, description="m; default the scan's")
    minimum_response: float = Field(0.1, ge=0, le=1, description="below: coast on prediction")
    refine_iterations: int = Field(8, ge=0, le=50, description="Gauss-Newton steps; 0: none")
    #: how far (m, rad) a scan may stray from constant velocity: the refinement's prior
    motion_prior_distance: float = Field(0.01, gt=0, le=10)
    motion_prior_angle: float = Field(0.01, gt=0, le=10)
    refine_outlier_distance: float = Field(0.1, gt=0, le=2, description="m; farther: no pair")


@dataclass
class OdometryWithCovariance(Odometry):
    """nav_msgs/Odometry with its two covariances ((x, y, yaw), 3x3): the pose's, grown
    match by match, and the twist's, from the last match over dt^2."""

    pose_covariance: F64 = field(default_factory=lambda: np.zeros((3, 3)))
    twist_covariance: F64 = field(default_factory=lambda: np.zeros((3, 3)))


@dataclass
class _Keyframe:
    """A reference scan: its robot pose in odom, its end points, its beams for pairing."""

    pose: Pose2D
    points_odom: F64  # (M, 2) its surfaces sampled densely in odom, beam order
    laser: Pose2D  # the laser's pose in odom
    beams_xy: F64  # (B, 2) every beam's end point in the laser frame, NaN if invalid
    angle_min: float
    angle_increment: float
    wraps: bool  # a full circle: beam B-1 neighbours beam 0
    covariance: F64
    grid: CorrelationGrid  # the surfaces smeared, built once for all scans matched to it


class LaserOdometry:
    """Odometry from consecutive scans; feed it with `scan_received` (see the module doc)."""

    Params = LaserOdometryParams
    frame_id = "odom"
    child_frame_id = "base_footprint"

    def __init__(
        self,
        laser: Pose2D,
        params: LaserOdometryParams | dict | None = None,
        *,
        stamp: float = 0.0,
        publish: Callable[[Odometry], None] | None = None,
    ) -> None:
        """`laser` is the scanner's mount in base_footprint; `publish(odom)` is called
        with every new estimate (the runtime sets odom -> base_footprint there)."""
        if params is None:
            params = LaserOdometryParams()
        elif isinstance(params, dict):
            params = LaserOdometryParams.model_validate(params)
        self.params = params
        self._matcher_params(1.0)  # a bad combination (smear for the cell size) fails now
        self.laser = laser
        self.publish = publish
        self._matcher: ScanMatcher | None = None
        self._keyframe: _Keyframe | None = None
        self._stamp: float | None = None
        self._velocity = (0.0, 0.0, 0.0)  # robot-frame motion per second, last scan pair
        self._covariance = np.zeros((3, 3))
        #: the last match's response (0..1), and whether the refinement was used
        self.response = 0.0
        self.refined = False
        self.keyframes = 0
        self.last: OdometryWithCovariance = OdometryWithCovariance(stamp, Pose2D(), Twist())

    @property
    def pose(self) -> Pose2D:
        """The latest pose in `odom`."""
        return self.last.pose

    # -- scans -------------------------------------------------------------------------

    def scan_received(self, scan: LaserScan) -> OdometryWithCovariance:
        """Estimate the pose at `scan.stamp`, publish it and return it."""
        p = self.params
        max_range = scan.range_max if p.max_laser_range is None else p.max_laser_range
        points = scan_points(scan, self.laser, max_range)[0]
        prev = self.last.pose
        if self._keyframe is None or self._stamp is None:
            self._new_keyframe(scan, prev, max_range, self._covariance)
            return self._emit(scan.stamp, prev, Twist(), np.zeros((3, 3)))

        dt = scan.stamp - self._stamp
        vx, vy, vw = self._velocity
        guess = prev @ Pose2D(vx * dt, vy * dt, vw * dt)
        kf = self._keyframe
        pose, match_cov = self._match(points, guess, kf)
        if pose is None:  # nothing to match: coast on the prediction, start afresh
            pose = guess
            match_cov = np.diag(COAST_VARIANCE)
            cov = self._covariance + match_cov
            self._new_keyframe(scan, pose, max_range, cov)
        else:
            cov = _propagate(kf.covariance, kf.pose, pose, match_cov)
            rel = pose.relative_to(kf.pose)
            moved = math.sqrt(rel.x * rel.x + rel.y * rel.y)
            if moved >= p.keyframe_distance or abs(rel.yaw) >= p.keyframe_angle:
                self._new_keyframe(scan, pose, max_range, cov)
        self._covariance = cov

        delta = pose.relative_to(prev)
        twist = Twist()
        twist_cov = np.zeros((3, 3))
        if dt > 0.0:
            vx, vy, vw = delta.x / dt, delta.y / dt, delta.yaw / dt
            self._velocity = (vx, vy, vw)
            twist = Twist(linear_x=vx, linear_y=vy, angular_z=vw)
            twist_cov = match_cov / (dt * dt)
        return self._emit(scan.stamp, pose, twist, twist_cov)

    def _emit(
        self, stamp: float, pose: Pose2D, twist: Twist, twist_cov: F64
    ) -> OdometryWithCovariance:
        self._stamp = stamp
        self.last = OdometryWithCovariance(
            stamp, pose, twist, pose_covariance=self._covariance.copy(), twist_covariance=twist_cov
        )
        if self.publish is not None:
            self.publish(self.last)
        return self.last

    # -- keyframes ---------------------------------------------------------------------

    def _new_keyframe(self, scan: LaserScan, pose: Pose2D, max_range: float, cov: F64) -> None:
        p = self.params
        ranges = np.asarray(scan.ranges, dtype=float)
        top = min(scan.range_max, max_range)
        ok = np.isfinite(ranges) & (ranges >= scan.range_min) & (ranges <= top)
        r = np.where(ok, ranges, np.nan)
        s, c = fmath.sincos(scan.angles)
        beams = np.column_stack([r * c, r * s])
        inc = float(scan.angle_increment)
        wraps = inc * ranges.size >= 2.0 * math.pi - 0.5 * abs(inc)
        laser = pose @ self.laser
        dense = laser.transform_points(_surfaces(beams, wraps, inc, p.search_space_resolution))
        if self._matcher is None:
            self._matcher = ScanMatcher(self._matcher_params(max_range))
        # it serves every scan until the next keyframe: guesses up to a keyframe step
        # (and a search square) away, seeing up to max_range
        reach = max_range + p.keyframe_distance + p.search_space_dimension + 0.5
        centre = pose.as_array()
        self._keyframe = _Keyframe(
            pose=pose,
            points_odom=dense,
            laser=laser,
            beams_xy=beams,
            angle_min=float(scan.angle_min),
            angle_increment=inc,
            wraps=wraps,
            covariance=cov.copy(),
            grid=self._matcher.correlation_grid([(dense, centre)], centre, centre, reach),
        )
        self.keyframes += 1

    def _matcher_params(self, max_range: float) -> MatcherParams:
        p = self.params
        return MatcherParams(
            search_space_dimension=p.search_space_dimension,
            search_space_resolution=p.search_space_resolution,
            smear_deviation=p.smear_deviation,
            range_threshold=max_range,
            coarse_search_angle_offset=p.coarse_search_angle_offset,
            coarse_angle_resolution=p.coarse_angle_resolution,
            fine_search_angle_offset=p.fine_search_angle_offset,
        )

    # -- matching ----------------------------------------------------------------------

    def _match(self, points: F64, guess: Pose2D, kf: _Keyframe) -> tuple[Pose2D | None, F64]:
        """The scan's pose in odom and its covariance, or (None, _) when not trusted."""
        assert self._matcher is not None
        self.refined = False
        if len(points) == 0 or len(kf.points_odom) == 0:
            self.response = 0.0
            return None, np.zeros((3, 3))
        result = self._matcher.match(points, guess.as_array(), (), grid=kf.grid)
        self.response = float(result.response)
        if result.response < self.params.minimum_response:
            return None, result.covariance
        pose = Pose2D.from_array(result.pose)
        if self.params.refine_iterations > 0:
            refined = self._refine(points, pose, kf, guess)
            if refined is not None:
                pose = refined
                self.refined = True
        return pose, result.covariance

    def _refine(self, points: F64, start: Pose2D, kf: _Keyframe, guess: Pose2D) -> Pose2D | None:
        """Point-to-line Gauss-Newton from `start` (odom), in the keyframe laser's frame,
        with the prediction `guess` as a weak prior: rf2o likewise falls back on its last
        velocity along directions the scan does not constrain (a corridor's length)."""
        p = self.params
        rel = start.relative_to(kf.laser)  # the robot in the keyframe laser's frame
        prior = guess.relative_to(kf.laser)
        info = (
            (RESIDUAL_SCALE / p.motion_prior_distance) ** 2,
            (RESIDUAL_SCALE / p.motion_prior_angle) ** 2,
        )
        tx, ty, th = rel.x, rel.y, rel.yaw
        px, py = points[:, 0], points[:, 1]
        c_out = p.refine_outlier_distance
        for it in range(p.refine_iterations):
            s, c = fmath.sincos(th)
            qx = c * px - s * py + tx
            qy = s * px + c * py + ty
            pair = _pair_lines(qx, qy, kf, c_out)
            if pair is None:
                return None
            keep, nx, ny, r = pair
            if keep.sum() < MIN_CORRESPONDENCES:
                return None
            # Cauchy weights: a scale shrinking to 2 cm as the pairs settle
            scale = max(RESIDUAL_SCALE, c_out * 0.5 ** (it + 1))
            u = r / scale
            w = keep / (1.0 + u * u)
            jt = nx * (ty - qy) + ny * (qx - tx)  # d residual / d theta
            off = (tx - prior.x, ty - prior.y, normalize_angle(th - prior.yaw))
            step = _solve_normal(nx, ny, jt, r, w, off, info)
            if step is None:
                return None
            tx -= step[0]
            ty -= step[1]
            th -= step[2]
            if abs(step[0]) + abs(step[1]) < REFINE_TOLERANCE and abs(step[2]) < REFINE_TOLERANCE:
                break
        out = kf.laser @ Pose2D(tx, ty, th)
        dx, dy = out.x - start.x, out.y - start.y
        moved = math.sqrt(dx * dx + dy * dy)
        turned = abs(normalize_angle(out.yaw - start.yaw))
        if moved > MAX_REFINE_SHIFT or turned > MAX_REFINE_TURN:
            return None
        return out


def _surface_gap(x: F64, y: F64, angle_increment: float) -> F64:
    """The widest step between neighbouring beams' end points that is still one surface:
    a few beam spacings at that range (a wall at a grazing angle), else a depth edge."""
    return np.maximum(0.1, 5.0 * np.sqrt(x * x + y * y) * angle_increment)


def _surfaces(beams: F64, wraps: bool, angle_increment: float, spacing: float) -> F64:
    """The keyframe as the reference the matcher sees: its end points with every surface
    between neighbouring beams filled in at `spacing`, in beam order (laser frame).

    End points alone alias: down a corridor every scan samples the walls at the same
    beam angles, so a scan laid back at the keyframe's pose fits point on point and
    motion along the corridor reads as none. Surfaces, unlike samples, do not move
    with the robot."""
    b = beams.shape[0]
    nxt = np.roll(beams, -1, axis=0)
    ex, ey = nxt[:, 0] - beams[:, 0], nxt[:, 1] - beams[:, 1]
    length = np.sqrt(ex * ex + ey * ey)  # NaN where either end is invalid
    joined = length <= _surface_gap(beams[:, 0], beams[:, 1], angle_increment)
    if not wraps:
        joined[b - 1] = False
    valid = np.isfinite(beams[:, 0])
    count = np.where(joined, np.maximum(1, np.ceil(length / spacing)), 1).astype(np.int64)
    count[~valid] = 0
    owner = np.repeat(np.arange(b), count)
    step = np.arange(owner.size) - np.repeat(np.cumsum(count) - count, count)
    t = np.where(joined[owner], step / count[owner], 0.0)
    ex = np.where(joined, ex, 0.0)
    ey = np.where(joined, ey, 0.0)
    return np.column_stack([beams[owner, 0] + ex[owner] * t, beams[owner, 1] + ey[owner] * t])


def _pair_lines(
    qx: F64, qy: F64, kf: _Keyframe, max_distance: float
) -> tuple[F64, F64, F64, F64] | None:
    """Pair each point (keyframe laser frame) with a line of the keyframe scan: the beam it
    projects onto (or the nearest of that beam's two neighbours) and the nearer of its
    neighbours. Returns (mask, normal x, normal y, signed distance) per point."""
    beams = kf.beams_xy
    b = beams.shape[0]
    if b < 5 or kf.angle_increment <= 0.0:
        return None
    # the bearing past the first beam, in [0, 2 pi): beams past the last are none
    offset = np.mod(fmath.arctan2(qy, qx) - kf.angle_min, 2.0 * math.pi)
    idx = karto_round(offset / kf.angle_increment)
    # beams idx-2..idx+2 (rows): the nearest of the middle three, and its nearer neighbour
    j = idx[None, :] + np.arange(-2, 3)[:, None]
    if kf.wraps:
        j %= b
        x, y = beams[j, 0], beams[j, 1]
    else:
        outside = (j < 0) | (j >= b)
        j = np.clip(j, 0, b - 1)
        x, y = beams[j, 0], beams[j, 1]
        x[outside] = np.nan
    dx, dy = x - qx, y - qy
    d2 = dx * dx + dy * dy
    d2[np.isnan(d2)] = np.inf
    cols = np.arange(idx.size)
    near = d2[1:4].argmin(axis=0) + 1
    other = np.where(d2[near - 1, cols] <= d2[near + 1, cols], near - 1, near + 1)
    ax, ay = x[near, cols], y[near, cols]
    ex, ey = x[other, cols] - ax, y[other, cols] - ay
    length = np.sqrt(ex * ex + ey * ey)
    gap = _surface_gap(ax, ay, kf.angle_increment)
    keep = np.isfinite(length) & (length > 1e-9) & (length <= gap)
    keep &= d2[near, cols] <= 9.0 * max_distance * max_distance
    safe = np.where(keep, length, 1.0)
    nx = np.where(keep, -ey / safe, 0.0)
    ny = np.where(keep, ex / safe, 0.0)
    r = np.where(keep, nx * (qx - ax) + ny * (qy - ay), 0.0)
    keep &= np.abs(r) <= max_distance
    return keep.astype(float), nx, ny, np.where(keep, r, 0.0)


def _solve_normal(
    nx: F64,
    ny: F64,
    jt: F64,
    r: F64,
    w: F64,
    off: tuple[float, float, float],
    info: tuple[float, float],
) -> tuple[float, float, float] | None:
    """The Gauss-Newton step of sum w (r + J d)^2 + the prior's info |off + d|^2, with
    J = (nx, ny, jt): H summed term by term, solved by the adjugate (no LAPACK)."""
    wx, wy, wt = w * nx, w * ny, w * jt
    h00 = float((wx * nx).sum())
    h01 = float((wx * ny).sum())
    h02 = float((wx * jt).sum())
    h11 = float((wy * ny).sum())
    h12 = float((wy * jt).sum())
    h22 = float((wt * jt).sum())
    g0 = float((wx * r).sum())
    g1 = float((wy * r).sum())
    g2 = float((wt * r).sum())
    h00 += info[0]
    h11 += info[0]
    h22 += info[1]
    g0 += info[0] * off[0]
    g1 += info[0] * off[1]
    g2 += info[1] * off[2]
    c00 = h11 * h22 - h12 * h12
    c01 = h02 * h12 - h01 * h22
    c02 = h01 * h12 - h02 * h11
    det = h00 * c00 + h01 * c01 + h02 * c02
    if not (det > 0.0 and math.isfinite(det)):
        return None
    c11 = h00 * h22 - h02 * h02
    c12 = h01 * h02 - h00 * h12
    c22 = h00 * h11 - h01 * h01
    return (
        (c00 * g0 + c01 * g1 + c02 * g2) / det,
        (c01 * g0 + c11 * g1 + c12 * g2) / det,
        (c02 * g0 + c12 * g1 + c22 * g2) / det,
    )


def _propagate(kf_cov: F64, kf_pose: Pose2D, pose: Pose2D, match_cov: F64) -> F64:
    """The pose's covariance: the keyframe's carried over the lever arm from the keyframe
    to the pose (first order: a heading error at the keyframe moves the pose sideways),
    plus the match's. Explicit 3x3 products in Python floats (no BLAS)."""
    dx, dy = pose.x - kf_pose.x, pose.y - kf_pose.y
    j = ((1.0, 0.0, -dy), (0.0, 1.0, dx), (0.0, 0.0, 1.0))
    k = kf_cov.tolist()
    jk = [[sum(j[a][m] * k[m][b] for m in range(3)) for b in range(3)] for a in range(3)]
    out = [[sum(jk[a][m] * j[b][m] for m in range(3)) for b in range(3)] for a in range(3)]
    return np.array(out) + match_cov
