"""SLAM on a recorded log: the engine `localization: slam` runs, fed from a file.

Each scan of the log goes through slam_toolbox's gate and Karto's mapper with the
odometry pose at the scan's time, exactly as online. The map is rebuilt from every
processed scan at its optimised pose. At the end every scan, processed or not, gets a
pose, so the trajectory has one row per scan, stamped with the scan's time:

- a processed scan: its node's optimised pose;
- any other scan, with `trajectory="matched"` (the default): Karto's sequential matcher
  lays the scan onto the two processed scans around it (at their optimised poses),
  searching around the odometry's guess between them (the odometry since the earlier
  one and to the later one, blended by time). slam_toolbox publishes such a scan's pose
  as `map -> odom` times the odometry, which is only as good as the odometry. Kümmerle's
  relations are between scans, nearly all of them skipped by the gate (12 of 2984 Intel
  relations join two processed scans), so a benchmark scores exactly these poses: on
  the Intel log (wheel odometry with bursty stamps, 1.6 degrees of error per relation
  under 2 s) matching takes the relation errors from 5.3 cm / 1.8 deg to 2.9 cm /
  0.35 deg on the same map, for about as much time again as the mapping;
- with `trajectory="odometry"`: the earlier processed scan's optimised pose moved by the
  odometry since (what `map -> odom` says after the last optimisation).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from ...core.errors import ParamsError
from ...core.geometry import Pose2D, compose_arrays, normalize_angle, relative_arrays
from ...params.localization import SlamToolboxParams
from ..logs import RecordedLog
from ..offline_result import OfflineResult
from .mapper import Mapper
from .occupancy_mapper import OccupancyMapper
from .scan_gate import ScanGate
from .scan_points import scan_points

F64 = NDArray[np.float64]
Trajectory = Literal["matched", "odometry"]


def refuse_localization(params: SlamToolboxParams) -> None:
    """`mode: localization` is refused, not mapped anyway: slam_toolbox's localization
    mode leaves the loaded graph and its map as they were, so this command's outputs (a
    map and a graph of the log) would be copies of map_file_name's; tracking the robot
    on that graph is what a mission's `localization: slam` does."""
    if params.mode == "localization":
        raise ParamsError(
            "btnav slam builds a map from the log, and mode: localization would only track "
            "the robot on map_file_name's saved graph without changing it (run a mission "
            "with localization: slam for that); remove the key or set it to mapping",
            key="slam_toolbox.mode",
        )


def run_slam(
    log: RecordedLog,
    params: SlamToolboxParams,
    progress: Callable[[int, int], None] | None = None,
    *,
    trajectory: Trajectory = "matched",
) -> OfflineResult:
    """Map `log`; `progress(done, total)` after every scan (twice over the scans when the
    trajectory is matched: mapping, then matching)."""
    if trajectory not in ("matched", "odometry"):
        raise ValueError(f"trajectory must be 'matched' or 'odometry', not {trajectory!r}")
    refuse_localization(params)
    wall0 = time.perf_counter()
    start = np.asarray(params.map_start_pose or (0.0, 0.0, 0.0), float)
    mapper = Mapper(params, start)
    gate = ScanGate(params)
    laser = Pose2D(*np.asarray(log.laser_offset, float))
    n = len(log.scans)
    total = 2 * n if trajectory == "matched" else n
    stamps = np.array([s.stamp for s in log.scans], float)
    odom = log.odom_at(stamps).reshape(n, 3)
    node_of = np.full(n, -1)
    is_node = np.zeros(n, bool)
    for i, scan in enumerate(log.scans):
        if gate(scan.stamp, odom[i]):
            points, ranges, angles = scan_points(scan, laser, params.max_laser_range)
            is_node[i] = mapper.process(scan.stamp, odom[i], points, ranges, angles)
        node_of[i] = len(mapper.scans) - 1
        if progress is not None:
            progress(i + 1, total)
    if trajectory == "matched":

        def matched(done: int) -> None:
            if progress is not None:
                progress(n + done, total)

        poses = matched_trajectory(log, mapper, odom, node_of, is_node, laser, matched)
    else:
        poses = odometry_trajectory(mapper, odom, node_of)
    occupancy = OccupancyMapper(params.resolution, params.max_laser_range)
    occupancy.rebuild(mapper.poses, [(s.ranges, s.angles, laser.as_array()) for s in mapper.scans])
    grid = occupancy.grid(params.map_frame)
    return OfflineResult(stamps, poses, mapper, grid, time.perf_counter() - wall0)


def odometry_trajectory(mapper: Mapper, odom: F64, node_of: NDArray[np.int64]) -> F64:
    """Every scan at its last processed scan's optimised pose moved by the odometry since
    (`map -> odom` after the last optimisation, times the odometry)."""
    nodes = mapper.poses
    node_odom = np.array([s.odom_pose for s in mapper.scans])
    return compose_arrays(nodes[node_of], relative_arrays(node_odom[node_of], odom))


def odometry_guesses(mapper: Mapper, stamps: F64, odom: F64, node_of: NDArray[np.int64]) -> F64:
    """Each scan's pose by the odometry from the processed scan before it and to the one
    after it, blended linearly in time: an odometry error between two processed scans
    (a jump of the Intel log's odometry) is then split, not carried to the next one."""
    nodes = mapper.poses
    node_odom = np.array([s.odom_pose for s in mapper.scans])
    node_stamp = np.array([s.stamp for s in mapper.scans])
    a = node_of
    b = np.minimum(a + 1, len(nodes) - 1)
    forward = compose_arrays(nodes[a], relative_arrays(node_odom[a], odom))
    backward = compose_arrays(nodes[b], relative_arrays(node_odom[b], odom))
    span = node_stamp[b] - node_stamp[a]
    f = np.where(span > 0.0, (stamps - node_stamp[a]) / np.where(span > 0.0, span, 1.0), 0.0)
    f = np.clip(f, 0.0, 1.0)
    out = np.empty_like(forward)
    out[:, :2] = forward[:, :2] + f[:, None] * (backward[:, :2] - forward[:, :2])
    out[:, 2] = normalize_angle(forward[:, 2] + f * normalize_angle(backward[:, 2] - forward[:, 2]))
    return out


def matched_trajectory(
    log: RecordedLog,
    mapper: Mapper,
    odom: F64,
    node_of: NDArray[np.int64],
    is_node: NDArray[np.bool_],
    laser: Pose2D,
    progress: Callable[[int], None] | None = None,
) -> F64:
    """Every scan's pose: a processed scan's node pose; any other scan matched by Karto's
    sequential matcher against the processed scans before and after it, around the
    blended odometry guess. The scans between two processed scans share one
    correlation grid (built once, centred between them), so the cost per scan is the
    search alone. A scan the matcher finds nothing for keeps the guess."""
    stamps = np.array([s.stamp for s in log.scans], float)
    guesses = odometry_guesses(mapper, stamps, odom, node_of)
    poses = guesses.copy()
    nodes = mapper.poses
    node_index = np.cumsum(is_node) - 1
    poses[is_node] = nodes[node_index[is_node]]
    matcher = mapper.sequential
    max_range = mapper.params.max_laser_range
    k = len(nodes)
    todo = np.flatnonzero(~is_node)
    # runs of scans with the same processed scan before them
    cuts = np.flatnonzero(np.diff(node_of[todo])) + 1
    for run in np.split(todo, cuts):
        if run.size == 0:
            continue
        a = int(node_of[run[0]])
        ids = [a] if a + 1 >= k else [a, a + 1]
        centre = nodes[ids, :2].mean(axis=0)
        points = [scan_points(log.scans[i], laser, max_range)[0] for i in run]
        reach = [
            _farthest(p) + float(np.sqrt(((guesses[i, :2] - centre) ** 2).sum()))
            for i, p in zip(run, points, strict=True)
        ]
        grid = matcher.correlation_grid(
            [(mapper.world_points(j), nodes[j]) for j in ids], centre, centre, max(reach)
        )
        for i, p in zip(run, points, strict=True):
            if len(p):
                result = matcher.match(p, guesses[i], (), grid=grid)
                if result.response > 0.0:
                    poses[i] = result.pose
        if progress is not None:
            progress(int(run[-1]) + 1)
    if progress is not None:
        progress(len(stamps))
    return poses


def _farthest(points: F64) -> float:
    if not len(points):
        return 0.0
    return float(np.sqrt((points[:, 0] * points[:, 0] + points[:, 1] * points[:, 1]).max()))
