"""nav2_route's PathConverter: the route's edges as a dense path, a pose every
`path_density` metres (at most), with corners rounded into arcs when `smooth_corners`.

Each pose faces the next one; the last faces along the last edge. A route of one node
is a path of one pose. After a reroute along the edge the robot was on, the path
begins at the robot's closest point on that edge.
"""

from __future__ import annotations

import itertools
import math

import numpy as np

from ..core import fmath
from ..core.messages import Path
from .corner_smoothing import CornerArc
from .graph import ReroutingState, Route


def interpolate_edge(x0: float, y0: float, x1: float, y1: float, density: float) -> np.ndarray:
    """Points from (x0, y0) (included) towards (x1, y1) (excluded), evenly spaced at most
    `density` apart; none for a zero-length edge."""
    length = fmath.hypot(x1 - x0, y1 - y0)
    n = math.ceil(length / density)
    if n < 1:
        return np.zeros((0, 2))
    t = np.arange(n) / n
    return np.stack([x0 + (x1 - x0) * t, y0 + (y1 - y0) * t], axis=1)


class PathConverter:
    def __init__(
        self,
        path_density: float = 0.05,
        smooth_corners: bool = False,
        smoothing_radius: float = 1.0,
        smoothing_angle_threshold: float = 2.9,
    ) -> None:
        self.density = path_density
        self.smooth_corners = smooth_corners
        self.smoothing_radius = smoothing_radius
        self.smoothing_angle_threshold = smoothing_angle_threshold

    def densify(
        self,
        route: Route,
        rerouting: ReroutingState | None = None,
        frame: str = "map",
        stamp: float = 0.0,
    ) -> Path:
        parts: list[np.ndarray] = []
        d = self.density
        if rerouting is not None and rerouting.curr_edge is not None:
            (px, py), end = rerouting.closest_pt_on_edge, rerouting.curr_edge.end
            parts.append(interpolate_edge(px, py, end.x, end.y, d))
        edges = route.edges
        if not edges:
            parts.append(np.array([[route.start_node.x, route.start_node.y]]))
        else:
            start = (edges[0].start.x, edges[0].start.y)
            for edge, after in itertools.pairwise(edges):
                corner = (edge.end.x, edge.end.y)
                arc = CornerArc(
                    start,
                    corner,
                    (after.end.x, after.end.y),
                    self.smoothing_radius,
                    self.smoothing_angle_threshold,
                )
                if self.smooth_corners and arc.valid:
                    parts.append(interpolate_edge(*start, *arc.start_point, d))
                    parts.append(arc.interpolate(d / self.smoothing_radius))
                    start = arc.end_point
                else:
                    parts.append(interpolate_edge(*start, *corner, d))
                    start = corner
            last = edges[-1].end
            parts.append(interpolate_edge(*start, last.x, last.y, d))
            parts.append(np.array([[last.x, last.y]]))
        xy = np.concatenate(parts)
        yaw = np.zeros(len(xy))
        if len(xy) > 1:
            step = np.diff(xy, axis=0)
            yaw[:-1] = fmath.arctan2(step[:, 1], step[:, 0])
        if edges:
            e = edges[-1]
            yaw[-1] = float(fmath.arctan2(e.end.y - e.start.y, e.end.x - e.start.x))
        return Path(stamp, np.column_stack([xy, yaw]), frame)
