"""Inside tests for many points at once, and the circle's outline (nav2_util's
isPointInsidePolygon and the collision monitor's circleToPolygon)."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..core import fmath

#: Edges of the polygon a circle is drawn as (Nav2's Circle::getPolygon).
CIRCLE_EDGES = 16


class Outline:
    """A polygon's vertices (V, 2) and what every inside test of them needs (its edges,
    bounding box and reach), worked out once: a zone keeps one while its shape holds.

    `contains` is Nav2's ray-crossing rule (nav2_util's isPointInsidePolygon), edge
    (i, j) counted when `(py <= yi) == (py > yj)` and the crossing lies right of the
    point, so points on an edge fall as in Nav2. A point outside the bounding box (by
    more than rounding) crosses an even number of edges, so it is outside without the
    edges; the rest (usually few: a zone holds few of the points a lidar sees) go
    against all edges at once, no loop over points.
    """

    def __init__(self, vertices: ArrayLike) -> None:
        v = np.asarray(vertices, dtype=float).reshape(-1, 2)
        self.vertices = v
        previous = v[np.arange(-1, len(v) - 1)]  # edge i -> j, i the previous vertex
        self._xi, self._yi = previous[:, 0], previous[:, 1]
        self._xj, self._yj = v[:, 0], v[:, 1]
        self._run = self._xj - self._xi
        dy = self._yj - self._yi
        self._rise = np.where(dy == 0.0, 1.0, dy)  # such an edge never spans: unused
        #: The furthest any vertex is from the origin (0 for no vertices).
        self.reach = 0.0
        if len(v):
            self.reach = float(np.sqrt(np.max(v[:, 0] * v[:, 0] + v[:, 1] * v[:, 1])))
            # a crossing's x is within rounding of its edge's ends: 1e-9 of the extent is plenty
            margin = 1e-9 * (1.0 + float(np.abs(v).max()))
            (self._x_low, self._y_low), (self._x_high, self._y_high) = v.min(axis=0), v.max(axis=0)
            self._x_low -= margin
            self._x_high += margin

    def contains(self, points: ArrayLike) -> NDArray[np.bool_]:
        """Which of `points` (..., 2) are inside."""
        p = np.asarray(points, dtype=float)
        out = np.zeros(p.shape[:-1], dtype=bool)
        if len(self.vertices) == 0 or p.size == 0:
            return out
        px, py = p[..., 0], p[..., 1]
        box = (py >= self._y_low) & (py <= self._y_high)
        box &= px >= self._x_low
        box &= px <= self._x_high
        candidates = p[box]
        px, py = candidates[:, 0, None], candidates[:, 1, None]  # (K, 1) against (V,)
        spans = (py <= self._yi) == (py > self._yj)
        x_inter = self._xi + (py - self._yi) * self._run / self._rise
        crossings = np.count_nonzero(spans & (x_inter > px), axis=-1)
        out[box] = (crossings % 2) == 1
        return out


def points_in_polygon(points: ArrayLike, vertices: ArrayLike) -> NDArray[np.bool_]:
    """Which of `points` (..., 2) are inside the polygon `vertices` (V, 2) (`Outline`)."""
    return Outline(vertices).contains(points)


def points_in_circle(points: ArrayLike, radius: float) -> NDArray[np.bool_]:
    """Which of `points` (..., 2) are strictly inside the circle of `radius` at the origin."""
    p = np.asarray(points, dtype=float)
    return p[..., 0] * p[..., 0] + p[..., 1] * p[..., 1] < radius * radius


def circle_outline(radius: float, edges: int = CIRCLE_EDGES) -> NDArray[np.float64]:
    """The `edges`-gon a circle zone is drawn as, its first vertex on +x."""
    s, c = fmath.sincos(np.arange(edges) * (2.0 * math.pi / edges))
    return np.stack([radius * c, radius * s], axis=-1)
