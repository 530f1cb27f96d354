"""slam_toolbox's `mode: localization`: the robot tracked on a deserialised pose graph.

Each scan that passes the gate is matched (Karto's sequential matcher, penalised
towards the odometry prediction) against the graph's scans whose barycenters lie
within `loop_search_maximum_distance` of the prediction (at most `scan_buffer_size`
x 2 of the nearest) plus the last `scan_buffer_size` localisation scans, which carry
the robot through places the graph saw poorly. A match above
`link_match_minimum_response_fine` sets the pose; a weaker one keeps the prediction.
The loaded graph and its map never change, as in slam_toolbox, whose localisation
scans leave the graph again after `scan_buffer_size` newer ones.
"""

from __future__ import annotations

from collections import deque

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial import cKDTree

from ...core.geometry import compose_arrays, relative_arrays
from .mapper import Mapper

F64 = NDArray[np.float64]


class GraphLocalizer:
    def __init__(self, mapper: Mapper, start_pose: ArrayLike) -> None:
        self.mapper = mapper
        self.params = mapper.params
        self.tree = cKDTree(mapper.barycenters()) if mapper.scans else None
        self.pose = np.asarray(start_pose, float)
        self.odom: F64 | None = None
        self.recent: deque[tuple[F64, F64]] = deque(maxlen=self.params.scan_buffer_size)
        self.last_response = 0.0

    def predict(self, odom_pose: ArrayLike) -> F64:
        odom = np.asarray(odom_pose, float)
        if self.odom is None:
            return self.pose
        delta = relative_arrays(self.odom[None, :], odom[None, :])
        return compose_arrays(self.pose[None, :], delta)[0]

    def _reference(self, guess: F64) -> list[tuple[F64, F64]]:
        ref = list(self.recent)
        if self.tree is not None:
            p = self.params
            k = min(2 * p.scan_buffer_size, len(self.mapper.scans))
            d, idx = self.tree.query(guess[:2], k=k)
            near = np.atleast_1d(idx)[np.atleast_1d(d) <= p.loop_search_maximum_distance]
            ref += [
                (self.mapper.world_points(int(i)), self.mapper.poses[int(i)]) for i in sorted(near)
            ]
        return ref

    def process(self, odom_pose: ArrayLike, points: F64) -> F64:
        """The robot's map pose at this scan (points: valid end points in the robot frame)."""
        guess = self.predict(odom_pose)
        ref = self._reference(guess)
        pose = guess
        if ref and len(points):
            match = self.mapper.sequential.match(points, guess, ref)
            self.last_response = match.response
            if match.response >= self.params.link_match_minimum_response_fine:
                pose = match.pose
        self.pose, self.odom = pose, np.asarray(odom_pose, float)
        world = compose_arrays(pose, np.column_stack([points, np.zeros(len(points))]))[:, :2]
        self.recent.append((world, pose))
        return pose
