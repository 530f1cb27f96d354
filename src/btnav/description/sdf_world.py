"""A Gazebo world (classic `.world`, gz-sim `.sdf`): its collision shapes placed in the
world frame, its scripted actors, and each shape's section through a height band.

The `<world>` is read as the top model of a robot description is, so `sdf_include` and
`sdf_frames` expand includes and compose poses, and every element keeps its file and line
for a located `DescriptionError`. Scenery (lights, physics, ground planes, the sun) is left
out without a word, other network (Fuel) includes with one warning; a model named as the
robot is its spawn. `ground_shapes` cuts each collision by the band a 2D lidar sees and
projects the section onto the ground (boxes, circles, polygons, convex hulls; meshes are
not cut). Details: docs/decisions/0085.
"""

from __future__ import annotations

import contextlib
import math
import warnings
import xml.etree.ElementTree as ET
from collections.abc import Collection, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..core import fmath
from ..core.errors import BtnavWarning
from ..core.suggest import best_match
from .errors import DescriptionError
from .footprint import _thin, convex_hull
from .gazebo_sensors import sdf_pose
from .meshes import MeshError, MeshSources
from .model import Geometry
from .model_paths import SCHEME, ModelPaths, split_uri
from .packages import PackagePaths
from .sdf_frames import Frames, Scope, read_scopes
from .sdf_include import RemoteInclude, expand_includes
from .sdf_reader import _geometry
from .source_lines import LINE_ATTR, SourceFiles, parse_with_lines, read_source, to_element_tree
from .transforms import Transform, compose, yaw_of
from .xml_values import child_number, child_text, error, floats, required, tag

#: Gazebo's own models, which a world names by `model://` and Gazebo always has.
SCENERY_MODELS = ("sun", "ground_plane")
#: Words of a Fuel model's name that make it scenery (`Ground Plane`, `Sun`).
SCENERY_WORDS = ("ground", "plane", "sun")
#: Sides of the prism that stands for a cylinder cut by the band (circumscribed, so the
#: section never falls inside the true one; 0.5% wider at most).
PRISM_SIDES = 32
#: Coordinates are rounded to a micrometre, as the footprint's are: the same shapes on
#: every machine, and a converted world's YAML reads back to the same bits.
DECIMALS = 6
#: How vertical an axis must be (the cosine) to count as upright.
UPRIGHT = 1.0 - 1e-9
#: The smallest side or radius a shape gets (`WorldSpec`'s MIN_SIZE).
MIN_SIZE = 1e-3


@dataclass(frozen=True)
class WorldCollision:
    """One `<collision>`, its geometry posed in the world frame."""

    name: str  # scoped: `table_1::leg::collision`
    model: str  # the top-level model it belongs to
    geometry: Geometry  # kind box | cylinder | sphere | mesh | polyline; pose in the world
    #: a polyline's outlines (in the collision frame) and `geometry.size` its (height,)
    polylines: tuple[tuple[tuple[float, float], ...], ...] = ()
    #: the line of its top-level `<model>`/`<include>` in the world file
    model_line: int | None = None


@dataclass(frozen=True)
class ActorTrajectory:
    """An `<actor>`'s scripted trajectory: (time, x, y, yaw) waypoints in time order."""

    name: str
    waypoints: tuple[tuple[float, float, float, float], ...]
    loop: bool
    file: str | None
    line: int | None


@dataclass(frozen=True)
class Spawn:
    """The top-level model or include that is the robot: where it starts."""

    name: str
    x: float
    y: float
    yaw: float
    file: str | None
    line: int | None


@dataclass(frozen=True)
class SdfWorld:
    """What stands in a Gazebo world, in its world frame."""

    name: str
    file: str
    collisions: tuple[WorldCollision, ...]
    actors: tuple[ActorTrajectory, ...]
    spawn: Spawn | None
    meshes: MeshSources
    line: int | None  # of the <world>


@dataclass(frozen=True)
class GroundShape:
    """A collision's section through the band, seen from above (a `WorldSpec` obstacle)."""

    kind: str  # box | circle | polygon
    source: str  # the collision's scoped name
    file: str | None
    line: int | None
    center: tuple[float, float] = (0.0, 0.0)
    size: tuple[float, float] = (0.0, 0.0)  # a box's
    yaw: float = 0.0  # a box's
    radius: float = 0.0  # a circle's
    points: tuple[tuple[float, float], ...] = ()  # a polygon's, counter-clockwise


class WorldModelPaths(ModelPaths):
    """Gazebo's model paths, and last the `models/` folders beside the world file (its own
    folder's and its parent's: ROBOTIS's `worlds/` and `models/` sit side by side)."""

    def __init__(self, given: ModelPaths, world: Path) -> None:
        super().__init__(given.given, None)
        here = world.resolve().parent
        beside = [here / "models", here.parent / "models"]
        object.__setattr__(self, "_beside", tuple(p for p in beside if p.is_dir()))

    def search(self) -> list[tuple[Path, str]]:
        return [*super().search(), *((p, "beside the world") for p in self._beside)]


def _norm(name: str) -> str:
    return name.strip().lower().replace(" ", "_")


def _warn(message: str, element: ET.Element | None, sources: SourceFiles) -> None:
    file, line = sources.place(element)
    warnings.warn(BtnavWarning(message, file=file, line=line), stacklevel=3)


def _is_scenery(remote: RemoteInclude) -> bool:
    words = {w for n in remote.names for w in _norm(n).replace("-", "_").split("_")}
    return bool(words & set(SCENERY_WORDS))


def _include_name(include: ET.Element) -> str | None:
    """The include's `<name>`, else the NAME of its `model://NAME` (None for a path)."""
    name = child_text(include, "name")
    if name:
        return name
    uri = child_text(include, "uri") or ""
    return split_uri(uri)[0] if uri.startswith(SCHEME) else None


def _robot_placeholder(include: ET.Element, name: str) -> ET.Element:
    """An empty model standing for the robot's include: only its name and pose matter."""
    model = ET.Element("model", {"name": name, LINE_ATTR: include.get(LINE_ATTR, "")})
    pose = include.find("pose")
    if pose is not None:
        model.append(pose)
    return model


def _warn_remote(remotes: Sequence[RemoteInclude]) -> None:
    """One warning per Fuel include that is not a ground plane or a sun."""
    for remote in remotes:
        if not _is_scenery(remote):
            warnings.warn(
                BtnavWarning(
                    f"the model at {remote.uri} is left out of the world: btnav reads nothing "
                    f"from the network (download it with gz fuel download --url "
                    f"'{remote.uri}' and include it by model://)",
                    file=remote.file,
                    line=remote.line,
                ),
                stacklevel=4,
            )


def _expand_include(
    include: ET.Element, file: str, sources: SourceFiles, models: ModelPaths
) -> ET.Element | None:
    """The model a top-level include stands for (None: scenery, or nothing btnav can read)."""
    uri = child_text(include, "uri") or ""
    if uri.startswith(SCHEME) and models.find_model(uri) is None:
        name, _ = split_uri(uri)
        if name in SCENERY_MODELS:
            return None  # Gazebo's own sun or ground plane, not installed here
        raise error(
            f"{uri} not found: no model folder {name}/ in the model paths (searched "
            f"{models.searched()}); add the folder that holds {name}/ to GZ_SIM_RESOURCE_PATH "
            "(or to `model_paths:` of a world file that names this world by `sdf:`), or, "
            "if it is the robot, give the mission a `robot:` with its description",
            include.find("uri"),
            sources,
            suggestion=best_match(name, models.known()),
        )
    holder = ET.Element("model", {"name": "__include__"})
    holder.append(include)
    _warn_remote(expand_includes(holder, file, sources, models))
    inner = [el for el in holder if el.tag == "model"]
    return inner[0] if inner else None


def _top_model(
    world: ET.Element,
    file: str,
    sources: SourceFiles,
    models: ModelPaths,
    robot_names: Collection[str],
) -> tuple[ET.Element, dict[int, int | None], ET.Element | None]:
    """The synthetic model holding the world's models (includes expanded), the world-file
    line of each top-level model (by `id`), and the robot's model if the world has it."""
    top = ET.Element("model", {"name": world.get("name") or "world"})
    wanted = {_norm(n) for n in robot_names}
    lines: dict[int, int | None] = {}
    robot: ET.Element | None = None
    seen: dict[str, int | None] = {}
    for child in list(world):
        if child.tag not in ("model", "include", "frame"):
            if child.tag in ("population", "road"):
                _warn(f"<{child.tag}> is not read by btnav: it is left out", child, sources)
            continue
        _, line = sources.place(child)
        if child.tag == "frame":
            top.append(child)
            continue
        model: ET.Element | None = child
        is_robot = False
        if child.tag == "include":
            name = _include_name(child)
            uri = child_text(child, "uri") or ""
            uri_name = split_uri(uri)[0] if uri.startswith(SCHEME) else ""
            if wanted and {_norm(name or ""), _norm(uri_name)} & wanted:
                model, is_robot = _robot_placeholder(child, name or uri_name), True
            else:
                model = _expand_include(child, file, sources, models)
        if model is None:
            continue
        name = required(model, "name", sources)
        if name in seen:
            raise error(
                f"two models of the world are named '{name}' (the first at line "
                f"{seen[name]}); Gazebo refuses that: give the include a <name>",
                child,
                sources,
            )
        seen[name] = line
        if _norm(name) in wanted:
            is_robot = True
        if is_robot and robot is None:
            robot = model
        lines[id(model)] = line
        top.append(model)
    return top, lines, robot


def _polylines(
    shape: ET.Element, sources: SourceFiles
) -> tuple[tuple[tuple[tuple[float, float], ...], ...], float]:
    """A `<polyline>` geometry's outlines and its height (SDF: from z = 0 up, default 1 m)."""
    outlines, height = [], 0.0
    for pl in shape.findall("geometry/polyline"):
        points = tuple(
            (p[0], p[1])
            for p in (
                floats(pt.text, 2, "polyline <point>", pt, sources) for pt in pl.findall("point")
            )
        )
        if len(points) < 3:
            raise error("a <polyline> needs at least 3 <point>s", pl, sources)
        outlines.append(points)
        height = max(height, child_number(pl, "height", sources, 1.0, positive=True) or 1.0)
    return tuple(outlines), height


def _placed(
    c: ET.Element, key: str, scope: Scope, frames: Frames, sources: SourceFiles
) -> tuple[Geometry, tuple[tuple[tuple[float, float], ...], ...]] | None:
    """A collision's geometry in its link's frame (and a polyline's outlines); None for a
    plane, and for a kind btnav cannot read (with one warning)."""
    geometry = c.find("geometry")
    kinds = [] if geometry is None else [g for g in geometry if isinstance(g.tag, str)]
    kind = tag(kinds[0]) if kinds else ""
    if kind == "polyline":
        polylines, height = _polylines(c, sources)
        file, line = sources.place(kinds[0])
        pose = frames.placed(c.find("pose"), key, c, scope)
        return Geometry("polyline", (height,), pose, file, line), polylines
    g = _geometry(c, frames, key, scope, sources)
    if g is not None:
        return g, ()
    if kind not in ("", "plane", "empty"):
        _warn(
            f"collision '{key}::{c.get('name')}': <{kind}> geometry is not read by btnav, "
            "so it is left out of the world",
            kinds[0],
            sources,
        )
    return None


def _collisions(
    scopes: list[Scope],
    frames: Frames,
    sources: SourceFiles,
    lines: dict[int, int | None],
    robot: ET.Element | None,
) -> list[WorldCollision]:
    """Every collision of every model but the robot's, posed in the world frame."""
    out: list[WorldCollision] = []
    top_of: dict[int, Scope] = {}  # each scope's top-level model
    for s in scopes[1:]:
        parent = s.parent if s.parent is not None else scopes[0]
        top_of[id(s.element)] = s if parent is scopes[0] else top_of[id(parent.element)]
    for s in scopes[1:]:
        owner = top_of[id(s.element)]
        if owner.element is robot:
            continue
        for link in s.element.findall("link"):
            key = s.key(required(link, "name", sources))
            in_world = frames.resolve(key, link)
            for c in link.findall("collision"):
                found = _placed(c, key, s, frames, sources)
                if found is None:
                    continue
                g, polylines = found
                placed = Geometry(g.kind, g.size, compose(in_world, g.pose), g.file, g.line, g.uri)
                name = f"{key}::{c.get('name') or 'collision'}"
                model_line = lines.get(id(owner.element))
                out.append(WorldCollision(name, owner.name, placed, polylines, model_line))
    return out


def _actor(actor: ET.Element, sources: SourceFiles) -> ActorTrajectory | None:
    """An actor's scripted trajectory, its `<trajectory>`s played in `id` order (Gazebo's
    waypoints are world poses); None, with one warning, when it has none to play."""
    name = actor.get("name") or "actor"
    file, line = sources.place(actor)
    script = actor.find("script")
    trajectories = script.findall("trajectory") if script is not None else []
    why = None
    if not trajectories:
        why = "it has no scripted <trajectory> (a plugin moves it in Gazebo)"
    elif (child_text(script, "auto_start") or "true").lower() in ("false", "0"):
        why = "its script waits for a plugin to start it (<auto_start>false</auto_start>)"
    points: list[tuple[float, float, float, float]] = []
    if why is None:

        def order(t: ET.Element) -> float:
            try:
                return float(t.get("id") or 0)
            except ValueError:
                return 0.0

        offset = 0.0
        for traj in sorted(trajectories, key=order):
            own = []
            for wp in traj.findall("waypoint"):
                time = child_number(wp, "time", sources, 0.0) or 0.0
                pose = sdf_pose(wp.find("pose"), sources)
                own.append((time + offset, pose[1][0], pose[1][1], yaw_of(pose)))
            own.sort(key=lambda w: w[0])
            points += own
            offset = points[-1][0] if points else offset
        if len({(x, y) for _, x, y, _ in points}) < 2:
            why = "its trajectory has fewer than two places to go"
    if why is not None:
        warnings.warn(
            BtnavWarning(f"actor '{name}' is left out of the world: {why}", file=file, line=line),
            stacklevel=3,
        )
        return None
    loop = (child_text(script, "loop") or "true").lower() not in ("false", "0")
    return ActorTrajectory(name, tuple(points), loop, file, line)


def read_world(
    path: str | Path,
    model_paths: ModelPaths | None = None,
    robot_names: Collection[str] = (),
) -> SdfWorld:
    """Read a Gazebo world file; any mistake is a located `DescriptionError`.

    `robot_names`: the names the robot goes by (its description's name, its file's or
    model folder's): a top-level model or include of one of them is the `spawn`.
    """
    p = Path(path)
    if not p.is_file():
        raise DescriptionError("Gazebo world file not found", file=p)
    models = WorldModelPaths(model_paths or ModelPaths(), p)
    models.check()
    sources = SourceFiles()
    root = to_element_tree(parse_with_lines(read_source(p), str(p), sources.add(p)))
    if tag(root) != "sdf":
        raise error(f"a Gazebo world's top element is <sdf>, not <{tag(root)}>", root, sources)
    world = root.find("world")
    if world is None:
        what = "a model (a robot description?)" if root.find("model") is not None else "no <world>"
        raise error(f"this SDF file holds {what}: give a Gazebo world file", root, sources)
    top, lines, robot = _top_model(world, str(p), sources, models, robot_names)
    remote = expand_includes(top, str(p), sources, models)  # those inside inline models
    _warn_remote(remote)
    scopes = read_scopes(top, sources)
    frames = Frames(scopes, sources, remote)
    collisions = _collisions(scopes, frames, sources, lines, robot)
    actors = [a for a in (_actor(el, sources) for el in world.findall("actor")) if a is not None]
    spawn = None
    if robot is not None:
        scope = next(s for s in scopes if s.element is robot)
        placed = frames.resolve(scope.frame, robot)
        file, line = sources.place(robot.find("pose") if robot.find("pose") is not None else robot)
        spawn = Spawn(scope.name, placed[1][0], placed[1][1], yaw_of(placed), file, line)
    _, world_line = sources.place(world)
    return SdfWorld(
        name=world.get("name") or p.stem,
        file=str(p),
        collisions=tuple(collisions),
        actors=tuple(actors),
        spawn=spawn,
        meshes=MeshSources(PackagePaths(), models),
        line=world_line,
    )


# -- sections through the height band -------------------------------------------------


def _r(v: float) -> float:
    return round(float(v), DECIMALS) + 0.0  # + 0.0: no -0.0


def _world_points(pose: Transform, local: np.ndarray) -> np.ndarray:
    """Points given in a shape's frame, in the world (elementwise products: no BLAS)."""
    (r0, r1, r2), t = pose
    x, y, z = local[:, 0], local[:, 1], local[:, 2]
    return np.stack(
        [
            r0[0] * x + r0[1] * y + r0[2] * z + t[0],
            r1[0] * x + r1[1] * y + r1[2] * z + t[1],
            r2[0] * x + r2[1] * y + r2[2] * z + t[2],
        ],
        axis=1,
    )


def band_section(points: np.ndarray, lo: float, hi: float) -> np.ndarray:
    """(x, y) points whose convex hull is the convex solid hull(`points`) cut to lo <= z <= hi,
    seen from above: the points in the band, and where each segment between two points
    crosses z = lo or z = hi (every edge of the solid is such a segment)."""
    z = points[:, 2]
    out = [points[(z >= lo) & (z <= hi), :2]]
    i, j = np.triu_indices(len(points), 1)
    a, b = points[i], points[j]
    for level in (lo, hi):
        da, db = a[:, 2] - level, b[:, 2] - level
        cross = (da * db) < 0.0
        t = (da[cross] / (da[cross] - db[cross]))[:, None]
        out.append(a[cross, :2] + t * (b[cross, :2] - a[cross, :2]))
    return np.concatenate(out)


def _polygon(points: np.ndarray, c: WorldCollision, thin: bool = False) -> GroundShape | None:
    hull = convex_hull(points)
    if thin:
        hull = _thin(hull)
    if len(hull) < 3:
        return None
    x, y = hull[:, 0], hull[:, 1]
    area = 0.5 * float((x * np.roll(y, -1)).sum() - (np.roll(x, -1) * y).sum())
    if area < MIN_SIZE * MIN_SIZE:
        return None  # a plate seen edge-on
    g = c.geometry
    pts = tuple((_r(px), _r(py)) for px, py in hull)
    return GroundShape("polygon", c.name, g.file, g.line, points=pts)


def _circle_section(radius: float, z0: float, z1: float, lo: float, hi: float) -> float:
    """The widest section through the band of the points within `radius` of the vertical
    segment z0..z1 (a sphere: z0 = z1; a capsule); 0 when the band misses it."""
    if z1 >= lo and z0 <= hi:
        return radius
    d = lo - z1 if z1 < lo else z0 - hi
    return math.sqrt(radius * radius - d * d) if d < radius else 0.0


def _prism_ring(radius: float, sides: int = PRISM_SIDES) -> np.ndarray:
    s, c = fmath.sincos(np.arange(sides) * (2.0 * np.pi / sides))
    r = radius / fmath.cos(math.pi / sides)
    return np.stack([c * r, s * r], axis=1)


def _box(c: WorldCollision, lo: float, hi: float) -> GroundShape | None:
    g = c.geometry
    (rot, t) = g.pose
    half = [0.5 * v for v in g.size]
    vertical = [j for j in range(3) if abs(rot[2][j]) >= UPRIGHT]
    if vertical:
        j = vertical[0]
        if not (t[2] + half[j] > lo and t[2] - half[j] < hi):
            return None
        a, b = (k for k in range(3) if k != j)
        yaw = float(fmath.arctan2(rot[1][a], rot[0][a]))
        size = (max(_r(g.size[a]), MIN_SIZE), max(_r(g.size[b]), MIN_SIZE))
        return GroundShape(
            "box", c.name, g.file, g.line, center=(_r(t[0]), _r(t[1])), size=size, yaw=_r(yaw)
        )
    corners = np.array(
        [
            (sx * half[0], sy * half[1], sz * half[2])
            for sx in (-1, 1)
            for sy in (-1, 1)
            for sz in (-1, 1)
        ]
    )
    return _polygon(band_section(_world_points(g.pose, corners), lo, hi), c)


def _round_body(c: WorldCollision, lo: float, hi: float) -> GroundShape | None:
    """A sphere, or a cylinder (capsules come as cylinders over their caps)."""
    g = c.geometry
    (rot, t) = g.pose
    radius = g.size[0]
    if g.kind == "sphere":
        r = _circle_section(radius, t[2], t[2], lo, hi)
    elif abs(rot[2][2]) >= UPRIGHT:
        half = 0.5 * g.size[1]
        r = radius if (t[2] + half > lo and t[2] - half < hi) else 0.0
    else:
        ring = _prism_ring(radius)
        half = 0.5 * g.size[1]
        local = np.concatenate(
            [np.column_stack([ring, np.full(len(ring), z)]) for z in (-half, half)]
        )
        return _polygon(band_section(_world_points(g.pose, local), lo, hi), c)
    if r <= 0.0:
        return None
    return GroundShape(
        "circle", c.name, g.file, g.line, center=(_r(t[0]), _r(t[1])), radius=max(_r(r), MIN_SIZE)
    )


def _polyline(c: WorldCollision, lo: float, hi: float) -> list[GroundShape]:
    g = c.geometry
    rot = g.pose[0]
    height = g.size[0]
    out = []
    for outline in c.polylines:
        xy = np.asarray(outline, dtype=float)
        local = np.concatenate([np.column_stack([xy, np.full(len(xy), z)]) for z in (0.0, height)])
        placed = _world_points(g.pose, local)
        if abs(rot[2][2]) >= UPRIGHT:
            z = placed[:, 2]
            if not (z.max() > lo and z.min() < hi):
                continue
            pts = tuple((_r(x), _r(y)) for x, y in placed[: len(xy), :2])
            out.append(GroundShape("polygon", c.name, g.file, g.line, points=pts))
        else:
            shape = _polygon(band_section(placed, lo, hi), c)
            if shape is not None:
                out.append(shape)
    return out


def _mesh(c: WorldCollision, lo: float, hi: float, meshes: MeshSources) -> GroundShape | None:
    g = c.geometry
    try:
        v = meshes.scaled_vertices(g)
    except MeshError as exc:
        warnings.warn(
            BtnavWarning(
                f"cannot read the collision mesh '{g.uri}' of '{c.name}': {exc}; it is left "
                "out of the world",
                file=g.file,
                line=g.line,
            ),
            stacklevel=3,
        )
        return None
    placed = _world_points(g.pose, v)
    z = placed[:, 2]
    if not (z.max() > lo and z.min() < hi):
        return None
    points = placed[:, :2]
    from scipy.spatial import ConvexHull, QhullError  # only when a mesh is read

    with contextlib.suppress(QhullError):  # flat from above: the polygon check drops it
        points = points[ConvexHull(points).vertices]  # a CAD mesh's few outline points
    return _polygon(points, c, thin=True)


def ground_shapes(
    c: WorldCollision, band: Sequence[float], meshes: MeshSources | None = None
) -> list[GroundShape]:
    """The collision's section through the band [lo, hi] (m above the world's z = 0), as
    the shapes a 2D world holds; none when the band misses it (a table top)."""
    lo, hi = float(band[0]), float(band[1])
    kind = c.geometry.kind
    if kind == "polyline":
        return _polyline(c, lo, hi)
    if kind == "box":
        shape = _box(c, lo, hi)
    elif kind in ("cylinder", "sphere"):
        shape = _round_body(c, lo, hi)
    elif kind == "mesh":
        shape = _mesh(c, lo, hi, meshes or MeshSources())
    else:  # pragma: no cover - read_world gives only the kinds above
        raise DescriptionError(f"unknown geometry kind {kind}")
    return [] if shape is None else [shape]
