"""A Gazebo world (classic `.world`, gz-sim `.sdf`) as a btnav world: what a 2D lidar sees.

`btnav.description.sdf_world` cuts each collision by the robot's sensing height band
([0.05, lidar height + 0.1] m); here the sections become obstacles that keep the line they
were written at, so a contact names it. A scripted `<actor>` becomes a moving circle at its
trajectory's mean speed. The robot is the mission's, else the world YAML's, else btnav's
default; it starts at its `pose`, the world's spawn, or the free place nearest the origin.
A world YAML names the Gazebo world with `sdf:` and adds `model_paths`, `height_band` and
`robot`. Details and an example: docs/decisions/0085.
"""

from __future__ import annotations

import copy
import os
import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from os import PathLike
from pathlib import Path
from typing import Any

import numpy as np
import yaml
from pydantic import Field, field_validator

from ..core import fmath
from ..core.errors import BtnavError, BtnavWarning, WorldError
from ..core.validation import StrictModel, validate
from ..core.yaml_io import YamlMap, YamlSeq, file_of, line_at, to_plain
from ..description import ModelPaths, RobotDescription
from ..description.footprint import convex_hull
from ..description.sdf_world import GroundShape, SdfWorld, ground_shapes, read_world
from .scene import box_corners
from .world_spec import (
    MAX_POLYGON_POINTS,
    Point,
    Real,
    RobotSpec,
    WorldSpec,
    check_polygon,
    robot_from_block,
)

#: The lidar height (m) when the robot's description gives none.
DEFAULT_LIDAR_HEIGHT = 0.25
#: The band starts this high (m): floors, rugs and door sills are not walls.
BAND_FLOOR = 0.05
#: ... and ends this far (m) above the lidar: what the beams graze still counts.
BAND_OVER_LIDAR = 0.10
#: The bounds hold the geometry, the actors' routes and the start, plus this (m).
BOUNDS_MARGIN = 1.0
#: The footprint of an actor (a person), m.
ACTOR_RADIUS = 0.2
#: How far (m) beyond the robot's outline the free start place must be clear.
START_CLEARANCE = 0.05
#: The robot a Gazebo world gets when nobody gives one: the office demo's.
DEFAULT_ROBOT: dict[str, Any] = {
    "drive": "diff_drive",
    "footprint": {"radius": 0.22},
    "limits": {"v_max": 0.5, "w_max": 1.5, "a_max": 1.0, "alpha_max": 3.0},
    "odometry": {"noise": [0.002, 0.0005, 0.0001, 0.0001], "rate": 50},
    "sensors": [
        {
            "lidar": {
                "frame": "laser",
                "pose": [0.1, 0.0, 0.0],
                "beams": 360,
                "range": [0.12, 8.0],
                "rate": 10,
                "noise_std": 0.01,
            }
        }
    ],
}


class SdfWorldRef(StrictModel):
    """A world YAML that names a Gazebo world (`sdf:`), with what the file cannot say."""

    world: str | None = Field(None, max_length=200)
    sdf: str = Field(min_length=1)
    model_paths: list[str] = Field(default_factory=list)
    height_band: tuple[Real, Real] | None = None
    bounds: tuple[Point, Point] | None = None
    robot: Any = None

    @field_validator("height_band")
    @classmethod
    def _ordered(cls, v: tuple[float, float] | None) -> tuple[float, float] | None:
        if v is not None and not v[0] < v[1]:
            raise ValueError("height_band is [lo, hi] in metres with lo < hi")
        return v


@dataclass
class SdfConversion:
    """A Gazebo world read as a btnav world, with what `btnav world convert` writes."""

    spec: WorldSpec
    source: SdfWorld
    shapes: list[GroundShape]  # the static obstacles, first in `spec.obstacles`
    band: tuple[float, float]
    robot_doc: YamlMap  # the robot block as read (its pose the start)
    entries: list[dict[str, Any]]  # `spec.obstacles` as written: shapes, then actors
    entry_lines: list[int | None]  # the line of each in the world file


def robot_names(robot: RobotSpec) -> tuple[str, ...]:
    """The names a world's model of this robot would go by: its description's name, its
    file's (`turtlebot3_burger` of `turtlebot3_burger.urdf.xacro`) or model folder's."""
    desc = robot.description
    if not isinstance(desc, RobotDescription):
        return ()
    path = Path(desc.file)
    names = {desc.name, path.parent.name if desc.kind == "sdf" else path.name.split(".")[0]}
    return tuple(sorted(n for n in names if n))


def lidar_band(robot: RobotSpec) -> tuple[float, float]:
    """[BAND_FLOOR, lidar height + BAND_OVER_LIDAR]: the first lidar of the description."""
    desc = robot.description
    height = DEFAULT_LIDAR_HEIGHT
    if isinstance(desc, RobotDescription) and desc.lidars:
        height = desc.lidars[0].z
    return BAND_FLOOR, max(height + BAND_OVER_LIDAR, 2.0 * BAND_FLOOR)


def _r(v: float, decimals: int = 6) -> float:
    return round(float(v), decimals) + 0.0


def _obstacle(shape: GroundShape) -> dict[str, Any]:
    """The world YAML's entry for a shape (a polygon that crosses itself: its hull)."""
    if shape.kind == "box":
        return {"box": {"center": list(shape.center), "size": list(shape.size), "yaw": shape.yaw}}
    if shape.kind == "circle":
        return {"circle": {"center": list(shape.center), "radius": shape.radius}}
    points = [list(p) for p in shape.points]
    try:
        if len(points) > MAX_POLYGON_POINTS:
            raise ValueError(f"it has more than {MAX_POLYGON_POINTS} points")
        check_polygon(points)
    except ValueError as exc:
        warnings.warn(
            BtnavWarning(
                f"the polyline of '{shape.source}' is not a simple polygon ({exc}); its convex "
                "hull stands for it",
                file=shape.file,
                line=shape.line,
            ),
            stacklevel=4,
        )
        points = [[float(x), float(y)] for x, y in convex_hull(np.asarray(points, dtype=float))]
    return {"polygon": {"points": points}}


def _actor_entry(waypoints: Sequence[tuple[float, float, float, float]], loop: bool) -> dict:
    """A moving circle through the waypoints at the trajectory's mean speed."""
    points: list[list[float]] = []
    for _, x, y, _ in waypoints:
        p = [_r(x), _r(y)]
        if not points or points[-1] != p:
            points.append(p)
    xy = np.asarray(points, dtype=float)
    length = float(fmath.hypot(*np.diff(xy, axis=0).T).sum())
    duration = waypoints[-1][0] - waypoints[0][0]
    speed = _r(min(max(length / duration if duration > 0 else 1.0, 1e-3), 100.0))
    moves = {"path": points[1:], "speed": speed, "loop": loop}
    return {"circle": {"center": points[0], "radius": ACTOR_RADIUS, "moves": moves}}


def _extent(entries: Sequence[dict[str, Any]], start: Sequence[float] | None) -> np.ndarray:
    """(x0, y0, x1, y1) around every entry (and the start), or None when there is nothing."""
    xs: list[float] = []
    ys: list[float] = []
    for entry in entries:
        kind, body = next(iter(entry.items()))
        if kind == "polygon":
            pts = np.asarray(body["points"], dtype=float)
        else:
            cx, cy = body["center"]
            if kind == "circle":
                r = body["radius"]
                pts = np.array([[cx - r, cy - r], [cx + r, cy + r]])
            else:
                pts = box_corners((cx, cy), body["size"], body["yaw"])
            if "moves" in body:
                pts = np.concatenate([pts, np.asarray(body["moves"]["path"], dtype=float)])
        xs += pts[:, 0].tolist()
        ys += pts[:, 1].tolist()
    if start is not None:
        xs.append(float(start[0]))
        ys.append(float(start[1]))
    if not xs:
        return np.array([-5.0, -5.0, 5.0, 5.0])
    m = BOUNDS_MARGIN
    return np.array([min(xs) - m, min(ys) - m, max(xs) + m, max(ys) + m])


def _free_start(spec: WorldSpec) -> tuple[float, float, float]:
    """The free place nearest the world's origin with room for the robot (heading 0)."""
    from scipy.ndimage import distance_transform_edt

    from ..maps.occupancy_grid import FREE
    from .rasterize import rasterize

    grid = rasterize(spec, 0.05, padding=0.0)
    fp = spec.robot.footprint
    corners = fp.polygon or []
    reach = fp.radius if fp.radius is not None else max(fmath.hypot(x, y) for x, y in corners)
    room = distance_transform_edt(grid.data == FREE) * grid.resolution > reach + START_CLEARANCE
    (row, col) = grid.world_to_cell([(0.0, 0.0)])[0]
    if not room.any() or (grid.in_bounds(np.array([row, col])) and room[row, col]):
        return (0.0, 0.0, 0.0)  # the origin, where Gazebo spawns a model by default
    rows, cols = np.nonzero(room)
    x = grid.origin.x + (cols + 0.5) * grid.resolution
    y = grid.origin.y + (rows + 0.5) * grid.resolution
    best = int(np.argmin(x * x + y * y))  # the first of equals: row-major, deterministic
    return (_r(x[best], 3), _r(y[best], 3), 0.0)


def _robot_block(robot: Any, ref: SdfWorldRef | None, ref_doc: Any, world: Path) -> Any:
    """The caller's block, else the world YAML's, else btnav's default (with a warning)."""
    if robot is not None:
        return robot
    if ref is not None and ref.robot is not None:
        return ref_doc["robot"]
    warnings.warn(
        BtnavWarning(
            "a Gazebo world holds no btnav robot: btnav's default robot stands in (a 0.22 m "
            "disc, diff drive, a 360-beam lidar at 0.1 m); give the mission a `robot:` (a "
            "description file, or a robot block as a world file writes it; `btnav world "
            "convert --robot FILE`)",
            file=str(world),
        ),
        stacklevel=4,
    )
    return YamlMap(copy.deepcopy(DEFAULT_ROBOT), file=str(world))


def convert_sdf_world(
    path: str | PathLike[str],
    robot: Any = None,
    *,
    ref: Any = None,
    height_band: Sequence[float] | None = None,
    model_paths: Sequence[str] = (),
) -> SdfConversion:
    """Read a Gazebo world (or the world YAML `ref` naming one, loaded from `path`) as a
    btnav world; `robot` is a robot block written elsewhere (a mission's), its paths
    relative to its own file. Any mistake is a located `BtnavError`."""
    file = Path(path)
    base = file.parent
    parsed = None
    if ref is not None:
        parsed = validate(SdfWorldRef, ref, file=str(file), error_cls=WorldError)
        world_file = Path(os.path.normpath(base / parsed.sdf))
        own = ModelPaths.from_list(parsed.model_paths, base).given
        band_given = height_band if height_band is not None else parsed.height_band
    else:
        world_file, own, band_given = file, (), height_band
    models = ModelPaths((*own, *ModelPaths.from_list(model_paths).given))
    try:
        models.check()
    except BtnavError as err:
        line = line_at(ref, ["model_paths"]) if ref is not None else None
        raise WorldError(err.message, file=str(file), line=line, key="model_paths") from None
    block = _robot_block(robot, parsed, ref, world_file)
    pose_given = isinstance(block, dict) and "pose" in block
    spec_robot, robot_doc = robot_from_block(block)
    band = (float(band_given[0]), float(band_given[1])) if band_given else lidar_band(spec_robot)
    if not band[0] < band[1]:
        raise WorldError(f"the height band [{band[0]:g}, {band[1]:g}] needs lo < hi")
    source = read_world(world_file, models, robot_names(spec_robot))

    shapes: list[GroundShape] = []
    for collision in source.collisions:
        shapes += ground_shapes(collision, band, source.meshes)
    lines = {c.name: (c.geometry.file, c.geometry.line, c.model_line) for c in source.collisions}
    entries: list[dict[str, Any]] = []
    item_lines: list[int | None] = []
    for shape in shapes:
        entries.append(_obstacle(shape))
        at_file, at_line, model_line = lines[shape.source]
        item_lines.append(at_line if at_file == str(world_file) else model_line)
    for actor in source.actors:
        entries.append(_actor_entry(actor.waypoints, actor.loop))
        item_lines.append(actor.line)

    start = spec_robot.pose if pose_given else None
    if start is None and source.spawn is not None:
        start = (_r(source.spawn.x), _r(source.spawn.y), _r(source.spawn.yaw))
    if parsed is not None and parsed.bounds is not None:
        bounds = [list(parsed.bounds[0]), list(parsed.bounds[1])]
    else:
        x0, y0, x1, y1 = (_r(v, 3) for v in _extent(entries, start))
        bounds = [[x0, y0], [x1, y1]]

    name = str(world_file)
    doc = YamlMap(file=name, line=source.line)
    doc["world"] = (parsed.world if parsed is not None else None) or source.name
    doc["bounds"] = bounds
    obstacles = YamlSeq(entries, file=name, line=source.line)
    obstacles.item_lines = [line if line is not None else source.line or 1 for line in item_lines]
    doc["obstacles"] = obstacles
    if start is not None:
        spec_robot.pose = tuple(start)  # type: ignore[assignment]
    doc["robot"] = spec_robot
    spec = WorldSpec.from_doc(doc, name)
    spec.use_robot(spec_robot, robot_doc)
    if start is None:
        spec.robot.pose = _free_start(spec)  # type: ignore[assignment]
    robot_doc["pose"] = list(spec.robot.pose)
    return SdfConversion(spec, source, shapes, band, robot_doc, entries, item_lines)


def load_sdf_world(path: str | PathLike[str], robot: Any = None, *, ref: Any = None) -> WorldSpec:
    """The `WorldSpec` of a Gazebo world file (or of a world YAML naming one, `ref`)."""
    return convert_sdf_world(path, robot, ref=ref).spec


# -- btnav world convert ------------------------------------------------------------------


def _num(v: float) -> str:
    text = f"{float(v):.6f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def _flow(value: Any) -> str:
    """A value in YAML's flow style, numbers as `_num` writes them."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int | float):
        return _num(value)
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k}: {_flow(v)}" for k, v in value.items()) + "}"
    if isinstance(value, list | tuple):
        return "[" + ", ".join(_flow(v) for v in value) + "]"
    return yaml.safe_dump(value, default_flow_style=True).strip().removesuffix("...").strip()


def _written_robot(conv: SdfConversion, out_dir: Path) -> dict[str, Any]:
    """The robot block as the converted file writes it: a description's path relative to
    the new file, the start pose filled in."""
    block = to_plain(conv.robot_doc)
    desc = block.get("description")
    if isinstance(desc, str) and not desc.startswith("model://"):
        from_file = file_of(conv.robot_doc)
        base = Path(from_file).parent if from_file else Path.cwd()
        target = Path(desc).expanduser()
        target = target if target.is_absolute() else base / target
        block["description"] = os.path.relpath(
            os.path.normpath(target.resolve()), out_dir.resolve()
        )
    return block


def sdf_world_yaml(conv: SdfConversion, out: str | PathLike[str]) -> str:
    """The world YAML text `btnav world convert` writes to `out` (paths relative to it)."""
    out_path = Path(out)
    spec, source = conv.spec, conv.source
    lo, hi = conv.band
    src = Path(source.file)
    lines = [
        f"# {src.name} (Gazebo world '{source.name}') as a btnav world, made by",
        f"# `btnav world convert`: every collision cut at {_num(lo)}-{_num(hi)} m above the",
        "# ground (the robot's lidar band) and seen from above; actors move along their",
        "# trajectories. Each obstacle names the collision it comes from.",
        f"world: {_flow(spec.world)}",
        f"bounds: {_flow([list(p) for p in spec.bounds])}",
        "obstacles:" if spec.obstacles else "obstacles: []",
    ]
    names = [s.source for s in conv.shapes] + [f"actor {a.name}" for a in source.actors]
    for entry, name, line in zip(conv.entries, names, conv.entry_lines, strict=True):
        where = f" ({src.name}:{line})" if line else ""
        lines.append(f"  - {_flow(entry)}  # {name}{where}")
    lines.append("robot:")
    for key, value in _written_robot(conv, out_path.parent).items():
        lines.append(f"  {key}: {_flow(value)}")
    return "\n".join(lines) + "\n"
