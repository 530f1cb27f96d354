"""A zone around the robot and the action it asks for (nav2_collision_monitor's Polygon).

For stop, slowdown and limit a polygon is a zone: the action applies while at least
`min_points` sensed points are inside it (held through `trigger_consecutive_points`
and `release_consecutive_points` cycles when they are above 1). For approach it is the
robot's footprint: `collision_time` moves it along the commanded motion and reports
when `min_points` points would first be inside. A polygon with no `points` takes its
shape at run time: an approach polygon from the footprint it is handed (Nav2's
`footprint_topic`), the others from `set_polygon` (Nav2's `polygon_sub_topic`).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..core import fmath
from ..core.messages import Twist
from ..params.collision_monitor import CollisionPolygon
from .action import ActionType, action_type_of
from .kinematics import projected_poses, step_times
from .shapes import Outline

#: The points each source sensed, (N, 2) in the base frame, by source name.
PointsBySource = Mapping[str, NDArray[np.float64]]

_NO_POINTS = np.zeros((0, 2))
_NO_POINTS.flags.writeable = False


class Polygon:
    """A `polygon` zone: Nav2's Polygon with its params, shape and trigger state."""

    def __init__(
        self,
        name: str,
        params: CollisionPolygon,
        sources: list[str],
        footprint: Callable[[], NDArray[np.float64]] | None = None,
    ) -> None:
        self.name = name
        self.params = params
        self.action_type: ActionType = action_type_of(params.action_type)
        self.enabled = params.enabled
        self.min_points = params.required_min_points
        self.trigger_consecutive_points = params.trigger_consecutive_points
        self.release_consecutive_points = params.release_consecutive_points
        self.slowdown_ratio = params.slowdown_ratio
        self.linear_limit = params.linear_limit
        self.angular_limit = params.angular_limit
        self.time_before_collision = params.time_before_collision
        self.simulation_time_step = params.simulation_time_step
        #: The sources whose points this zone checks (all by default).
        self.sources_names = list(params.sources_names) if params.sources_names else sources
        #: The robot footprint in the base frame, for a polygon with no points of its own.
        self._footprint = footprint
        self.vertices: NDArray[np.float64] | None = (
            np.asarray(params.points, dtype=float) if params.points else None
        )
        #: `vertices` as an Outline (edges, box, reach), and the array it was made from.
        self._shape: Outline | None = None
        self._shape_of: NDArray[np.float64] | None = None
        #: The footprint array `vertices` was last read from.
        self._footprint_read: object = None
        self.reset_trigger_state()

    # -- the shape ----------------------------------------------------------------------

    @property
    def follows_footprint(self) -> bool:
        """An approach polygon without points is the robot footprint (Nav2's
        footprint_topic, read only then), refreshed before every check."""
        return self.params.points is None and self.action_type == ActionType.APPROACH

    def is_shape_set(self) -> bool:
        return self.vertices is not None and len(self.vertices) > 0

    def update_polygon(self, cmd: Twist) -> None:
        """Before each check: the footprint's latest shape, for a footprint polygon."""
        if self.follows_footprint and self._footprint is not None:
            footprint = self._footprint()
            # the costmap replaces its footprint array when the footprint changes (never
            # in place): the same array is the same shape, and its Outline still holds
            if footprint is not self._footprint_read:
                self.vertices = np.asarray(footprint, dtype=float).reshape(-1, 2)
                self._footprint_read = footprint

    def set_polygon(self, vertices: ArrayLike) -> None:
        """A shape given at run time, in the base frame (Nav2's polygon_sub_topic message);
        fewer than 3 vertices is refused, as Nav2 does. The trigger state starts over."""
        v = np.asarray(vertices, dtype=float).reshape(-1, 2)
        if len(v) < 3:
            raise ValueError(f"polygon '{self.name}': a polygon needs at least 3 points")
        self.vertices = v
        self.reset_trigger_state()

    def outline(self) -> NDArray[np.float64]:
        """The zone's vertices in the base frame (what Nav2 publishes for RViz)."""
        return _NO_POINTS if self.vertices is None else self.vertices

    def shape(self) -> Outline:
        """`vertices` as an Outline, made again only when they are another array."""
        if self._shape is None or self._shape_of is not self.vertices:
            self._shape = Outline(_NO_POINTS if self.vertices is None else self.vertices)
            self._shape_of = self.vertices
        return self._shape

    def inside(self, points: NDArray[np.float64]) -> NDArray[np.bool_]:
        """Which of `points` (..., 2) are inside the zone."""
        if self.vertices is None:
            return np.zeros(points.shape[:-1], dtype=bool)
        return self.shape().contains(points)

    # -- points inside --------------------------------------------------------------------

    def collision_points(self, points_by_source: PointsBySource) -> NDArray[np.float64]:
        """All points of this zone's sources, stacked (N, 2)."""
        parts = [points_by_source[s] for s in self.sources_names if s in points_by_source]
        parts = [p for p in parts if len(p)]
        if not parts:
            return _NO_POINTS
        return parts[0] if len(parts) == 1 else np.concatenate(parts)

    def points_inside(self, points_by_source: PointsBySource) -> NDArray[np.float64]:
        """The points of this zone's sources that are inside it."""
        points = self.collision_points(points_by_source)
        return points[self.inside(points)] if len(points) else _NO_POINTS

    def is_triggered(self, points_by_source: PointsBySource) -> tuple[bool, NDArray[np.float64]]:
        """Whether the zone acts this cycle, and the points inside it.

        At least `min_points` inside is a hit; the zone turns on after
        `trigger_consecutive_points` hits in a row and off after
        `release_consecutive_points` misses in a row (both 1: it follows each cycle).
        """
        inside = self.points_inside(points_by_source)
        hit = len(inside) >= self.min_points
        if self.trigger_consecutive_points == 1 and self.release_consecutive_points == 1:
            self.trigger_active = hit
            return hit, inside
        if hit:
            self.trigger_hits += 1
            self.release_hits = 0
            if self.trigger_hits >= self.trigger_consecutive_points:
                self.trigger_active = True
        else:
            self.release_hits += 1
            self.trigger_hits = 0
            if self.release_hits >= self.release_consecutive_points:
                self.trigger_active = False
        return self.trigger_active, inside

    def reset_trigger_state(self) -> None:
        self.trigger_hits = 0
        self.release_hits = 0
        self.trigger_active = False

    # -- approach -------------------------------------------------------------------------

    def collision_time(
        self, points_by_source: PointsBySource, velocity: Twist
    ) -> tuple[float, NDArray[np.float64]]:
        """Seconds until `min_points` points would be inside the zone if the robot kept
        `velocity`, and those points; (-1, none) when not within `time_before_collision`.

        Nav2's getCollisionTime: 0 if they are inside already; else the footprint is
        moved step by step (`simulation_time_step`) and the time of the step before the
        first one that holds them is returned. All poses (now, then each step's end) and
        all points at once, each point seen from a pose only when it is within the
        zone's reach of it (the others cannot be inside: the answer is the same).
        """
        points = self.collision_points(points_by_source)
        if len(points) == 0:
            return -1.0, _NO_POINTS
        dt = self.simulation_time_step
        times = step_times(self.time_before_collision, dt)
        poses = np.concatenate([np.zeros((1, 3)), projected_poses(velocity, dt, len(times))])
        # the margins cover rounding: a point inside is within reach of its pose, and the
        # poses within the path's length of the origin
        reach = self.reach() * (1.0 + 1e-9)
        path = float(fmath.hypot(velocity.linear_x, velocity.linear_y)) * (dt * len(times))
        around = (reach + path) * (1.0 + 1e-9)
        times = [0.0, *times]  # pose k > 0 answers with the start of its step
        near = points[points[:, 0] * points[:, 0] + points[:, 1] * points[:, 1] <= around * around]
        if len(near) < self.min_points:  # most commands: a lidar's points are mostly far
            return -1.0, _NO_POINTS
        dx = near[None, :, 0] - poses[:, 0, None]  # (poses, points)
        dy = near[None, :, 1] - poses[:, 1, None]
        close = dx * dx + dy * dy <= reach * reach
        steps = np.flatnonzero(np.count_nonzero(close, axis=1) >= self.min_points)
        if len(steps) == 0:
            return -1.0, _NO_POINTS
        # the close (pose, point) pairs of the poses that could hold enough, in the pose's
        # frame; fmath's Python-float sincos for a few headings (a straight drive's are 0)
        k, i = np.nonzero(close[steps])
        s, c = np.array([fmath.sincos(theta) for theta in poses[steps, 2].tolist()]).T
        s, c = s[k], c[k]
        pair_dx, pair_dy = dx[steps[k], i], dy[steps[k], i]
        seen = np.empty((len(k), 2))
        seen[:, 0] = pair_dx * c + pair_dy * s
        seen[:, 1] = -pair_dx * s + pair_dy * c
        inside = self.inside(seen)
        counts = np.bincount(k[inside], minlength=len(steps))
        hits = np.flatnonzero(counts >= self.min_points)
        if len(hits) == 0:
            return -1.0, _NO_POINTS
        first = int(hits[0])
        return times[int(steps[first])], near[i[(k == first) & inside]]

    def reach(self) -> float:
        """The furthest any point of the zone is from the robot's origin."""
        return self.shape().reach

    def __repr__(self) -> str:
        return f"{type(self).__name__}({self.name!r}, {self.params.action_type})"
