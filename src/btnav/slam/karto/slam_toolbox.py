"""`slam_toolbox` (`localization: slam`): slam_toolbox's online asynchronous mapping, driven
by Nav2's `slam_toolbox:` section.

Every scan passes slam_toolbox's gate (`ScanGate`) and Karto's, then `map -> odom` is set
so that `map -> base_footprint` is the scan's corrected pose; the map is published on
`map_update_interval`, as slam_toolbox's latched `/map`. `mode: localization` tracks the
robot on a loaded pose graph (`GraphLocalizer`); `mode: mapping` with `map_file_name`
continues mapping from it (`ContinuedMapper`). Without a `slam_toolbox:` section, slam_toolbox's
own mapper_params_online_async.yaml applies (bundled in params/). Details: docs/decisions/0055.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from os import PathLike
from pathlib import Path
from typing import Any

import numpy as np

from ...core.errors import BtnavWarning, ParamsError
from ...core.geometry import Pose2D
from ...core.messages import LaserScan, PoseWithCovariance
from ...core.resources import bundled_dir
from ...localization.localizer import Localizer, LocalizerContext
from ...maps.occupancy_grid import OccupancyGrid
from ...params.check import ParamsCheck
from ...params.loader import load_params
from ...params.localization import SlamToolboxParams
from ...params.paramsfile import ParamsFile
from ...plugins import register
from .continued_mapper import ContinuedMapper
from .graph_io import graph_file, load_pose_graph, save_pose_graph
from .graph_localizer import GraphLocalizer
from .mapper import Mapper
from .occupancy_mapper import OccupancyMapper
from .scan_gate import ScanGate
from .scan_points import scan_points

#: slam_toolbox's own params file, bundled in params/ (see the module doc).
DEFAULT_PARAMS_FILE = "mapper_params_online_async.yaml"


#: How the warning about keys btnav does not act on starts (the Cartographer plugin's words).
IGNORED_WARNING = "btnav does not implement these slam_toolbox keys and runs without them: "


def default_slam_params() -> SlamToolboxParams:
    return load_params(bundled_dir("params") / DEFAULT_PARAMS_FILE).server("slam_toolbox").model


def warn_ignored(params: ParamsFile, stacklevel: int = 2) -> None:
    """One warning listing the `slam_toolbox:` keys `params` sets that btnav does not act
    on, each as `btnav params check` lists it (line, key, reason): none is dropped silently."""
    entries = [e for e in ParamsCheck(params).ignored if e.key.split(".", 1)[0] == "slam_toolbox"]
    if entries:
        listed = "; ".join(str(e) for e in entries)
        warnings.warn(BtnavWarning(IGNORED_WARNING + listed, file=params.path), stacklevel=stacklevel + 1)  # fmt: skip


@register("slam", "slam_toolbox", aliases=["slam", "slam_toolbox::AsyncSlamToolbox"])
class SlamToolbox(Localizer):
    """Maps while the robot drives and localises it on that map (see the module doc)."""

    Params = SlamToolboxParams
    rate = 20.0  # how often the latest scan is looked at; a 10 Hz lidar is never missed

    def __init__(self, name: str = "slam_toolbox", params: Any = None) -> None:
        super().__init__(name, params)

    def configure(self, context: LocalizerContext) -> None:  # type: ignore[override]
        super().configure(context)
        p = self.params
        frames = context.frames
        for key in ("map_frame", "odom_frame", "base_frame"):
            frames.require(getattr(p, key), key=f"slam_toolbox.{key}")
        if p.map_start_pose is not None:
            anchor = np.asarray(p.map_start_pose, float)
        else:
            anchor = frames.lookup(p.map_frame, p.odom_frame).as_array()
        self.occupancy = OccupancyMapper(p.resolution, p.max_laser_range)
        self._map_revision = 0
        #: `mode: localization`: the robot is tracked on a loaded graph that never changes.
        self.localizer: GraphLocalizer | None = None
        #: A continued map: where the session's first scan goes, until it has gone; then
        #: the session's odom frame in the graph's (slam_toolbox's reprocessing transform).
        self._continue_at: np.ndarray | None = None
        self._odom_in_graph: Pose2D | None = None
        if p.mode == "localization":
            if not p.map_file_name:
                raise ParamsError(
                    "mode: localization needs the pose graph to localise on",
                    key="slam_toolbox.map_file_name",
                )
            self.mapper = load_pose_graph(graph_file(p.map_file_name), p)
            self.localizer = GraphLocalizer(self.mapper, anchor)
        elif p.map_file_name:
            self.mapper = load_pose_graph(
                graph_file(p.map_file_name), p, into=ContinuedMapper(p, anchor)
            )
            self._continue_at = anchor
            self._map_revision = -1  # drawn at once, or with the first new scan
        else:
            self.mapper = Mapper(p, anchor)
        self._map_subscribers: list[Callable[[OccupancyGrid], None]] = []
        self._last_scan: LaserScan | None = None
        self.gate = ScanGate(p)
        self._last_map_time: float | None = None
        self._dirty = False
        self.map: OccupancyGrid | None = None
        self.map_to_odom = Pose2D.from_array(anchor)
        self.pose = PoseWithCovariance(
            context.clock.now, frames.lookup(p.map_frame, p.base_frame), frame_id=p.map_frame
        )
        if self.mapper.scans and context.latest_scan is not None:
            self._publish_loaded(context.latest_scan)

    def _publish_loaded(self, scan: LaserScan) -> None:
        """A loaded graph's map, published as it is loaded (slam_toolbox does so on
        deserialising): a goal beyond the lidar's reach on that map is on the map at once."""
        p = self.params
        self._laser = self.context.frames.lookup(p.base_frame, scan.frame_id).as_array()
        self._rebuild()
        self.publish_map(scan.stamp)

    # -- topics ------------------------------------------------------------------------------

    def subscribe_map(self, callback: Callable[[OccupancyGrid], None]) -> None:
        """`callback(map)` on every published map (and now, if one exists): `/map`, latched."""
        self._map_subscribers.append(callback)
        if self.map is not None:
            callback(self.map)

    def update(self, now: float) -> PoseWithCovariance:
        scan = self.context.latest_scan
        if scan is not None and scan is not self._last_scan:
            self._last_scan = scan
            self.laser_received(scan)
        due = (
            self._last_map_time is None
            or now - self._last_map_time >= self.params.map_update_interval
        )
        if self._dirty and due:
            self.publish_map(now)
        return self.pose

    # -- scans -------------------------------------------------------------------------------

    def laser_received(self, scan: LaserScan) -> bool:
        """One scan; True when the mapper took it."""
        p = self.params
        frames = self.context.frames
        odom_t_base = frames.lookup(p.odom_frame, p.base_frame)
        odom = odom_t_base.as_array()
        if not self.gate(scan.stamp, odom):
            return False
        laser = frames.lookup(p.base_frame, scan.frame_id)
        self._laser = laser.as_array()
        points, ranges, angles = scan_points(scan, laser, p.max_laser_range)
        if self.localizer is not None:
            if self.map is None:  # the loaded graph's map, once
                self._rebuild()
                self.publish_map(scan.stamp)
            estimate = Pose2D.from_array(self.localizer.process(odom, points))
        else:
            if not self._map_scan(scan.stamp, odom_t_base, points, ranges, angles):
                return False
            node = len(self.mapper.scans) - 1
            if self.mapper.revision != self._map_revision:
                self._rebuild()
            else:
                self.occupancy.add_scan(self.mapper.poses[node], ranges, angles, self._laser)
            self._dirty = True
            if self.map is None:
                self.publish_map(scan.stamp)
            estimate = Pose2D.from_array(self.mapper.poses[node])
        self.map_to_odom = estimate @ odom_t_base.inverse()
        frames.set_transform(p.map_frame, p.odom_frame, self.map_to_odom, scan.stamp)
        self.pose = PoseWithCovariance(scan.stamp, estimate, frame_id=p.map_frame)
        return True

    def _map_scan(
        self,
        stamp: float,
        odom_t_base: Pose2D,
        points: np.ndarray,
        ranges: np.ndarray,
        angles: np.ndarray,
    ) -> bool:
        """The mapper's `process`; on a continued map, the session's first scan is placed
        near `map_start_pose` instead, and fixes the odometry's place in the graph's frame."""
        mapper = self.mapper
        if self._continue_at is not None and isinstance(mapper, ContinuedMapper):
            guess = (Pose2D.from_array(self._continue_at) @ odom_t_base).as_array()
            in_graph = mapper.process_near(stamp, guess, points, ranges, angles)
            self._odom_in_graph = Pose2D.from_array(in_graph) @ odom_t_base.inverse()
            self._continue_at = None
            return True
        odom = odom_t_base if self._odom_in_graph is None else self._odom_in_graph @ odom_t_base
        return mapper.process(stamp, odom.as_array(), points, ranges, angles)

    def serialize_pose_graph(self, path: str | PathLike[str]) -> Path:
        """slam_toolbox's SerializePoseGraph: the graph and its scans, for `mode: localization`."""
        return save_pose_graph(self.mapper, graph_file(path))

    def _rebuild(self) -> None:
        scans = [(s.ranges, s.angles, self._laser) for s in self.mapper.scans]
        self.occupancy.rebuild(self.mapper.poses, scans)
        self._map_revision = self.mapper.revision

    # -- the map -----------------------------------------------------------------------------

    def publish_map(self, now: float) -> OccupancyGrid:
        self.map = self.occupancy.grid(self.params.map_frame)
        self._last_map_time = now
        self._dirty = False
        for callback in self._map_subscribers:
            callback(self.map)
        return self.map
