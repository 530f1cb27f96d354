"""Cartographer's engine on a recorded log: `btnav slam LOG --lua FILE`.

What cartographer_ros's offline node does with a bag: every scan through local SLAM with
the log's odometry at its time as the prior, the nodes to global SLAM, and
FinishTrajectory's final optimisation. Odometry is read at each reading's first report
(`fresh_odometry`), since a logger that repeats a stalled pose and then jumps would turn
the map (MIT CSAIL's log: see docs/decisions/0058). Every scan gets a pose, and the map is
every submap at its optimised pose, as map_saver saves /map.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Callable

import numpy as np

from ...core.geometry import compose_arrays, relative_arrays
from ..logs import RecordedLog
from ..offline_result import OfflineResult
from .options import CartographerConfig
from .slam import CartographerMapper, LocalTrajectoryBuilder, compose, global_map, relative
from .submaps import RangeData


def run_cartographer(
    log: RecordedLog,
    config: CartographerConfig,
    progress: Callable[[int, int], None] | None = None,
) -> OfflineResult:
    """Map `log` with Cartographer's options; `progress(done, total)` after every scan.
    The options btnav does not act on are one warning first, as the live plugin gives."""
    config.warn_ignored()
    wall0 = time.perf_counter()
    tb, frames = config.trajectory_builder_2d, config.frames
    local = LocalTrajectoryBuilder(tb, frames.use_odometry, np.zeros(3))
    mapper = CartographerMapper(config.pose_graph, frames.use_odometry, local.submaps.submaps)
    laser = np.asarray(log.laser_offset, float)
    n = len(log.scans)
    stamps = np.array([s.stamp for s in log.scans], float)
    if log.has_odometry or frames.use_odometry:  # (odometry asked for and missing: LogError)
        odom = fresh_odometry(log).odom_at(stamps).reshape(n, 3)
    else:  # a laser-only log: Cartographer's pose extrapolator alone
        odom = np.zeros((n, 3))
    local_poses = np.full((n, 3), np.nan)
    node_of = np.full(n, -1)
    for i, scan in enumerate(log.scans):
        data = RangeData.from_scan(
            scan, laser, tb.min_range, tb.max_range, tb.missing_data_ray_length
        )
        out = local.add_range_data(scan.stamp, odom[i], data)
        if out is not None:
            local_poses[i], insertion = out
            if insertion is not None:
                mapper.add_node(insertion)
        node_of[i] = len(mapper.scans) - 1
        if progress is not None:
            progress(i + 1, n)
    mapper.run_final_optimization()
    poses = _scan_poses(mapper, local_poses, node_of, odom)
    grid = global_map(local.submaps.submaps, mapper, frames.map_frame)
    return OfflineResult(stamps, poses, mapper, grid, time.perf_counter() - wall0)


def fresh_odometry(log: RecordedLog) -> RecordedLog:
    """`log` with each odometry pose at the time it was first reported: a reading that
    repeats the one before it bit for bit is a stale one (see the module doc), so
    interpolation runs from a pose's first report to the next new pose. A real stop
    costs at most one odometry step spread over the stop."""
    stamps, poses = log.odom_stamps, log.odom_poses
    if len(stamps) < 3:
        return log
    new = np.ones(len(stamps), dtype=bool)
    new[1:] = (poses[1:] != poses[:-1]).any(axis=1)
    if new.all():
        return log
    return dataclasses.replace(log, odom_stamps=stamps[new], odom_poses=poses[new])


def _scan_poses(
    mapper: CartographerMapper, local_poses: np.ndarray, node_of: np.ndarray, odom: np.ndarray
) -> np.ndarray:
    """Every scan in the map frame (see the module doc)."""
    local = local_poses.copy()
    for i in np.flatnonzero(~np.isfinite(local[:, 0])):  # accumulating scans: by odometry
        if i:
            local[i] = compose(local[i - 1], relative(odom[i - 1], odom[i]))
        else:
            local[i] = 0.0
    if not mapper.scans:
        return local
    node_local = np.array([node.local_pose for node in mapper.scans])
    k = np.maximum(node_of, 0)
    correction = relative_arrays(node_local[k], local)
    return compose_arrays(mapper.poses[k], correction)
