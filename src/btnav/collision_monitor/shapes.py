"""Inside tests for many points at once, and the circle's outline (nav2_util's
isPointInsidePolygon and the collision monitor's circleToPolygon)."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..core import fmath

#: Edges of the polygon a circle is drawn as (Nav2's Circle::getPolygon).
CIRCLE_EDGES = 16


def points_in_polygon(points: ArrayLike, vertices: ArrayLike) -> NDArray[np.bool_]:
    """Which of `points` (..., 2) are inside the polygon `vertices` (V, 2).

    Nav2's ray-crossing rule, edge (i, j) counted when `(py <= yi) == (py > yj)` and
    the crossing lies right of the point, so points on an edge fall as in Nav2. All
    points against all edges at once: (..., V) arrays, no loop over points.
    """
    p = np.asarray(points, dtype=float)
    v = np.asarray(vertices, dtype=float)
    if len(v) == 0 or p.size == 0:
        return np.zeros(p.shape[:-1], dtype=bool)
    xi, yi = np.roll(v[:, 0], 1), np.roll(v[:, 1], 1)  # edge i -> j, i the previous vertex
    xj, yj = v[:, 0], v[:, 1]
    px, py = p[..., 0, None], p[..., 1, None]
    spans = (py <= yi) == (py > yj)
    dy = yj - yi
    safe = np.where(dy == 0.0, 1.0, dy)  # such an edge never spans: its value is unused
    x_inter = xi + (py - yi) * (xj - xi) / safe
    crossings = np.count_nonzero(spans & (x_inter > px), axis=-1)
    return (crossings % 2) == 1


def points_in_circle(points: ArrayLike, radius: float) -> NDArray[np.bool_]:
    """Which of `points` (..., 2) are strictly inside the circle of `radius` at the origin."""
    p = np.asarray(points, dtype=float)
    return p[..., 0] * p[..., 0] + p[..., 1] * p[..., 1] < radius * radius


def circle_outline(radius: float, edges: int = CIRCLE_EDGES) -> NDArray[np.float64]:
    """The `edges`-gon a circle zone is drawn as, its first vertex on +x."""
    s, c = fmath.sincos(np.arange(edges) * (2.0 * math.pi / edges))
    return np.stack([radius * c, radius * s], axis=-1)
