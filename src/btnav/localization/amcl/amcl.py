"""The `amcl` localiser: nav2_amcl's AmclNode on btnav's runtime.

Built as `Amcl(name, params)` with Nav2's `amcl:` section (`params.localization.
AmclParams`), then `configure(context)` hands it the runtime; the map comes from map_server through `set_map(grid)` (the latched `map`
topic: with `first_map_only` only the first is taken). On each new scan (`update`
runs every physics step and acts when the lidar has published), as laserReceived:

1. the first scan after an initial pose (or global localisation) always updates the
   filter, without motion; after that, only once odometry has moved more than
   `update_min_d` in x or y or turned more than `update_min_a` since the last update
   (or `request_nomotion_update()` asked for one), and then the particles are first
   moved by the motion model;
2. the laser model weighs the particles, and every `resample_interval`-th update
   resamples them;
3. after a resampling (or the first update) the heaviest cluster's mean is the pose,
   published with the whole set's covariance as `pose`, and map -> odom is set so that
   map -> base_footprint is that pose at the scan's odometry (unless `tf_broadcast` is
   false). Until an initial pose is known (`set_initial_pose`, the `initial_pose`
   params with `set_initial_pose: true`, or global localisation) nothing is published.

`reinitialize_global_localization()` spreads the particles uniformly over the free
cells (every other row and column with `freespace_downsampling`). `reset()` is a
lifecycle reset: the filter restarts at the last published pose, or waits for a new
initial pose with `always_reset_initial_pose`. Randomness: the `amcl` stream of
`random_seed` (-1: the mission seed).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ...core.geometry import Pose2D, angle_diff
from ...core.messages import LaserScan, PoseWithCovariance
from ...core.rng import stream
from ...maps.occupancy_grid import OccupancyGrid
from ...params.localization import AmclParams
from ...plugins import register
from ..localizer import Localizer, LocalizerContext
from .laser_models import LASER_MODELS, LaserData, LaserModel
from .likelihood_field import MapField
from .motion_models import MotionModel, make_motion_model
from .particle_filter import ParticleFilter

F64 = NDArray[np.float64]

#: nav2_amcl's spread round the initial pose when none was given: 0.5 m, 0.5 m, pi/12.
DEFAULT_INIT_COV = np.diag([0.5 * 0.5, 0.5 * 0.5, (math.pi / 12.0) ** 2])


def _cov3(covariance: Any) -> F64:
    """A 3x3 (x, y, yaw) covariance from a 3x3 array or ROS's 6x6 / 36-vector."""
    if covariance is None:
        return np.zeros((3, 3))
    c = np.asarray(covariance, float)
    if c.size == 36:
        c6 = c.reshape(6, 6)
        out = np.zeros((3, 3))
        out[:2, :2] = c6[:2, :2]
        out[2, 2] = c6[5, 5]
        return out
    return c.reshape(3, 3).copy()


@register("localizer", "amcl", aliases=("nav2_amcl::AmclNode", "nav2_amcl/AmclNode"))
class Amcl(Localizer):
    """Adaptive Monte Carlo localisation on a known map (see the module doc)."""

    Params = AmclParams

    def __init__(self, name: str = "amcl", params: Any = None) -> None:
        super().__init__(name, params)

    def configure(self, context: LocalizerContext) -> None:  # type: ignore[override]
        super().configure(context)
        p = self.params
        frames = context.frames
        for key in ("global_frame_id", "odom_frame_id", "base_frame_id"):
            frames.require(getattr(p, key), key=f"amcl.{key}")
        # Scan-driven: look for a new scan every physics step (no scan, no work).
        self.rate = 1.0 / float(getattr(context, "physics_dt", 0.01))
        seed = p.random_seed if p.random_seed >= 0 else context.seed
        self.rng = stream(seed, "amcl")
        self.motion_model: MotionModel = make_motion_model(
            p.robot_model_type, (p.alpha1, p.alpha2, p.alpha3, p.alpha4, p.alpha5)
        )
        self.laser_model: LaserModel = LASER_MODELS[p.laser_model_type](
            z_hit=p.z_hit,
            z_rand=p.z_rand,
            sigma_hit=p.sigma_hit,
            max_beams=p.max_beams,
            z_short=p.z_short,
            z_max=p.z_max,
            lambda_short=p.lambda_short,
            do_beamskip=p.do_beamskip,
            beam_skip_distance=p.beam_skip_distance,
            beam_skip_threshold=p.beam_skip_threshold,
            beam_skip_error_threshold=p.beam_skip_error_threshold,
        )
        self.pf = ParticleFilter(
            p.min_particles,
            p.max_particles,
            p.recovery_alpha_slow,
            p.recovery_alpha_fast,
            p.pf_err,
            p.pf_z,
            self.rng,
        )
        self.field: MapField | None = None
        self._free_xy: F64 | None = None
        self.first_map_received = False
        self.initial_pose_is_known = False
        self.first_pose_sent = False
        self.force_update = False
        self._pf_init = False  # nav2_amcl's pf_init_: the filter has its odometry reference
        self._pf_odom_pose = (0.0, 0.0, 0.0)
        self._resample_count = 0
        self._last_scan: LaserScan | None = None
        #: map -> odom as last computed (nav2_amcl's latest_tf_), None before the first pose.
        self.map_to_odom: Pose2D | None = None
        #: Filter updates and resamplings so far (for tests and benches).
        self.updates = 0
        self.resamples = 0
        self.pose = PoseWithCovariance(
            context.clock.now, Pose2D(), DEFAULT_INIT_COV.copy(), frame_id=p.global_frame_id
        )
        self.last_published_pose = self.pose
        self.pf.init_gaussian((0.0, 0.0, 0.0), DEFAULT_INIT_COV)
        if p.set_initial_pose:
            ip = p.initial_pose
            self.set_initial_pose(Pose2D(ip.x, ip.y, ip.yaw))

    # -- inputs ---------------------------------------------------------------------------

    def set_map(self, grid: OccupancyGrid) -> None:
        """A map from map_server (nav2_amcl's mapReceived)."""
        if self.params.first_map_only and self.first_map_received:
            return
        self.field = MapField(grid, self.params.laser_likelihood_max_dist)
        step = 2 if self.params.freespace_downsampling else 1
        self._free_xy = self.field.free_cell_centres(step)
        self.first_map_received = True

    def set_initial_pose(self, pose: Pose2D | PoseWithCovariance, covariance: Any = None) -> None:
        """nav2_amcl's initialpose: the particles from N(pose, covariance) (zeros, as
        nav2_simple_commander sends, put them all on the pose); the next scan updates."""
        if isinstance(pose, PoseWithCovariance):
            covariance = pose.covariance if covariance is None else covariance
            pose = pose.pose
        cov = _cov3(covariance)
        now = self.context.clock.now
        self.last_published_pose = PoseWithCovariance(
            now, pose, cov, frame_id=self.params.global_frame_id
        )
        self.pf.init_gaussian((pose.x, pose.y, pose.yaw), cov)
        self._pf_init = False
        self.initial_pose_is_known = True

    def reinitialize_global_localization(self) -> None:
        """nav2_amcl's reinitialize_global_localization service: a uniform cloud over the
        map's free cells; the next scan updates."""
        self.pf.init_model(self.uniform_poses)
        self.initial_pose_is_known = True
        self._pf_init = False

    def request_nomotion_update(self) -> None:
        """nav2_amcl's request_nomotion_update service: the next scan updates the filter."""
        self.force_update = True

    def reset(self) -> None:
        """A lifecycle reset (cleanup, configure, activate): a fresh filter at the last
        published pose with its covariance; with `always_reset_initial_pose`, no pose
        until a new initial pose is given (or, with `set_initial_pose`, the last pose,
        which Nav2 writes into `initial_pose` on cleanup)."""
        last = self.last_published_pose
        self.pf.init_gaussian((last.pose.x, last.pose.y, last.pose.yaw), last.covariance)
        self._pf_init = False
        self._resample_count = 0
        self.first_pose_sent = False
        if self.params.always_reset_initial_pose:
            self.initial_pose_is_known = False
            if self.params.set_initial_pose:  # Nav2 stored the last pose in initial_pose.*
                self.set_initial_pose(last.pose)

    def uniform_poses(self, n: int) -> F64:
        """n poses at free cells' centres, any heading (nav2_amcl's uniformPoseGenerator)."""
        free = self._free_xy
        if free is None or not len(free):
            raise RuntimeError("amcl: no free cell in the map to spread particles over")
        out = np.empty((n, 3))
        out[:, :2] = free[self.rng.integers(0, len(free), size=n)]
        out[:, 2] = self.rng.random(n) * (2.0 * math.pi) - math.pi
        return out

    # -- the scan loop --------------------------------------------------------------------

    def update(self, now: float) -> PoseWithCovariance:
        scan = self.context.latest_scan
        if scan is not None and scan is not self._last_scan:
            self._last_scan = scan
            self.laser_received(scan)
        return self.pose

    def laser_received(self, scan: LaserScan) -> None:
        """One scan (nav2_amcl's laserReceived)."""
        if self.field is None:
            return
        p = self.params
        frames = self.context.frames
        odom = frames.lookup(p.odom_frame_id, p.base_frame_id)
        pose = (odom.x, odom.y, odom.yaw)
        force_publication = False
        update = False
        if not self._pf_init:
            self._pf_odom_pose = pose
            self._pf_init = True
            update = True
            force_publication = True
            self._resample_count = 0
        else:
            ox, oy, oyaw = self._pf_odom_pose
            delta = (pose[0] - ox, pose[1] - oy, angle_diff(pose[2], oyaw))
            update = (
                abs(delta[0]) > p.update_min_d
                or abs(delta[1]) > p.update_min_d
                or abs(delta[2]) > p.update_min_a
                or self.force_update
            )
            if update:
                self.pf.poses = self.motion_model.odometry_update(
                    self.pf.poses, pose, delta, self.rng
                )
            self.force_update = False
        resampled = False
        if update:
            self._update_filter(scan, pose)
            self._resample_count += 1
            if self._resample_count % p.resample_interval == 0:
                self.pf.resample(self.uniform_poses)
                self.resamples += 1
                resampled = True
        if resampled or force_publication or not self.first_pose_sent:
            self._publish(scan.stamp, odom)
        elif self.map_to_odom is not None and p.tf_broadcast and self.initial_pose_is_known:
            frames.set_transform(p.global_frame_id, p.odom_frame_id, self.map_to_odom, scan.stamp)

    def _update_filter(self, scan: LaserScan, pose: tuple[float, float, float]) -> None:
        p = self.params
        if not scan.range_max > 0.0:
            return  # a malformed scan: nav2_amcl ignores it
        laser = self.context.frames.lookup(p.base_frame_id, scan.frame_id)
        data = LaserData.from_scan(
            scan, (laser.x, laser.y, laser.yaw), p.laser_min_range, p.laser_max_range
        )
        assert self.field is not None
        factors = self.laser_model.sensor_function(
            self.field, self.pf.poses, data, self.pf.converged, self.pf.sincos
        )
        self.pf.update_sensor(factors)
        self._pf_odom_pose = pose
        self.updates += 1

    def _publish(self, stamp: float, odom_t_base: Pose2D) -> None:
        best = self.pf.best_cluster()
        if best is None or not self.initial_pose_is_known:
            return
        p = self.params
        estimate = Pose2D(*best.mean)
        cov = np.zeros((3, 3))
        cov[:2, :2] = self.pf.cov[:2, :2]
        cov[2, 2] = self.pf.cov[2, 2]
        if not np.isfinite(cov).all():
            return  # nav2_amcl: "AMCL covariance or pose is NaN"
        self.pose = PoseWithCovariance(stamp, estimate, cov, frame_id=p.global_frame_id)
        self.last_published_pose = self.pose
        self.first_pose_sent = True
        self.map_to_odom = estimate @ odom_t_base.inverse()
        if p.tf_broadcast:
            self.context.frames.set_transform(
                p.global_frame_id, p.odom_frame_id, self.map_to_odom, stamp
            )

    # -- views ----------------------------------------------------------------------------

    @property
    def particles(self) -> tuple[F64, F64]:
        """The particle cloud: (N, 3) poses in the map frame and their (N,) weights."""
        return self.pf.poses.copy(), self.pf.weights.copy()
