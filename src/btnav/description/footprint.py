"""The footprint: the base link's collision geometry projected onto the ground.

The base link is the description's `base_link` (else its root link); when it carries
no collision geometry itself but is welded by a fixed joint to exactly one other link
(a `chassis`), that link's is used. Boxes, cylinders and spheres are projected exactly
and joined into their convex hull, which is what Nav2's `footprint` polygon holds; one
upright cylinder or a sphere centred on the base frame is a disc (`robot_radius`).
A mesh joins the hull with its vertices (scaled by its `<scale>`, placed at the
collision's pose; read by `meshes`, trimesh in the `btnav[meshes]` extra), and that hull
is thinned of the points within `MESH_TOLERANCE` of their neighbours' chord: a CAD
mesh gives a vertex per facet. A mesh that cannot be read (no trimesh, a missing or
broken file) is one warning naming it, and the description then gives no footprint, so
the world's `footprint:` is used rather than the hull of what is left.
"""

from __future__ import annotations

import warnings

import numpy as np

from ..core import fmath
from ..core.errors import BtnavWarning
from .meshes import MeshError, MeshSources
from .model import Geometry, RobotModel
from .robot_description import FootprintDescription
from .transforms import Transform, apply, compose, up_of

#: Points on a cylinder's or sphere's outline when it joins a polygon.
CIRCLE_POINTS = 32
#: Coordinates are rounded to this many decimals (a micrometre): sums like -0.032 - 0.07
#: read back as the -0.102 the file means, and the polygon is the same on every machine.
DECIMALS = 6
#: A mesh's hull keeps the points farther than this (m) from the chord of their kept
#: neighbours: it stays within a millimetre of the true hull (costmap cells are 5 cm)
#: and a finely tessellated cylinder does not give Nav2 a footprint of 500 edges.
MESH_TOLERANCE = 1e-3


def body_link(model: RobotModel) -> str:
    """The link whose collision geometry is the footprint (see the module docstring)."""
    link = model.find("base_link") or model.root
    seen = {link}
    while not model.links[link].collisions:
        fixed = [j for j in model.child_joints(link) if j.kind == "fixed"]
        if len(fixed) != 1 or fixed[0].child in seen:
            break
        link = fixed[0].child
        seen.add(link)
    return link


def _circle(n: int = CIRCLE_POINTS) -> np.ndarray:
    s, c = fmath.sincos(np.arange(n) * (2.0 * np.pi / n))
    return np.stack([c, s], axis=1)


def _points(g: Geometry, pose: Transform) -> np.ndarray:
    """Points of the shape (in the base frame) whose 2D convex hull is its outline."""
    place = compose(pose, g.pose)
    if g.kind == "box":
        hx, hy, hz = (0.5 * s for s in g.size)
        local = [(sx * hx, sy * hy, sz * hz) for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]
    elif g.kind == "cylinder":
        r, h = g.size
        ring = _circle() * r
        local = [(x, y, z) for z in (-0.5 * h, 0.5 * h) for x, y in ring]
    else:  # sphere: its outline from above is a circle around its centre
        cx, cy, _ = apply(place, (0.0, 0.0, 0.0))
        return _circle() * g.size[0] + (cx, cy)
    return np.array([apply(place, p)[:2] for p in local])


def convex_hull(points: np.ndarray) -> np.ndarray:
    """Counter-clockwise hull (Andrew's monotone chain), starting at the lowest-left point."""
    pts = np.unique(np.round(points, DECIMALS), axis=0)  # sorted by x, then y
    if len(pts) < 3:
        return pts

    def half(seq: np.ndarray) -> list[np.ndarray]:
        out: list[np.ndarray] = []
        for p in seq:
            while len(out) >= 2:
                (ax, ay), (bx, by) = out[-2], out[-1]
                if (bx - ax) * (p[1] - ay) - (by - ay) * (p[0] - ax) > 1e-12:
                    break
                out.pop()
            out.append(p)
        return out

    lower, upper = half(pts), half(pts[::-1])
    return np.array(lower[:-1] + upper[:-1])


def _mesh_points(g: Geometry, pose: Transform, link: str, meshes: MeshSources) -> np.ndarray | None:
    """The mesh's vertices in the base frame, seen from above; None (and a warning) if unread."""
    try:
        v = meshes.scaled_vertices(g)
    except MeshError as exc:
        warnings.warn(
            BtnavWarning(
                f"cannot read the collision mesh '{g.uri}' of link '{link}': {exc}; the "
                "description gives no footprint, so the world's `footprint:` is used",
                file=g.file,
                line=g.line,
            ),
            stacklevel=4,
        )
        return None
    (r0, r1, _), t = compose(pose, g.pose)
    x = r0[0] * v[:, 0] + r0[1] * v[:, 1] + r0[2] * v[:, 2] + t[0]  # elementwise: no BLAS
    y = r1[0] * v[:, 0] + r1[1] * v[:, 1] + r1[2] * v[:, 2] + t[1]
    points = np.stack([x, y], axis=1)
    from scipy.spatial import ConvexHull, QhullError  # only when a mesh is read

    try:  # qhull keeps the outline's few points of a CAD mesh's thousands
        return points[ConvexHull(points).vertices]
    except QhullError:  # flat from above (a plate seen edge-on): all on one line
        return points


def _thin(hull: np.ndarray, tol: float = MESH_TOLERANCE) -> np.ndarray:
    """The hull's corners without those within `tol` of their neighbours' chord
    (Douglas-Peucker on the closed outline: every dropped point stays within `tol`)."""
    n = len(hull)
    if n <= 4:
        return hull
    keep = np.zeros(n, dtype=bool)
    far = int(np.argmax(fmath.hypot(*(hull - hull[0]).T)))
    keep[[0, far]] = True
    chains = [(0, far), (far, n)]  # index n is point 0 again
    closed = np.concatenate([hull, hull[:1]])
    while chains:
        a, b = chains.pop()
        if b - a < 2:
            continue
        p, q = closed[a], closed[b]
        mid = closed[a + 1 : b]
        d = q - p
        dist = np.abs(d[0] * (mid[:, 1] - p[1]) - d[1] * (mid[:, 0] - p[0])) / fmath.hypot(*d)
        i = int(np.argmax(dist))
        if dist[i] > tol:
            k = a + 1 + i
            keep[k % n] = True
            chains += [(a, k), (k, b)]
    return hull[keep] if keep.sum() >= 3 else hull


def read_footprint(
    model: RobotModel, poses: dict[str, Transform], meshes: MeshSources | None = None
) -> FootprintDescription | None:
    """The footprint in the base frame (`poses`: each link's pose there), or None."""
    link = body_link(model)
    shapes = model.links[link].collisions
    if not shapes:
        return None
    pose = poses[link]
    first = shapes[0]
    source = " + ".join(dict.fromkeys(g.kind for g in shapes))
    solids = [g for g in shapes if g.kind != "mesh"]
    mesh_shapes = [g for g in shapes if g.kind == "mesh"]
    if not mesh_shapes and len(solids) == 1 and first.kind in ("cylinder", "sphere"):
        place = compose(pose, first.pose)
        cx, cy, _ = apply(place, (0.0, 0.0, 0.0))
        upright = first.kind == "sphere" or abs(up_of(place)) > 1.0 - 1e-9
        if upright and abs(cx) < 1e-9 and abs(cy) < 1e-9:
            r = round(float(first.size[0]), DECIMALS)
            return FootprintDescription(r, None, link, source, first.file, first.line)
    parts = [_points(g, pose) for g in solids]
    sources = meshes or MeshSources()
    read = [_mesh_points(g, pose, link, sources) for g in mesh_shapes]
    if any(r is None for r in read):
        return None
    parts += [r for r in read if r is not None]
    hull = convex_hull(np.concatenate(parts))
    if mesh_shapes:
        hull = _thin(hull)
    if len(hull) < 3:
        return None
    polygon = tuple((float(x) + 0.0, float(y) + 0.0) for x, y in hull)  # + 0.0: no -0.0
    return FootprintDescription(None, polygon, link, source, first.file, first.line)
