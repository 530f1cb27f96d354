"""Where the robot is against the path it follows: Nav2's controller-server tracking feedback.

The robot is projected onto the path's segments within a window ahead of the last
closest one (a path is followed forward; `search_dist` metres of it are searched), as
`nav2_util::distance_from_path` does; the nearest segment gives the signed cross-track
error (positive left of the path), the heading error against that segment's direction,
and the length still to go. Vectorised over the window's segments.

The window ends where the path's running sums from its first pose pass `search_dist`
beyond the closest one's (Nav2 sums from the closest pose on: the two differ by
rounding only, at a tie; the tracking feedback, which IsWithinPathTrackingBounds reads,
is pinned to this one).
"""

from __future__ import annotations

import numpy as np

from ..core import fmath
from ..core.geometry import Pose2D, normalize_angle
from ..core.messages import Path
from ..core.path_utils import first_beyond, segment_lengths


class PathTracker:
    def __init__(self, search_dist: float = 2.0) -> None:
        self.search_dist = search_dist
        self._path: Path | None = None
        self._index = 0
        self._seg_len = np.zeros(0)
        self._along = np.zeros(0)  # length from the first pose to each pose

    def set_path(self, path: Path) -> None:
        if path is self._path:
            return
        self._path = path
        self._index = 0
        self._seg_len = segment_lengths(path.poses)
        self._along = np.concatenate([[0.0], np.cumsum(self._seg_len)])

    def track(self, pose: Pose2D) -> tuple[int, float, float, float]:
        """(index of the closest segment's first pose, signed cross-track error,
        heading error, remaining length) for `pose` in the path's frame."""
        path = self._path
        if path is None or len(path) == 0:
            return 0, 0.0, 0.0, 0.0
        poses = path.poses
        if len(path) == 1:
            x, y, yaw = poses[0]
            heading = float(normalize_angle(pose.yaw - yaw))
            return 0, fmath.hypot(pose.x - x, pose.y - y), heading, 0.0
        start = min(self._index, len(path) - 2)
        # the segments starting within search_dist (along the path) of the last closest one
        along = self._along
        reach = first_beyond(along, along[start] + self.search_dist)
        stop = min(max(start + 1, reach), len(path) - 1)
        a = poses[start:stop, :2]
        seg = poses[start + 1 : stop + 1, :2] - a
        lengths = self._seg_len[start:stop]
        rel = np.array([pose.x, pose.y]) - a
        sq = lengths**2
        t = np.clip((rel * seg).sum(axis=1) / np.where(sq > 0, sq, 1.0), 0.0, 1.0)
        nearest = a + seg * t[:, None]
        dist = fmath.hypot(pose.x - nearest[:, 0], pose.y - nearest[:, 1])
        k = int(np.argmin(dist))
        i = start + k
        self._index = i
        sx, sy = seg[k]
        side = sx * rel[k, 1] - sy * rel[k, 0]  # > 0: left of the segment's direction
        error = float(dist[k]) if side >= 0 else -float(dist[k])
        heading = float(normalize_angle(pose.yaw - fmath.arctan2(float(sy), float(sx))))
        remaining = float(along[-1] - along[i] - lengths[k] * t[k])
        return i, error, heading, remaining
