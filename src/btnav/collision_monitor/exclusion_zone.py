"""A region a source's points are dropped from (nav2_collision_monitor's ExclusionZone, Nav2
main): the dock the robot drives onto, a part of the robot the lidar sees.

A zone is anchored to `frame_id` (the base frame when empty: it rides with the robot).
Another frame is looked up in odom each cycle; if that frame's own transform is older
than `max(frame_hold_timeout, transform_tolerance)` or the frame does not exist, the
zone excludes nothing (fail safe: every point kept). `min_height`/`max_height` bound
the points' height; btnav's points are planar (z = 0), so they only matter when the
band leaves out 0. Disabled by default, as in Nav2.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ..core.frames import FrameTree
from ..core.geometry import Pose2D
from ..params.collision_monitor import ExclusionZone as ExclusionZoneParams
from .shapes import points_in_polygon


class ExclusionZone:
    """One exclusion zone; `apply(now, points)` returns the points outside it."""

    def __init__(
        self,
        name: str,
        params: ExclusionZoneParams,
        tree: FrameTree,
        base_frame: str,
        odom_frame: str,
        transform_tolerance: float = 0.1,
    ) -> None:
        self.name = name
        self.params = params
        self.enabled = params.enabled
        self.tree = tree
        self.base_frame = base_frame
        self.odom_frame = odom_frame
        self.frame_id = params.frame_id or base_frame
        self.max_age = max(params.frame_hold_timeout, transform_tolerance)
        self.vertices = None if params.points is None else np.asarray(params.points, float)

    def zone_to_base(self, now: float) -> Pose2D | None:
        """The zone's frame in the base frame now, or None when it cannot be trusted."""
        if self.frame_id == self.base_frame:
            return Pose2D()
        tree = self.tree
        if not tree.has(self.frame_id):
            return None
        edge = tree.edge(self.frame_id) if tree.parent(self.frame_id) is not None else None
        if edge is not None and not edge.static and now - edge.stamp > self.max_age:
            return None
        return tree.lookup(self.base_frame, self.frame_id)

    def apply(self, now: float, points: NDArray[np.float64]) -> NDArray[np.float64]:
        if not self.enabled or len(points) == 0:
            return points
        if not self.params.min_height <= 0.0 <= self.params.max_height:
            return points  # planar points are outside the zone's height band
        pose = self.zone_to_base(now)
        if pose is None:
            return points
        local = pose.inverse_transform_points(points)
        if self.params.type == "circle":
            assert self.params.radius is not None
            inside = _within(local, self.params.radius)
        else:
            assert self.vertices is not None
            inside = points_in_polygon(local, self.vertices)
        return points[~inside]


def _within(points: NDArray[np.float64], radius: float) -> NDArray[np.bool_]:
    """Nav2's circle zone includes its rim (<=), unlike the circle action zone (<)."""
    return points[:, 0] * points[:, 0] + points[:, 1] * points[:, 1] <= radius * radius
