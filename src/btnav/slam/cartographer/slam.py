"""`cartographer`: Cartographer's 2D SLAM (local SLAM on submaps, global SLAM on a pose graph),
driven by the user's Cartographer `.lua`.

Local SLAM is Cartographer's LocalTrajectoryBuilder (predict, real-time correlative match,
Ceres refinement, motion filter, insert into submaps), with one departure: a poor
real-time match is searched again wider (`RESCUE_BELOW_SCORE`). Global SLAM is PoseGraph2D
(intra-submap constraints, fast correlative loop closures, Huber-weighted
Levenberg-Marquardt every `optimize_every_n_nodes`). btnav's graph holds nodes only: a
submap's frame is the pose of the node that started it. Odometry is read from the frame
tree and `map -> odom` published. In full: docs/decisions/0070.
"""

from __future__ import annotations

import dataclasses
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ...core.errors import BtnavWarning
from ...core.geometry import Pose2D, compose_arrays, normalize_angle, relative_arrays
from ...core.messages import LaserScan, PoseWithCovariance
from ...core.resources import bundled_dir
from ...localization.localizer import Localizer, LocalizerContext
from ...maps.occupancy_grid import OccupancyGrid
from ...plugins import register
from ..graph.pose_graph import PoseGraph, optimize_poses
from .config import load_cartographer_config
from .fast_correlative_matcher import FastCorrelativeScanMatcher, match_batch
from .matchers import adaptive_voxel_filter, ceres_match, real_time_correlative_match, voxel_filter
from .options import CartographerConfig, TrajectoryBuilder2D
from .options import PoseGraph as PoseGraphOptions
from .submaps import ActiveSubmaps, RangeData, Submap, assemble_map

F64 = NDArray[np.float64]
#: A known cell more likely free than not is free on the live map: cartographer_ros
#: publishes every known cell's probability (x100) and Nav2's static layer, trinary,
#: takes any known value below its lethal threshold as free. With map_saver's 0.25 a
#: young submap (misses at 0.49 each) would have no free cell at all.
LIVE_MAP_FREE = 0.5
#: cartographer_ros's occupancy_grid_node publishes /map this often (its -publish_period_sec).
MAP_PUBLISH_PERIOD = 1.0
#: Not Cartographer's: when the real-time correlative match around the odometry's
#: prediction scores below this (good ones 0.55-0.9), the prediction is searched again
#: `RESCUE_LINEAR_WINDOW` metres and `RESCUE_ANGULAR_WINDOW` radians wide, and that match
#: replaces it, as the Ceres refinement's translation target too, when it scores at least
#: `RESCUE_MARGIN` more. FR079's odometry counts reversing as forward travel: Cartographer's
#: prediction is then 2 x the step from the truth, beyond the 0.1 m window, and its Ceres
#: cost pulls the pose back to the prediction.
RESCUE_BELOW_SCORE = 0.55
RESCUE_MARGIN = 0.15
RESCUE_LINEAR_WINDOW = 1.0
RESCUE_ANGULAR_WINDOW = 0.1


def compose(a: F64, b: F64) -> F64:
    return compose_arrays(np.asarray(a, float), np.asarray(b, float)[None, :])[0]


def relative(a: F64, b: F64) -> F64:
    """b in a's frame."""
    return relative_arrays(np.asarray(a, float)[None, :], np.asarray(b, float)[None, :])[0]


def _information(translation_weight: float, rotation_weight: float) -> F64:
    """Cartographer's residuals are weight x error, so the information is weight^2."""
    return np.diag([translation_weight**2, translation_weight**2, rotation_weight**2])


def optimize_huber(
    poses: F64,
    i: NDArray[np.int64],
    j: NDArray[np.int64],
    z: F64,
    info: F64,
    loops: NDArray[np.int64],
    scale: float,
    max_iterations: int,
) -> F64:
    """Levenberg-Marquardt over the graph (node 0 fixed) with Huber's loss on the edges
    `loops`, as Ceres minimises Cartographer's problem: one solve (`optimize_poses`),
    each linearisation weighing a closure by rho' at its residual."""
    x, _ = optimize_poses(poses, i, j, z, info, max_iterations=max_iterations, huber=(loops, scale))  # fmt: skip
    return x


@dataclass
class Node:
    """Cartographer's TrajectoryNode: what global SLAM keeps of an inserted scan."""

    stamp: float
    odom_pose: F64  # tracking frame in the odom frame
    local_pose: F64  # in local SLAM's frame
    points: F64  # loop-closure filtered returns, tracking frame
    submaps: list[int] = field(default_factory=list)


@dataclass
class Insertion:
    node: Node
    submaps: list[Submap]
    finished: Submap | None


class LocalTrajectoryBuilder:
    """Cartographer's LocalTrajectoryBuilder2D (see the module doc). `start`: the local
    frame is the map frame as it stood when SLAM started (`start` = map -> odom)."""

    def __init__(self, options: TrajectoryBuilder2D, use_odometry: bool, start: F64) -> None:
        self.o = options
        s = options.submaps
        self.submaps = ActiveSubmaps(s.num_range_data, s.resolution, s.hit_probability, s.miss_probability)  # fmt: skip
        self.use_odometry = use_odometry
        self.start = np.asarray(start, float)
        self.poses: list[tuple[float, F64, F64]] = []  # (stamp, local pose, odom pose), last two
        self.accumulated: list[tuple[F64, RangeData]] = []  # (odom pose, range data)
        self.filter_total = 0
        self.rescued = 0  # predictions replaced by the wider search (RESCUE_BELOW_SCORE)
        self.last_inserted: tuple[float, F64] | None = None

    def predict(self, stamp: float, odom: F64) -> F64:
        if not self.poses:
            return compose(self.start, odom)
        t1, p1, o1 = self.poses[-1]
        if self.use_odometry:
            return compose(p1, relative(o1, odom))
        if len(self.poses) < 2 or t1 <= self.poses[-2][0]:
            return p1.copy()
        t0, p0, _ = self.poses[-2]  # constant velocity, as Cartographer's pose extrapolator
        d = relative(p0, p1) * ((stamp - t1) / (t1 - t0))
        return compose(p1, d)

    def add_range_data(
        self, stamp: float, odom: F64, data: RangeData
    ) -> tuple[F64, Insertion | None] | None:
        """One scan (tracking frame); its local pose and what was inserted, or None while
        range data accumulates (`num_accumulated_range_data`)."""
        o = self.o
        self.accumulated.append((odom, data))
        if len(self.accumulated) < o.num_accumulated_range_data:
            return None
        # a few scans: each moved into this scan's frame by odometry, one array transform each
        moved = [d.transformed(relative(odom, before) if self.use_odometry else np.zeros(3)) for before, d in self.accumulated]  # fmt: skip
        self.accumulated = []
        returns = voxel_filter(np.concatenate([d.returns for d in moved]), o.voxel_filter_size)
        misses = voxel_filter(np.concatenate([d.misses for d in moved]), o.voxel_filter_size)
        pose = self.predict(stamp, odom)
        submap = self.submaps.matching
        if submap is not None and len(returns):
            cloud = adaptive_voxel_filter(returns, o.adaptive_voxel_filter)
            initial, target = pose, pose[:2]
            if o.use_online_correlative_scan_matching:
                rt = o.real_time_correlative_scan_matcher
                initial, score = real_time_correlative_match(submap, cloud, pose, rt)
                if score < RESCUE_BELOW_SCORE:  # not Cartographer's: see RESCUE_BELOW_SCORE
                    wide = dataclasses.replace(rt, linear_search_window=RESCUE_LINEAR_WINDOW, angular_search_window=RESCUE_ANGULAR_WINDOW)  # fmt: skip
                    found, better = real_time_correlative_match(submap, cloud, pose, wide)
                    if better >= score + RESCUE_MARGIN:
                        initial, target = found, found[:2]
                        self.rescued += 1
            pose = ceres_match(submap, cloud, target, initial, o.ceres_scan_matcher)
            pose[2] = normalize_angle(float(pose[2]))
        self.poses = [*self.poses[-1:], (stamp, pose, np.asarray(odom, float))]
        if self._similar(stamp, pose):
            return pose, None
        targets, finished = self.submaps.insert(RangeData(data.origin, returns, misses).transformed(pose), pose)  # fmt: skip
        cloud = adaptive_voxel_filter(returns, o.loop_closure_adaptive_voxel_filter)
        node = Node(stamp, np.asarray(odom, float), pose, cloud, [s.index for s in targets])
        return pose, Insertion(node, targets, finished)

    def _similar(self, stamp: float, pose: F64) -> bool:
        """Cartographer's MotionFilter: too soon, too near and too little turned to insert."""
        m = self.o.motion_filter
        self.filter_total += 1
        last = self.last_inserted
        if self.filter_total > 1 and last is not None and stamp - last[0] <= m.max_time_seconds:
            d = relative(last[1], pose)
            near = d[0] ** 2 + d[1] ** 2 <= m.max_distance_meters**2
            if near and abs(d[2]) <= m.max_angle_radians:
                return True
        self.last_inserted = (stamp, pose.copy())
        return False


class CartographerMapper:
    """Global SLAM over the nodes local SLAM inserts (see the module doc); `poses`,
    `scans`, `graph` and `loop_closures` read as Karto's Mapper's do."""

    def __init__(self, options: PoseGraphOptions, use_odometry: bool, submaps: list[Submap]):
        self.o = options
        self.use_odometry = use_odometry
        self.submaps = submaps
        self.graph = PoseGraph()
        self.scans: list[Node] = []
        self.anchors: dict[int, int] = {}  # submap -> the node that started it
        self.matchers: dict[int, FastCorrelativeScanMatcher] = {}
        self.samplers: dict[int, list[int]] = {}  # submap -> [pulses, samples]
        self.loop_edges: list[int] = []
        self.loop_closures = 0
        self.local_to_global = np.zeros(3)
        self.since_optimization = 0
        self.revision = 0  # bumped when optimisation moves nodes

    @property
    def poses(self) -> F64:
        """(K, 3) node poses in the map frame."""
        return self.graph.poses

    def submap_pose(self, index: int) -> F64:
        """A submap's global pose: its first node's (a submap's frame is that node's pose)."""
        return self.graph.poses[self.anchors[index]]

    def add_node(self, ins: Insertion) -> int:
        node = ins.node
        o, opt = self.o, self.o.optimization_problem
        n = self.graph.add_node(compose(self.local_to_global, node.local_pose))
        self.scans.append(node)
        if n > 0:
            prev = self.scans[n - 1]
            local = _information(opt.local_slam_pose_translation_weight, opt.local_slam_pose_rotation_weight)  # fmt: skip
            self.graph.add_edge(n - 1, n, relative(prev.local_pose, node.local_pose), information=local)  # fmt: skip
            if self.use_odometry:
                odom = _information(opt.odometry_translation_weight, opt.odometry_rotation_weight)
                self.graph.add_edge(n - 1, n, relative(prev.odom_pose, node.odom_pose), information=odom)  # fmt: skip
        for s in ins.submaps:
            s.node_ids.append(n)
            a = self.anchors.setdefault(s.index, n)
            if a != n:
                rel = relative(self.scans[a].local_pose, node.local_pose)
                self.graph.add_edge(a, n, rel, information=_information(o.matcher_translation_weight, o.matcher_rotation_weight))  # fmt: skip
        finished = [i for i in sorted(self.matchers) if i not in node.submaps]
        if finished:  # the node against every finished submap near it: one array pass
            anchors = self.graph.poses[[self.anchors[i] for i in finished]]
            rel = relative_arrays(anchors, np.broadcast_to(self.graph.poses[n], anchors.shape))
            self._add_constraints([(n, finished[k], rel[k]) for k in self._within(rel)])
        if ins.finished is not None:
            index = ins.finished.index
            self.matchers[index] = FastCorrelativeScanMatcher(ins.finished, o.constraint_builder.fast_correlative_scan_matcher.branch_and_bound_depth)  # fmt: skip
            inside = set(ins.finished.node_ids)
            rel = relative_arrays(self.submap_pose(index)[None, :], self.graph.poses)
            self._add_constraints([(m, index, rel[m]) for m in self._within(rel) if m not in inside])  # fmt: skip
        self.since_optimization += 1
        if o.optimize_every_n_nodes > 0 and self.since_optimization >= o.optimize_every_n_nodes:
            self.optimize()
        return n

    def _within(self, rel: F64) -> list[int]:
        """Rows of node-in-submap poses within max_constraint_distance, in order."""
        d2 = rel[:, 0] ** 2 + rel[:, 1] ** 2
        return np.flatnonzero(d2 <= self.o.constraint_builder.max_constraint_distance**2).tolist()

    def _add_constraints(self, pairs: list[tuple[int, int, F64]]) -> None:
        """Cartographer's ConstraintBuilder2D::MaybeAddConstraint for each (node, finished
        submap, the node in the submap's frame within max_constraint_distance), in turn:
        the submap's sampler, then the fast correlative search (all of them together:
        `match_batch`; the poses they start from hold until the next optimisation), the
        Ceres refinement and the loop closure, in the same order."""
        cb = self.o.constraint_builder
        fast = cb.fast_correlative_scan_matcher
        searched = []
        for n, index, rel in pairs:
            sampler = self.samplers.setdefault(index, [0, 0])
            sampler[0] += 1
            if sampler[1] / sampler[0] >= cb.sampling_ratio:  # Cartographer's FixedRatioSampler
                continue
            sampler[1] += 1
            initial = compose(self.submaps[index].local_pose, rel)
            searched.append((n, index, initial))
        queries = [(self.matchers[index], self.scans[n].points, initial) for n, index, initial in searched]  # fmt: skip
        found = match_batch(queries, fast.linear_search_window, fast.angular_search_window, cb.min_score)  # fmt: skip
        info = _information(cb.loop_closure_translation_weight, cb.loop_closure_rotation_weight)
        for (n, index, _), f in zip(searched, found, strict=True):
            if f is None:
                continue
            pose = ceres_match(self.submaps[index], self.scans[n].points, f[0][:2], f[0], cb.ceres_scan_matcher)  # fmt: skip
            a = self.anchors[index]
            self.loop_edges.append(self.graph.add_edge(a, n, relative(self.scans[a].local_pose, pose), information=info))  # fmt: skip
            self.loop_closures += 1

    def optimize(self, max_iterations: int | None = None) -> None:
        """Solve the graph (node 0 fixed), Huber's loss on the loop closures (see
        `optimize_huber`)."""
        opt = self.o.optimization_problem
        iterations = opt.max_num_iterations if max_iterations is None else max_iterations
        self.since_optimization = 0
        if self.graph.num_nodes < 2:
            return
        i, j, z, info = self.graph.edges
        loops = np.array(self.loop_edges, dtype=np.int64)
        poses = optimize_huber(self.graph.poses, i, j, z, info, loops, opt.huber_scale, iterations)  # fmt: skip
        self.graph.set_poses(poses)
        newest = self.submaps[max(self.anchors)]
        self.local_to_global = compose(self.submap_pose(newest.index), relative(newest.local_pose, np.zeros(3)))  # fmt: skip
        self.revision += 1

    def run_final_optimization(self) -> None:
        """What FinishTrajectory does: one last optimisation with max_num_final_iterations."""
        self.optimize(self.o.max_num_final_iterations)


def _config(params: Any) -> CartographerConfig:
    if isinstance(params, CartographerConfig):
        return params
    if params is None:
        params = bundled_dir("params") / "cartographer_2d.lua"
    if isinstance(params, str | Path):
        return load_cartographer_config(params)
    raise TypeError(f"cartographer takes a CartographerConfig or a .lua path, got {params!r}")


@register("slam", "cartographer", aliases=["cartographer_ros"])
class CartographerSlam(Localizer):
    """Maps while the robot drives, as cartographer_node does (see the module doc)."""

    rate = 20.0  # how often the latest scan is looked at; a 10 Hz lidar is never missed

    def __init__(self, name: str = "cartographer", params: Any = None) -> None:
        self.name = name
        self.params = self.config = _config(params)

    def configure(self, context: LocalizerContext) -> None:  # type: ignore[override]
        super().configure(context)
        c = self.config
        f = c.frames
        frames = context.frames
        for key in ("map_frame", "tracking_frame", "published_frame"):
            frames.require(getattr(f, key), key=key)
        c.warn_ignored(stacklevel=2)
        # btnav's wheel odometry owns odom -> base: the map frame's child on the way to the
        # tracking frame is what SLAM publishes (Cartographer's published_frame)
        child = f.tracking_frame
        while frames.parent(child) not in (f.map_frame, None):
            child = frames.parent(child)
        self.published_frame = child
        if f.provide_odom_frame or child != f.published_frame:
            warnings.warn(BtnavWarning(f"btnav keeps the wheel odometry's '{child}' frame and publishes {f.map_frame} -> {child}", file=c.file, key="provide_odom_frame" if f.provide_odom_frame else "published_frame"), stacklevel=2)  # fmt: skip
        anchor = frames.lookup(f.map_frame, child).as_array()
        tb = c.trajectory_builder_2d
        self.local = LocalTrajectoryBuilder(tb, f.use_odometry, anchor)
        self.mapper = CartographerMapper(c.pose_graph, f.use_odometry, self.local.submaps.submaps)
        self.map_to_odom = Pose2D.from_array(anchor)
        self.pose = PoseWithCovariance(context.clock.now, frames.lookup(f.map_frame, f.tracking_frame), frame_id=f.map_frame)  # fmt: skip
        self._last_scan: LaserScan | None = None
        self._subscribers: list[Callable[[OccupancyGrid], None]] = []
        self._map: OccupancyGrid | None = None
        self._map_key: tuple[int, int] | None = None
        self._last_publish: float | None = None

    # -- topics ------------------------------------------------------------------------------

    def subscribe_map(self, callback: Callable[[OccupancyGrid], None]) -> None:
        """`callback(map)` on every published map (and now, if one exists): `/map`, latched."""
        self._subscribers.append(callback)
        if self.mapper.scans:
            callback(self.map)

    def update(self, now: float) -> PoseWithCovariance:
        scan = self.context.latest_scan
        if scan is not None and scan is not self._last_scan:
            self._last_scan = scan
            self.laser_received(scan)
        due = self._last_publish is None or now - self._last_publish >= MAP_PUBLISH_PERIOD
        if self._subscribers and self.mapper.scans and due and self._map_key != self._key():
            self._last_publish = now
            grid = self.map
            for callback in self._subscribers:
                callback(grid)
        return self.pose

    def laser_received(self, scan: LaserScan) -> bool:
        """One scan through local SLAM; True when it became a node."""
        f, tb = self.config.frames, self.config.trajectory_builder_2d
        frames = self.context.frames
        odom_t = frames.lookup(self.published_frame, f.tracking_frame)
        laser = frames.lookup(f.tracking_frame, scan.frame_id).as_array()
        data = RangeData.from_scan(scan, laser, tb.min_range, tb.max_range, tb.missing_data_ray_length)  # fmt: skip
        odom = odom_t.as_array()
        out = self.local.add_range_data(scan.stamp, odom, data)
        if out is None:
            return False
        pose, insertion = out
        if insertion is not None:
            self.mapper.add_node(insertion)
        estimate = Pose2D.from_array(compose(self.mapper.local_to_global, pose))
        self.map_to_odom = estimate @ odom_t.inverse()
        frames.set_transform(f.map_frame, self.published_frame, self.map_to_odom, scan.stamp)
        self.pose = PoseWithCovariance(scan.stamp, estimate, frame_id=f.map_frame)
        return insertion is not None

    # -- the map -----------------------------------------------------------------------------

    def _key(self) -> tuple[int, int]:
        return self.mapper.revision, len(self.mapper.scans)

    @property
    def map(self) -> OccupancyGrid | None:
        """Every submap at its global pose (cartographer_ros's occupancy grid), built when asked."""
        if not self.mapper.scans:
            return None
        if self._map is None or self._map_key != self._key():
            self._map = global_map(
                self.local.submaps.submaps, self.mapper, self.config.frames.map_frame, LIVE_MAP_FREE
            )
            self._map_key = self._key()
        return self._map


def global_map(
    submaps: list[Submap], mapper: CartographerMapper, frame_id: str, free: float = 0.25
) -> OccupancyGrid:
    """Every submap the graph holds at its optimised pose (cartographer_ros's /map); `free`
    0.25 is map_saver's threshold, the live map uses `LIVE_MAP_FREE`."""
    subs = [s for s in submaps if s.index in mapper.anchors]
    poses = np.array([mapper.submap_pose(s.index) for s in subs])
    return assemble_map(subs, poses, mapper.poses[0], frame_id, free=free)
