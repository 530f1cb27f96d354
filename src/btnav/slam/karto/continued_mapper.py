"""slam_toolbox's continued mapping: Karto's Mapper going on from a deserialised graph."""

from __future__ import annotations

from typing import Any

import numpy as np

from .mapper import Mapper, Scan


class ContinuedMapper(Mapper):
    """Karto's Mapper going on from a deserialised graph (slam_toolbox's continued mapping):
    the session's first scan is placed by `process_near`, every later one by `process`."""

    #: The node the next link from "the scan before" comes from (Karto's last scan).
    _previous: int | None = None

    def process_near(
        self, stamp: float, guess: np.ndarray, points: np.ndarray, ranges: Any, angles: Any
    ) -> np.ndarray:
        """Karto's ProcessAgainstNodesNearBy: the scan matched, from `guess` (the map start
        pose), against the graph's scan nearest to it, which stands for the scan before it
        (its first edge, the running buffer); then linked to near chains and loops closed,
        as any scan. Its odometric pose is its matched pose, as Karto sets it: returned, it
        places the new session's odometry in the graph's odometry frame."""
        p = self.params
        pose, covariance = np.asarray(guess, float), np.eye(3)
        if self.scans:
            d2 = ((self.poses[:, :2] - pose[:2]) ** 2).sum(axis=1)
            self._previous = int(np.argmin(d2))
            self.running = [self._previous]
            if p.use_scan_matching and len(points):
                match = self.sequential.match(points, pose, self._reference(self.running))
                pose, covariance = np.asarray(match.pose, float), match.covariance
        scan = Scan(stamp, pose.copy(), np.asarray(points, float), ranges, angles)
        if len(scan.points):
            scan.centroid = scan.points.mean(axis=0)
        self.scans.append(scan)
        node = self.graph.add_node(pose)
        if p.use_scan_matching:
            if self._previous is not None:
                self._add_edges(node, pose, covariance)
            self._add_running(node)
            if p.do_loop_closing and len(scan.points):
                self._try_close_loop(node)
        self._previous = None
        return scan.odom_pose

    def _link(self, i: int, j: int, mean: np.ndarray, covariance: np.ndarray) -> None:
        """Karto links a scan first to its last scan: for `process_near`'s scan that is the
        graph's scan nearest to it (`_previous`), not the one before it in the file."""
        if self._previous is not None:
            i, self._previous = self._previous, None
        super()._link(i, j, mean, covariance)
