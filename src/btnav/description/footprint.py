"""The footprint: the base link's collision geometry projected onto the ground.

The base link is the description's `base_link` (else its root link); when it carries
no collision geometry itself but is welded by a fixed joint to exactly one other link
(a `chassis`), that link's is used. Boxes, cylinders and spheres are projected exactly
and joined into their convex hull, which is what Nav2's `footprint` polygon holds; one
upright cylinder or a sphere centred on the base frame is a disc (`robot_radius`).
Meshes are not read (no mesh library is a dependency): a base made only of meshes has
no footprint, and the world's `footprint:` is used.
"""

from __future__ import annotations

import numpy as np

from ..core import fmath
from .model import Geometry, RobotModel
from .robot_description import FootprintDescription
from .transforms import Transform, apply, compose, up_of

#: Points on a cylinder's or sphere's outline when it joins a polygon.
CIRCLE_POINTS = 32
#: Coordinates are rounded to this many decimals (a micrometre): sums like -0.032 - 0.07
#: read back as the -0.102 the file means, and the polygon is the same on every machine.
DECIMALS = 6


def body_link(model: RobotModel) -> str:
    """The link whose collision geometry is the footprint (see the module docstring)."""
    link = "base_link" if "base_link" in model.links else model.root
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


def read_footprint(model: RobotModel, poses: dict[str, Transform]) -> FootprintDescription | None:
    """The footprint in the base frame (`poses`: each link's pose there), or None."""
    link = body_link(model)
    shapes = [g for g in model.links[link].collisions if g.kind != "mesh"]
    if not shapes:
        return None
    pose = poses[link]
    first = shapes[0]
    source = " + ".join(dict.fromkeys(g.kind for g in shapes))
    if len(shapes) == 1 and first.kind in ("cylinder", "sphere"):
        place = compose(pose, first.pose)
        cx, cy, _ = apply(place, (0.0, 0.0, 0.0))
        upright = first.kind == "sphere" or abs(up_of(place)) > 1.0 - 1e-9
        if upright and abs(cx) < 1e-9 and abs(cy) < 1e-9:
            r = round(float(first.size[0]), DECIMALS)
            return FootprintDescription(r, None, link, source, first.file, first.line)
    hull = convex_hull(np.concatenate([_points(g, pose) for g in shapes]))
    if len(hull) < 3:
        return None
    polygon = tuple((float(x) + 0.0, float(y) + 0.0) for x, y in hull)  # + 0.0: no -0.0
    return FootprintDescription(None, polygon, link, source, first.file, first.line)
