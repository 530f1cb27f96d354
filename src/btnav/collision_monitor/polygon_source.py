"""A source of polygons (nav2_collision_monitor's PolygonSource): obstacles someone
else detected, given as outlines, sampled along their edges every
`sampling_distance` into points.

`receive(polygon)` is Nav2's PolygonInstanceStamped subscription: a polygon replaces
the one with its `id`. Polygons older than `source_timeout` are dropped on each read.
Until the first polygon arrives the source is invalid (with a timeout the monitor then
stops the robot, as Nav2's does).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..core import fmath
from ..core.geometry import Pose2D
from ..params.collision_monitor import ObservationSource
from .exclusion_zone import ExclusionZone
from .source import Source, SourceFrames


@dataclass(frozen=True)
class PolygonInstance:
    """geometry_msgs/PolygonInstanceStamped: an outline with an id, a frame and a stamp."""

    id: int
    points: ArrayLike
    frame_id: str
    stamp: float


def sample_outline(vertices: NDArray[np.float64], spacing: float) -> NDArray[np.float64]:
    """Points along each edge (closed), `ceil(length / spacing)` intervals per edge, both
    ends included, as Nav2 samples them (shared vertices appear twice)."""
    a = vertices
    b = np.roll(vertices, -1, axis=0)
    lengths = fmath.hypot(b[:, 0] - a[:, 0], b[:, 1] - a[:, 1])
    n = np.maximum(np.ceil(lengths / spacing).astype(np.int64), 1)
    edge = np.repeat(np.arange(len(a)), n + 1)
    start = np.repeat(np.cumsum(n + 1) - (n + 1), n + 1)
    j = np.arange(len(edge)) - start  # 0..n on each edge
    f = j / n[edge]
    return a[edge] + (b[edge] - a[edge]) * f[:, None]


class PolygonSource(Source):
    """`polygon` source: outlines handed to it, as points along their edges."""

    def __init__(
        self,
        name: str,
        params: ObservationSource,
        frames: SourceFrames,
        source_timeout: float,
        zones: list[ExclusionZone] | None = None,
    ) -> None:
        super().__init__(name, params, frames, source_timeout, zones)
        self.polygons: dict[int, tuple[PolygonInstance, Pose2D | None]] = {}

    def receive(self, polygon: PolygonInstance) -> None:
        self.polygons[polygon.id] = (polygon, self.frames.at_arrival(polygon.frame_id))

    def source_data(self, now: float) -> NDArray[np.float64] | None:
        if not self.polygons:
            return None
        self.polygons = {
            i: held
            for i, held in self.polygons.items()
            if not now - held[0].stamp > self.source_timeout
        }
        parts = [np.zeros((0, 2))]
        for polygon, odom_pose in self.polygons.values():
            vertices = np.asarray(polygon.points, dtype=float).reshape(-1, 2)
            local = sample_outline(vertices, self.params.sampling_distance)
            parts.append(self.frames.to_base(polygon.frame_id, odom_pose).transform_points(local))
        return np.concatenate(parts)
