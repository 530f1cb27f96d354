"""SLAM on a recorded log: the engine `localization: slam` runs, fed from a file.

Each scan of the log goes through slam_toolbox's gate and Karto's mapper with the
odometry pose at the scan's time, exactly as online. At the end every scan, processed
or not, gets a pose: its last processed scan's optimised pose moved by the odometry
since (what `map -> odom` said at that scan, after the last optimisation), so the
trajectory has one row per scan, stamped with the scan's time. The map is rebuilt from
every processed scan at its optimised pose.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..core.geometry import Pose2D, compose_arrays, relative_arrays
from ..maps.occupancy_grid import OccupancyGrid
from ..params.localization import SlamToolboxParams
from .logs import RecordedLog
from .mapper import Mapper
from .occupancy_mapper import OccupancyMapper
from .scan_gate import ScanGate
from .scan_points import scan_points

F64 = NDArray[np.float64]


@dataclass
class OfflineResult:
    stamps: F64  # (S,) every scan's time
    poses: F64  # (S, 3) every scan's robot pose in the map frame
    mapper: Mapper
    grid: OccupancyGrid
    wall_time: float

    @property
    def processed(self) -> int:
        return len(self.mapper.scans)


def run_slam(
    log: RecordedLog,
    params: SlamToolboxParams,
    progress: Callable[[int, int], None] | None = None,
) -> OfflineResult:
    """Map `log`; `progress(done, total)` after every scan."""
    wall0 = time.perf_counter()
    start = np.asarray(params.map_start_pose or (0.0, 0.0, 0.0), float)
    mapper = Mapper(params, start)
    gate = ScanGate(params)
    laser = Pose2D(*np.asarray(log.laser_offset, float))
    n = len(log.scans)
    stamps = np.array([s.stamp for s in log.scans], float)
    odom = log.odom_at(stamps).reshape(n, 3)
    node_of = np.full(n, -1)
    for i, scan in enumerate(log.scans):
        if gate(scan.stamp, odom[i]):
            points, ranges, angles = scan_points(scan, laser, params.max_laser_range)
            mapper.process(scan.stamp, odom[i], points, ranges, angles)
        node_of[i] = len(mapper.scans) - 1
        if progress is not None:
            progress(i + 1, n)
    nodes = mapper.poses
    node_odom = np.array([s.odom_pose for s in mapper.scans])
    poses = compose_arrays(nodes[node_of], relative_arrays(node_odom[node_of], odom))
    occupancy = OccupancyMapper(params.resolution, params.max_laser_range)
    occupancy.rebuild(nodes, [(s.ranges, s.angles, laser.as_array()) for s in mapper.scans])
    grid = occupancy.grid(params.map_frame)
    return OfflineResult(stamps, poses, mapper, grid, time.perf_counter() - wall0)
