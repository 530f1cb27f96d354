"""A laser scanner source (nav2_collision_monitor's Scan): the newest LaserScan's readings
within [range_min, range_max] as points in the base frame.

Nav2's scan source has no filters of its own: `min_height`, `max_height` and
`min_range` are its pointcloud source's keys (a planar scan has one height, its
mount's, and btnav's frames are 2D), so a scan source ignores them, as Nav2 does. The
readings REP-117 marks (+inf nothing hit, -inf too close, NaN) fail the range test.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ..core import fmath
from ..core.geometry import Pose2D
from ..core.messages import LaserScan
from .source import Source


class ScanSource(Source):
    """`scan` source: `receive(scan)` is the subscription callback."""

    scan: LaserScan | None = None
    #: The scan's frame in odom when it arrived (base_shift_correction), else None.
    _odom_pose: Pose2D | None = None
    #: The scan's readings in range, as points in its own frame.
    _local: NDArray[np.float64] = np.zeros((0, 2))
    #: sin and cos of the beams' angles, and the (angle_min, increment, beams) they are for.
    _directions: tuple[NDArray[np.float64], NDArray[np.float64]] = (np.zeros(0), np.zeros(0))
    _directions_of: tuple[float, float, int] | None = None

    def receive(self, scan: LaserScan) -> None:
        """Keep the newest scan as points in its own frame (a scan arrives at the lidar's
        rate, commands at the controller's: the points are made once), and where its frame
        was then (Nav2's dataCallback)."""
        self.scan = scan
        self._odom_pose = self.frames.at_arrival(scan.frame_id)
        ranges = scan.ranges  # compared in float32, as Nav2 compares the message's floats
        ok = (ranges >= np.float32(scan.range_min)) & (ranges <= np.float32(scan.range_max))
        r = ranges[ok].astype(float)
        s, c = self._beam_directions(scan)
        self._local = np.stack([r * c[ok], r * s[ok]], axis=-1)

    def _beam_directions(self, scan: LaserScan) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """sin and cos of every beam's angle: a lidar's beams keep their angles, so they
        are worked out once per (angle_min, angle_increment, beams)."""
        key = (scan.angle_min, scan.angle_increment, len(scan.ranges))
        if self._directions_of != key:
            self._directions = fmath.sincos(scan.angles)
            self._directions_of = key
        return self._directions

    def keep_scan_of(self, previous: ScanSource) -> None:
        """Take over `previous`'s scan as it received it (a rebuild on new params)."""
        self.scan, self._odom_pose = previous.scan, previous._odom_pose
        self._local = previous._local

    def source_data(self, now: float) -> NDArray[np.float64] | None:
        scan = self.scan
        if scan is None or not self.source_valid(scan.stamp, now):
            return None
        return self.frames.to_base(scan.frame_id, self._odom_pose).transform_points(self._local)
