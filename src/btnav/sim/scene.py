"""Turn a world spec into solids: convex parts for pymunk and outlines for sensors and maps.

Physics needs convex pieces (pymunk's `Poly` is convex); a lidar or a rasteriser
wants the outline a user drew, without the seams between pieces. Both come from
here, once, so the physics, the scans and the map agree on where everything is.
No pymunk space is built here: `rasterize` uses this without a physics world.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray
from pymunk.autogeometry import convex_decomposition

from ..core import fmath
from .geometry import Geometry
from .world_spec import (
    BoxSpec,
    CircleSpec,
    MovesSpec,
    PolygonSpec,
    WallSpec,
    WorldSpec,
    signed_area,
)

Array = NDArray[np.float64]


def _no_circles() -> Array:
    return np.zeros((0, 3))


@dataclass
class Solid:
    """One wall or obstacle. Shapes are relative to `origin` (its reference point in the
    world at the start: the centre of a box or circle, the area centroid of a polygon,
    (0, 0) for a wall), so a moving obstacle is its shapes plus its current position."""

    label: str  # for messages: "obstacles[3] (box)"
    key: tuple[str | int, ...]  # its key path in the world file
    origin: Array
    parts: list[Array]  # convex polygons, counter-clockwise (physics)
    outlines: list[Array]  # what sensors and maps see
    circles: Array = field(default_factory=_no_circles)  # (M, 3): x, y, r
    moves: MovesSpec | None = None


def box_corners(center: tuple[float, float], size: tuple[float, float], yaw: float) -> Array:
    """The four corners of a box, counter-clockwise."""
    hx, hy = size[0] / 2.0, size[1] / 2.0
    lx = np.array([-hx, hx, hx, -hx])
    ly = np.array([-hy, -hy, hy, hy])
    s, c = fmath.sincos(float(yaw))
    cx, cy = (float(v) for v in center)
    out = np.empty((4, 2))
    out[:, 0] = c * lx - s * ly + cx  # rotated by yaw (explicit products: not BLAS)
    out[:, 1] = s * lx + c * ly + cy
    return out


def is_convex(points: Array) -> bool:
    """Whether a counter-clockwise simple polygon turns left (or goes straight) at every vertex."""
    d1 = np.roll(points, -1, axis=0) - points
    d2 = np.roll(d1, -1, axis=0)
    cross = d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]
    scale = float(np.abs(points).max()) or 1.0
    return bool(np.all(cross >= -1e-12 * scale * scale))


def _ear_clip(points: Array) -> list[Array]:
    """Triangles of a counter-clockwise simple polygon (fallback when pymunk's decomposition fails)."""
    idx = list(range(len(points)))
    tris: list[Array] = []

    def cross(o: Array, a: Array, b: Array) -> float:
        return float((a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]))

    guard = 0
    while len(idx) > 3 and guard < 10 * len(points) ** 2:
        guard += 1
        for n in range(len(idx)):
            i0, i1, i2 = idx[n - 1], idx[n], idx[(n + 1) % len(idx)]
            a, b, c = points[i0], points[i1], points[i2]
            if cross(a, b, c) <= 0:
                continue
            inside = False
            for j in idx:
                if j in (i0, i1, i2):
                    continue
                p = points[j]
                if cross(a, b, p) >= 0 and cross(b, c, p) >= 0 and cross(c, a, p) >= 0:
                    inside = True
                    break
            if not inside:
                tris.append(np.array([a, b, c]))
                idx.pop(n)
                break
        else:
            break  # numerically stuck: keep what we have and take the rest as one piece
    if len(idx) >= 3:
        tris.append(points[idx])
    return tris


def convex_parts(points: Array) -> list[Array]:
    """Convex pieces of a simple polygon (any winding), counter-clockwise, for pymunk."""
    pts = np.asarray(points, dtype=float)
    if signed_area(pts) < 0:
        pts = pts[::-1].copy()
    if is_convex(pts):
        return [pts]
    closed = [(float(x), float(y)) for x, y in pts] + [(float(pts[0, 0]), float(pts[0, 1]))]
    try:
        hulls = convex_decomposition(closed, 0.0)
        parts = [np.array([(v.x, v.y) for v in h[:-1]]) for h in hulls]
        total = sum(abs(signed_area(p)) for p in parts if len(p) >= 3)
        if parts and math.isclose(total, abs(signed_area(pts)), rel_tol=1e-6, abs_tol=1e-9):
            return [p for p in parts if len(p) >= 3 and abs(signed_area(p)) > 0]
    except Exception:  # pymunk asserts on inputs it cannot take; the fallback always works
        pass
    return _ear_clip(pts)


#: Wall points closer than this (m) are one point: a shorter edge has no direction.
MIN_EDGE = 1e-9


def wall_pieces(wall: WallSpec) -> tuple[list[Array], Array]:
    """A wall as one rectangle per edge (butt ends) plus a circle at every joint (round joins)."""
    pts = np.asarray(wall.points, dtype=float)
    keep = np.ones(len(pts), dtype=bool)
    keep[1:] = fmath.hypot(*np.diff(pts, axis=0).T) > MIN_EDGE  # drop repeated points
    pts = pts[keep]
    half = wall.thickness / 2.0
    rects: list[Array] = []
    for a, b in itertools.pairwise(pts):
        d = b - a
        n = np.array([-d[1], d[0]]) * (half / fmath.hypot(d[0], d[1]))
        rects.append(np.array([a - n, b - n, b + n, a + n]))  # counter-clockwise
    closed = len(pts) > 2 and np.array_equal(pts[0], pts[-1])
    joints = pts[1:-1] if not closed else pts[:-1]
    circles = (
        np.column_stack([joints, np.full(len(joints), half)]) if len(joints) else _no_circles()
    )
    return rects, circles


def build_solids(spec: WorldSpec) -> list[Solid]:
    """Every wall and obstacle of the world, in file order."""
    solids: list[Solid] = []
    zero = np.zeros(2)
    for i, wall in enumerate(spec.walls):
        rects, circles = wall_pieces(wall)
        solids.append(Solid(f"walls[{i}]", ("walls", i), zero.copy(), rects, rects, circles))
    for i, entry in enumerate(spec.obstacles):
        shape = entry.shape
        label, key = f"obstacles[{i}] ({entry.kind})", ("obstacles", i)
        if isinstance(shape, BoxSpec):
            origin = np.asarray(shape.center, dtype=float)
            corners = box_corners(shape.center, shape.size, shape.yaw) - origin
            solids.append(Solid(label, key, origin, [corners], [corners], moves=shape.moves))
        elif isinstance(shape, CircleSpec):
            origin = np.asarray(shape.center, dtype=float)
            circle = np.array([[0.0, 0.0, shape.radius]])
            solids.append(Solid(label, key, origin, [], [], circle, moves=shape.moves))
        else:
            assert isinstance(shape, PolygonSpec)
            pts = np.asarray(shape.points, dtype=float)
            if signed_area(pts) < 0:
                pts = pts[::-1]  # solids wind counter-clockwise (see Geometry.one_sided)
            origin = polygon_centroid(pts)
            local = pts - origin
            solids.append(
                Solid(label, key, origin, convex_parts(local), [local], moves=shape.moves)
            )
    for i, (x0, y0, x1, y1) in enumerate(spec.map_boxes):  # a world made from a map image
        origin = np.array([(x0 + x1) / 2, (y0 + y1) / 2])
        corners = box_corners((0.0, 0.0), (x1 - x0, y1 - y0), 0.0)
        solids.append(Solid(f"map cells [{i}]", ("map", i), origin, [corners], [corners]))
    return solids


def polygon_centroid(points: Array) -> Array:
    """The area centroid of a simple polygon (the reference point a moving polygon's path follows)."""
    p = np.asarray(points, dtype=float)
    q = np.roll(p, -1, axis=0)
    cross = p[:, 0] * q[:, 1] - q[:, 0] * p[:, 1]
    area = cross.sum() / 2.0
    if abs(area) < 1e-12:
        return p.mean(axis=0)
    return np.array(
        [
            ((p[:, 0] + q[:, 0]) * cross).sum() / (6 * area),
            ((p[:, 1] + q[:, 1]) * cross).sum() / (6 * area),
        ]
    )


def solids_geometry(solids: list[Solid], positions: list[Array] | None = None) -> Geometry:
    """The outlines and circles of `solids`, each placed at its position (default: its origin)."""
    polygons: list[Array] = []
    circles: list[Array] = []
    for n, solid in enumerate(solids):
        pos = solid.origin if positions is None else positions[n]
        polygons += [o + pos for o in solid.outlines]
        if len(solid.circles):
            c = solid.circles.copy()
            c[:, :2] += pos
            circles.append(c)
    return Geometry(polygons, np.vstack(circles) if circles else _no_circles(), one_sided=True)
