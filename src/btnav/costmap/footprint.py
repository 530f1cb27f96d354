"""Robot footprints as Nav2's costmap handles them (nav2_costmap_2d/footprint.hpp).

A footprint is an (N, 2) polygon in the robot frame. `robot_radius` becomes a
16-gon, padding moves every vertex outwards by `footprint_padding` along x and y,
and the inscribed/circumscribed radii are the nearest edge and farthest vertex.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..core import fmath
from ..core.geometry import Pose2D
from .costmap_2d import Costmap2D

#: Vertices of the polygon Nav2 makes from robot_radius.
RADIUS_VERTICES = 16


def footprint_from_radius(radius: float) -> NDArray[np.float64]:
    """The 16-gon Nav2 uses for a circular robot (makeFootprintFromRadius)."""
    a = np.arange(RADIUS_VERTICES) * (2.0 * math.pi / RADIUS_VERTICES)
    s, c = fmath.sincos(a)
    return np.stack([radius * c, radius * s], axis=-1)


def pad_footprint(footprint: ArrayLike, padding: float) -> NDArray[np.float64]:
    """Every vertex `padding` further out along x and y (Nav2's padFootprint, sign-wise)."""
    fp = np.asarray(footprint, dtype=float).reshape(-1, 2)
    return fp + np.sign(fp) * padding


def min_max_distances(footprint: ArrayLike) -> tuple[float, float]:
    """(inscribed, circumscribed) radius: nearest edge and farthest vertex from the origin."""
    fp = np.asarray(footprint, dtype=float).reshape(-1, 2)
    if len(fp) == 0:
        return 0.0, 0.0
    vertex = fmath.hypot(fp[:, 0], fp[:, 1])
    if len(fp) < 2:
        return float(vertex.min()), float(vertex.max())
    a, b = fp, np.roll(fp, -1, axis=0)
    ab = b - a
    den = fmath.dot_rows(ab, ab)
    t = np.clip(np.where(den > 0, -fmath.dot_rows(a, ab) / np.where(den > 0, den, 1), 0), 0, 1)
    closest = a + t[:, None] * ab
    edge = fmath.hypot(closest[:, 0], closest[:, 1])
    return float(min(vertex.min(), edge.min())), float(vertex.max())


def transform_footprint(pose: Pose2D, footprint: ArrayLike) -> NDArray[np.float64]:
    return pose.transform_points(np.asarray(footprint, dtype=float).reshape(-1, 2))


def polygon_cells(
    costmap: Costmap2D, polygon: ArrayLike
) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """(my, mx) of the cells a world polygon covers: its outline and its inside.

    Like Nav2's convexFillCells: every cell the outline passes through, plus every
    cell whose centre is inside. Vectorised over the polygon's bounding box.
    """
    poly = np.asarray(polygon, dtype=float).reshape(-1, 2)
    if len(poly) == 0:
        return np.zeros(0, np.int64), np.zeros(0, np.int64)
    res = costmap.resolution
    ox, oy = costmap.origin_x, costmap.origin_y
    size_y, size_x = costmap.costs.shape
    # The outline, sampled finer than a cell.
    a = poly
    b = np.concatenate((poly[1:], poly[:1]))  # np.roll(poly, -1, axis=0)
    ab = b - a
    n = np.maximum(np.ceil(fmath.hypot(ab[:, 0], ab[:, 1]) / (0.25 * res)).astype(int), 1)
    seg, t = _outline_steps(n)
    # its cells (costmap.world_to_map, x and y apart; 0 <= m < size as one unsigned test)
    mx = np.floor((a[seg, 0] + t * ab[seg, 0] - ox) / res).astype(np.int64)
    my = np.floor((a[seg, 1] + t * ab[seg, 1] - oy) / res).astype(np.int64)
    inside = mx.view(np.uint64) < size_x
    inside &= my.view(np.uint64) < size_y
    ys_out, xs_out = my[inside], mx[inside]
    # The inside: cell centres in the bounding box, even-odd rule. (The box's corner
    # cells as world_to_map finds them, one point at a time.)
    px, py = poly[:, 0].tolist(), poly[:, 1].tolist()
    min_x, min_y, max_x, max_y = min(px), min(py), max(px), max(py)
    x0 = max(math.floor((min_x - ox) / res), 0)
    y0 = max(math.floor((min_y - oy) / res), 0)
    x1 = min(math.floor((max_x - ox) / res) + 1, size_x)
    y1 = min(math.floor((max_y - oy) / res) + 1, size_y)
    if x0 < x1 and y0 < y1:
        # costmap.cell_centers(x0, y0, x1, y1)
        cx = (ox + (np.arange(x0, x1) + 0.5) * res)[None, :]
        cy = (oy + (np.arange(y0, y1) + 0.5) * res)[:, None]
        # Every edge against every cell centre at once: (edges, rows, cols).
        ax, ay = a[:, 0, None, None], a[:, 1, None, None]
        bx, by = b[:, 0, None, None], b[:, 1, None, None]
        crosses = (ay > cy) != (by > cy)
        rise = by - ay
        rise[rise == 0] = 1.0  # a level edge crosses no row: any divisor does
        xint = ax + (cy - ay) * (bx - ax) / rise
        inside_poly = np.logical_xor.reduce(crosses & (cx < xint), axis=0)
        iy, ix = np.nonzero(inside_poly)
        return np.concatenate([ys_out, iy + y0]), np.concatenate([xs_out, ix + x0])
    return ys_out, xs_out


_STEPS: dict[bytes, tuple[NDArray[np.int64], NDArray[np.float64]]] = {}


def _outline_steps(n: NDArray[np.int64]) -> tuple[NDArray[np.int64], NDArray[np.float64]]:
    """For edges sampled in n[i] steps: each sample's edge and its fraction along it
    (kept per step counts: a footprint's edges keep their lengths as the robot moves)."""
    key = n.tobytes()
    found = _STEPS.get(key)
    if found is None:
        seg = np.repeat(np.arange(len(n)), n + 1)
        t = np.arange(seg.size) - np.repeat(np.cumsum(n + 1) - (n + 1), n + 1)
        found = (seg, t / np.repeat(n, n + 1))
        if len(_STEPS) > 256:
            _STEPS.clear()
        _STEPS[key] = found
    return found
