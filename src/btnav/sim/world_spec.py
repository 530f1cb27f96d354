"""The world YAML, as pydantic models: what a world file may say, checked with line numbers.

A world file describes the physical scene (bounds, walls, obstacles, some of them
moving) and the robot (footprint, start pose, drive limits, odometry noise,
sensors). The robot may name a `description` (URDF, xacro or a Gazebo SDF model, read
by `btnav.description`): its footprint, drive, lidars and drive limits fill every robot
key the world leaves out, and a key the world writes wins. `load_world_spec` reads one
and turns every mistake into a `WorldError` naming the file, the line, the key path
and, for a misspelt key, the right spelling.
Geometry that cannot be checked key by key (a start pose inside a wall) is checked
by `World` against the physics, with the line of `robot.pose`.
"""

from __future__ import annotations

import itertools
import math
import os
import warnings
from collections.abc import Sequence
from os import PathLike
from pathlib import Path
from typing import Annotated, Any, Literal

import numpy as np
from pydantic import BeforeValidator, Field, PrivateAttr, field_validator, model_validator

from ..core import fmath
from ..core.errors import BtnavError, BtnavWarning, WorldError
from ..core.suggest import best_match
from ..core.validation import StrictModel, validate
from ..core.yaml_io import YamlMap, file_of, line_at, load_yaml, load_yaml_text
from ..description import ModelPaths, PackagePaths, RobotDescription, load_description
from ..maps import load_map
from ..maps.occupied_rectangles import occupied_rectangles
from .dock_spec import Docks

#: Coordinates beyond this (metres) are a mistake, not a building; it also keeps
#: pymunk and the rasteriser away from float overflow.
MAX_COORD = 1.0e5
#: The largest size of one thing (box side, radius, wall thickness), metres.
MAX_SIZE = 1.0e4
#: The smallest size of one thing: below a millimetre a shape is a typo, and pymunk
#: needs a positive area to build it.
MIN_SIZE = 1.0e-3
#: Polygons are checked for self-intersection pairwise; this keeps that check cheap.
MAX_POLYGON_POINTS = 1000


def _finite_number(v: Any) -> Any:
    """YAML `true` is not a number, and NaN/inf have no place in a scene."""
    if isinstance(v, bool):
        raise ValueError("expected a number, not true/false")
    if isinstance(v, float) and not math.isfinite(v):
        raise ValueError("expected a finite number")
    return v


#: A finite number that is not a boolean; bounds go in the field's `Field(...)`.
Real = Annotated[float, BeforeValidator(_finite_number), Field(allow_inf_nan=False)]
Coord = Annotated[
    float, BeforeValidator(_finite_number), Field(allow_inf_nan=False, ge=-MAX_COORD, le=MAX_COORD)
]
Size = Annotated[
    float, BeforeValidator(_finite_number), Field(allow_inf_nan=False, ge=MIN_SIZE, le=MAX_SIZE)
]
Angle = Annotated[
    float, BeforeValidator(_finite_number), Field(allow_inf_nan=False, ge=-1000.0, le=1000.0)
]


def _numbers(n: int | tuple[int, ...], what: str) -> Any:
    """A before-validator: a list of exactly `n` items (or one of the counts `n` lists),
    with a message that says what it is."""
    counts = (n,) if isinstance(n, int) else n

    def check(v: Any) -> Any:
        if isinstance(v, list | tuple) and len(v) not in counts:
            raise ValueError(f"{what}, got {len(v)} item{'s' if len(v) != 1 else ''}")
        return v

    return BeforeValidator(check)


Point = Annotated[tuple[Coord, Coord], _numbers(2, "a point is [x, y]")]


# -- polygon checks -----------------------------------------------------------------


def signed_area(points: np.ndarray) -> float:
    """Shoelace area: positive for counter-clockwise vertices."""
    x, y = points[:, 0], points[:, 1]
    # products and numpy's sum, not np.dot (BLAS: CPU-dependent bits; it sets polygon masses)
    return 0.5 * float((x * np.roll(y, -1)).sum() - (np.roll(x, -1) * y).sum())


def crossing_edges(points: np.ndarray) -> tuple[int, int] | None:
    """The first pair of non-adjacent edges of a closed polygon that touch or cross, or None.

    Vectorised over all edge pairs (K <= MAX_POLYGON_POINTS keeps it under a million).
    """
    p = np.asarray(points, dtype=float)
    k = len(p)
    if k < 4:
        return None
    a, b = p, np.roll(p, -1, axis=0)
    i, j = np.triu_indices(k, 2)
    keep = ~((i == 0) & (j == k - 1))  # the first and last edges share a vertex
    i, j = i[keep], j[keep]

    def orient(p1: np.ndarray, p2: np.ndarray, p3: np.ndarray) -> np.ndarray:
        return (p2[:, 0] - p1[:, 0]) * (p3[:, 1] - p1[:, 1]) - (p2[:, 1] - p1[:, 1]) * (
            p3[:, 0] - p1[:, 0]
        )

    a1, b1, a2, b2 = a[i], b[i], a[j], b[j]
    scale = max(1.0, float(np.abs(p).max()))
    eps = 1e-12 * scale * scale
    d1, d2 = orient(a2, b2, a1), orient(a2, b2, b1)
    d3, d4 = orient(a1, b1, a2), orient(a1, b1, b2)
    proper = (((d1 > eps) & (d2 < -eps)) | ((d1 < -eps) & (d2 > eps))) & (
        ((d3 > eps) & (d4 < -eps)) | ((d3 < -eps) & (d4 > eps))
    )

    def on_segment(p1: np.ndarray, p2: np.ndarray, q: np.ndarray, d: np.ndarray) -> np.ndarray:
        lo, hi = np.minimum(p1, p2), np.maximum(p1, p2)
        return (np.abs(d) <= eps) & np.all((q >= lo - 1e-12 * scale) & (q <= hi + 1e-12 * scale), 1)

    touching = (
        on_segment(a2, b2, a1, d1)
        | on_segment(a2, b2, b1, d2)
        | on_segment(a1, b1, a2, d3)
        | on_segment(a1, b1, b2, d4)
    )
    hit = np.flatnonzero(proper | touching)
    if hit.size == 0:
        return None
    return int(i[hit[0]]), int(j[hit[0]])


def check_polygon(points: Sequence[Sequence[float]]) -> list[tuple[float, float]]:
    """A simple polygon's vertices without a repeated closing point; ValueError otherwise."""
    pts = [(float(x), float(y)) for x, y in points]
    if len(pts) > 1 and pts[0] == pts[-1]:
        pts = pts[:-1]
    # Consecutive duplicates add nothing and would read as touching edges.
    pts = [p for n, p in enumerate(pts) if n == 0 or p != pts[n - 1]]
    if len(pts) < 3:
        raise ValueError("a polygon needs at least 3 distinct points")
    arr = np.array(pts)
    pair = crossing_edges(arr)
    if pair is not None:
        e1, e2 = pair
        raise ValueError(
            f"the polygon crosses itself: edge {e1} ({pts[e1]} -> {pts[(e1 + 1) % len(pts)]}) "
            f"meets edge {e2} ({pts[e2]} -> {pts[(e2 + 1) % len(pts)]}); "
            "list the points in order around the outline"
        )
    if abs(signed_area(arr)) < MIN_SIZE * MIN_SIZE:
        raise ValueError("the polygon has no area (its points are on one line)")
    return pts


PolygonPoints = Annotated[list[Point], Field(min_length=3, max_length=MAX_POLYGON_POINTS + 1)]


# -- scene ----------------------------------------------------------------------------


class MovesSpec(StrictModel):
    """A kinematic obstacle's route: its centre goes from where it is through `path`."""

    path: list[Point] = Field(min_length=1, max_length=10_000)
    speed: Real = Field(gt=0, le=100, description="m/s along the route")
    loop: bool = Field(False, description="back and forth forever; false stops at the last point")


class BoxSpec(StrictModel):
    center: Point
    size: Annotated[tuple[Size, Size], _numbers(2, "a size is [length_x, length_y]")]
    yaw: Angle = 0.0
    moves: MovesSpec | None = None


class CircleSpec(StrictModel):
    center: Point
    radius: Size
    moves: MovesSpec | None = None


class PolygonSpec(StrictModel):
    points: PolygonPoints
    moves: MovesSpec | None = None

    @field_validator("points")
    @classmethod
    def _simple(cls, v: list[tuple[float, float]]) -> list[tuple[float, float]]:
        return check_polygon(v)


ObstacleKind = Literal["box", "circle", "polygon"]
OBSTACLE_KINDS: tuple[str, ...] = ("box", "circle", "polygon")


_EXAMPLES = {
    "box": "{center: [x, y], size: [sx, sy], yaw: 0}",
    "circle": "{center: [x, y], radius: r}",
    "polygon": "{points: [[x, y], ...]}",
}


class ObstacleEntry(StrictModel):
    """One obstacle, written as a one-key mapping: `- box: {...}`, `- circle: {...}`, `- polygon: {...}`."""

    box: BoxSpec | None = None
    circle: CircleSpec | None = None
    polygon: PolygonSpec | None = None

    @model_validator(mode="before")
    @classmethod
    def _one_key(cls, data: Any) -> Any:
        if not isinstance(data, dict):
            raise ValueError(
                "an obstacle is a one-key mapping: box: {...}, circle: {...} or polygon: {...}"
            )
        known = [k for k in data if k in OBSTACLE_KINDS]
        if not data:
            raise ValueError("an empty obstacle; write box: {...}, circle: {...} or polygon: {...}")
        if len(known) > 1:
            raise ValueError(f"one obstacle per list item, got {' and '.join(map(str, known))}")
        if len(known) == 1 and data[known[0]] is None:
            raise ValueError(
                f"'{known[0]}' needs its parameters: {known[0]}: {_EXAMPLES[known[0]]}"
            )
        return data

    @property
    def kind(self) -> str:
        for k in OBSTACLE_KINDS:
            if getattr(self, k) is not None:
                return k
        raise AssertionError("validated obstacles have one kind")  # pragma: no cover

    @property
    def shape(self) -> BoxSpec | CircleSpec | PolygonSpec:
        return getattr(self, self.kind)

    @property
    def moves(self) -> MovesSpec | None:
        return self.shape.moves


def _polyline_as_wall(v: Any) -> Any:
    """A bare polyline is a wall of default thickness."""
    return {"points": v} if isinstance(v, list) else v


class WallSpec(StrictModel):
    """A polyline of thickness `thickness`, centred on the line (butt ends, round joints)."""

    points: list[Point] = Field(min_length=2, max_length=100_000)
    thickness: Size = 0.10

    @field_validator("points")
    @classmethod
    def _has_length(cls, v: list[tuple[float, float]]) -> list[tuple[float, float]]:
        if all(p == v[0] for p in v):
            raise ValueError("a wall needs at least two distinct points")
        return v


WallEntry = Annotated[WallSpec, BeforeValidator(_polyline_as_wall)]


# -- robot ----------------------------------------------------------------------------


class FootprintSpec(StrictModel):
    """`{radius: r}` or `{polygon: [[x, y], ...]}` in base_footprint (the rotation centre)."""

    radius: Real | None = Field(None, ge=0.01, le=100.0)
    polygon: PolygonPoints | None = None

    @field_validator("polygon")
    @classmethod
    def _simple(cls, v: list[tuple[float, float]] | None) -> list[tuple[float, float]] | None:
        if v is None:
            return v
        pts = check_polygon(v)
        if max(fmath.hypot(x, y) for x, y in pts) > 100.0:
            raise ValueError("a footprint vertex is more than 100 m from the robot's centre")
        if abs(signed_area(np.array(pts))) < 1e-4:
            raise ValueError("the footprint polygon is smaller than 1 cm^2")
        return pts

    @model_validator(mode="after")
    def _exactly_one(self) -> FootprintSpec:
        if (self.radius is None) == (self.polygon is None):
            raise ValueError("a footprint is either {radius: r} or {polygon: [[x, y], ...]}")
        return self


class LimitsSpec(StrictModel):
    """Drive limits: speeds (m/s, rad/s) and accelerations (m/s^2, rad/s^2)."""

    v_max: Real = Field(0.5, gt=0, le=100)
    v_min: Real | None = Field(
        None, ge=-100, le=0, description="most negative linear speed (reversing); default -v_max"
    )
    w_max: Real = Field(1.5, gt=0, le=100)
    a_max: Real = Field(1.0, gt=0, le=1000)
    alpha_max: Real = Field(3.0, gt=0, le=1000)

    @property
    def v_low(self) -> float:
        """The most negative linear speed allowed."""
        return -self.v_max if self.v_min is None else self.v_min


Alpha = Annotated[float, BeforeValidator(_finite_number), Field(ge=0, le=10)]


#: Where odom -> base_footprint comes from: the wheels (dead reckoning with `noise`) or
#: the lidar (laser odometry, rf2o's role: scan matching, at the scan rate).
ODOMETRY_SOURCES: tuple[str, ...] = ("wheels", "laser")


def _odometry_source(v: Any) -> Any:
    """A misspelt source names the closest one (a Literal's error would only list them)."""
    if isinstance(v, str) and v not in ODOMETRY_SOURCES:
        near = best_match(v, ODOMETRY_SOURCES)
        hint = f"; did you mean '{near}'?" if near else ""
        raise ValueError(f"unknown odometry source, expected 'wheels' or 'laser'{hint}")
    return v


class OdometrySpec(StrictModel):
    """AMCL's alphas for the drive's motion model (differential: four; omni: five, alpha5
    the strafe noise), as variance per metre or radian of motion, and the `source` of
    odom (`laser`: the wheels' noise and rate are then unused)."""

    noise: Annotated[
        tuple[Alpha, Alpha, Alpha, Alpha] | tuple[Alpha, Alpha, Alpha, Alpha, Alpha],
        _numbers((4, 5), "noise is [alpha1, alpha2, alpha3, alpha4] (and alpha5 for omni)"),
    ] = (0.0, 0.0, 0.0, 0.0)
    rate: Real = Field(50.0, gt=0, le=10_000, description="odometry messages per second")
    source: Annotated[Literal["wheels", "laser"], BeforeValidator(_odometry_source)] = Field(
        "wheels", description="wheels: noisy dead reckoning; laser: scan matching (no wheels)"
    )


#: The footprint a robot has when neither the world nor its description gives one.
DEFAULT_FOOTPRINT_RADIUS = 0.22


def _drive_class(name: Any) -> Any:
    """The drive plugin class a name means (aliases too), or None when it is unknown."""
    from ..plugins import lookup

    try:
        return lookup("drive", str(name))
    except BtnavError:
        return None


def _described_drive(desc: RobotDescription, given: Any) -> Any:
    """`robot.drive` with the description's drive filled in under what the world wrote.

    The description's parameters that the drive plugin has (`wheelbase`,
    `max_steering_angle`, ... for `ackermann`) fill the ones the world leaves out; a
    world naming another drive keeps its own entry whole.
    """
    drive = desc.drive
    if drive is None:
        return given
    name, world_params = drive.name, None
    if given is not None:
        if isinstance(given, str):
            name = given
        elif isinstance(given, dict) and len(given) == 1:
            name, world_params = next(iter(given.items()))
        else:
            return given  # not a drive entry: the field validator says why
        if world_params is not None and not isinstance(world_params, dict):
            return given
        cls = _drive_class(name)
        if cls is None or cls is not _drive_class(drive.name):
            return given
    cls = _drive_class(name)
    fields = set(cls.Params.model_fields) if cls is not None else set()
    params = YamlMap(
        {k: v for k, v in drive.params().items() if k in fields},
        file=getattr(world_params, "file", None),
        line=getattr(world_params, "line", None),
    )
    params.update(world_params or {})
    params.key_lines = dict(getattr(world_params, "key_lines", {}))
    return {name: params} if params or world_params is not None else name


def _read_description(data: Any) -> Any:
    """A robot section with `description: FILE` read, and the world's keys put over it.

    What the description gives (footprint, drive and its parameters, lidars, the drive
    plugin's limits) fills only the keys the world file leaves out: a key written in
    the world wins. The file, `package_paths`, `model_paths` and xacro args resolve from
    the world file's folder (`description: model://NAME` through the model paths); a
    description that cannot be read is its own located error.
    """
    if not isinstance(data, dict) or data.get("description") is None:
        return data
    if isinstance(data["description"], RobotDescription):
        return data  # validated already (an assignment re-validates the model)
    file = getattr(data, "file", None)
    base = Path(file).parent if file else Path.cwd()

    def where(key: str) -> dict[str, Any]:
        line = data.line_of(key) if isinstance(data, YamlMap) else None
        return dict(file=file, line=line, key=["robot", key])

    path, paths, args = data["description"], data.get("package_paths"), data.get("xacro_args")
    folders = data.get("model_paths")
    if not isinstance(path, str) or not path.strip():
        raise WorldError(
            "description is the path of a URDF, xacro or Gazebo SDF file, or model://NAME",
            **where("description"),
        )
    if paths is not None and not (
        isinstance(paths, dict) and all(isinstance(v, str) for v in paths.values())
    ):
        raise WorldError(
            "package_paths maps package names to folders: {name: dir}", **where("package_paths")
        )
    if folders is not None and not (
        isinstance(folders, list) and all(isinstance(v, str) for v in folders)
    ):
        raise WorldError(
            "model_paths lists the folders model:// is looked up in: [dir, ...]",
            **where("model_paths"),
        )
    if args is not None and not (
        isinstance(args, dict)
        and all(isinstance(v, str | int | float | bool) for v in args.values())
    ):
        raise WorldError(
            "xacro_args maps arg names to values: {name: value}", **where("xacro_args")
        )
    try:
        models = ModelPaths.from_list(folders, base)
        models.check()
    except BtnavError as err:
        raise WorldError(err.message, **where("model_paths")) from None
    if path.strip().startswith("model://"):
        try:
            target = models.model_sdf(path.strip())
        except BtnavError as err:
            raise WorldError(
                err.message, suggestion=err.suggestion, **where("description")
            ) from None
    else:
        target = Path(path).expanduser()
        target = target if target.is_absolute() else Path(os.path.normpath(base / target))
        if not target.exists():
            raise WorldError(f"robot description not found: {target}", **where("description"))
    try:
        packages = PackagePaths.from_mapping(paths, base)
        packages.check()
    except BtnavError as err:
        raise WorldError(err.message, **where("package_paths")) from None
    desc = load_description(target, packages, args, models)

    merged = YamlMap(data, file=file, line=getattr(data, "line", None))
    merged.key_lines = dict(getattr(data, "key_lines", {}))
    merged["description"] = desc
    if "footprint" not in data:
        if desc.footprint is not None:
            merged["footprint"] = desc.footprint.spec()
        else:
            warnings.warn(
                BtnavWarning(
                    f"the description {desc.file} has no collision geometry btnav can read "
                    "(box, cylinder, sphere, or a mesh with btnav[meshes]) on its base link, "
                    "so the robot's footprint is the default "
                    f"{{radius: {DEFAULT_FOOTPRINT_RADIUS:g}}}; give the world's robot a "
                    "`footprint:`",
                    **where("description"),
                ),
                stacklevel=2,
            )
    drive = _described_drive(desc, data.get("drive"))
    if drive is not None:
        merged["drive"] = drive
    if "sensors" not in data:
        if desc.lidars:
            merged["sensors"] = [{"lidar": lidar.sensor_params()} for lidar in desc.lidars]
        else:
            warnings.warn(
                BtnavWarning(
                    f"the description {desc.file} has no 2D lidar (a Gazebo <sensor> of type "
                    "ray, gpu_ray, lidar or gpu_lidar), so the robot has none; list the "
                    "world's robot `sensors:`",
                    **where("description"),
                ),
                stacklevel=2,
            )
    limits = desc.drive.limits if desc.drive is not None else {}
    if limits and (data.get("limits") is None or isinstance(data.get("limits"), dict)):
        given = data.get("limits") or {}
        merged_limits = YamlMap({**limits, **given}, file=file, line=getattr(given, "line", None))
        merged_limits.key_lines = dict(getattr(given, "key_lines", {}))
        merged["limits"] = merged_limits
    return merged


class RobotSpec(StrictModel):
    #: A URDF, xacro or Gazebo SDF robot description (a path from the world file's folder);
    #: once validated, the `RobotDescription` read from it. It gives the footprint, the
    #: drive, the lidars and the drive plugin's limits; what the world writes wins.
    description: Any = None
    #: Folders of the ROS packages the description names (`$(find pkg)`, `package://`).
    package_paths: dict[str, str] = Field(default_factory=dict)
    #: Folders `model://NAME` is looked up in (each holding `NAME/model.config`), before
    #: GZ_SIM_RESOURCE_PATH and GAZEBO_MODEL_PATH.
    model_paths: list[str] = Field(default_factory=list)
    #: The description's xacro args (`name:=value` on xacro's command line).
    xacro_args: dict[str, str | int | float | bool] = Field(default_factory=dict)
    #: The drive plugin: its name (`diff_drive`, `ackermann`, `omni`, a user's), or a
    #: one-key mapping `{name: {params}}`; kept as loaded, as `sensors` entries are, and
    #: validated by the plugin's own `Params` when the world is built.
    drive: Any = "diff_drive"
    footprint: FootprintSpec = Field(
        default_factory=lambda: FootprintSpec(radius=DEFAULT_FOOTPRINT_RADIUS)
    )
    pose: Annotated[tuple[Coord, Coord, Angle], _numbers(3, "a pose is [x, y, yaw]")]
    limits: LimitsSpec = Field(default_factory=LimitsSpec)
    odometry: OdometrySpec = Field(default_factory=OdometrySpec)
    #: Raw entries (`{plugin_name: params}`), kept as loaded so their lines survive;
    #: each plugin's own `Params` validates them when the sensors are built.
    sensors: list[Any] = Field(default_factory=list, max_length=1000)

    @model_validator(mode="before")
    @classmethod
    def _described(cls, data: Any) -> Any:
        return _read_description(data)

    @field_validator("drive")
    @classmethod
    def _drive_entry(cls, v: Any) -> Any:
        if isinstance(v, str):
            return v
        if isinstance(v, dict) and len(v) == 1:
            name, params = next(iter(v.items()))
            if isinstance(name, str) and (params is None or isinstance(params, dict)):
                return v
        raise ValueError(
            "a drive is a plugin name (diff_drive, ackermann, omni) or one mapping "
            "{name: {params}}, e.g. {ackermann: {wheelbase: 0.33}}"
        )

    @property
    def drive_name(self) -> str:
        return self.drive if isinstance(self.drive, str) else next(iter(self.drive))

    @property
    def drive_params(self) -> Any:
        """The drive's params as written (None when only its name is given)."""
        return None if isinstance(self.drive, str) else next(iter(self.drive.values()))

    @field_validator("sensors")
    @classmethod
    def _one_key_each(cls, v: list[Any]) -> list[Any]:
        for entry in v:
            if not (isinstance(entry, dict) and len(entry) == 1):
                raise ValueError(
                    "each sensor is a one-key mapping {plugin_name: {params}}, e.g. - lidar: {...}"
                )
            name, params = next(iter(entry.items()))
            if not isinstance(name, str):
                raise ValueError(f"a sensor's plugin name is a string, got {name!r}")
            if params is not None and not isinstance(params, dict):
                raise ValueError(f"the parameters of sensor '{name}' are a mapping")
        return v


def _map_geometry(doc: Any, file: str | None) -> np.ndarray:
    """The rectangles of the occupied cells of the world's `map:` (and, when the world gives
    no `bounds`, the map's extent written into `doc`); a map that cannot be read is a
    located error."""
    where = {"file": file, "line": line_at(doc, ("map",)), "key": "map"}
    value = doc["map"]
    if not isinstance(value, str):
        raise WorldError("map is the path of a map_server .yaml file", **where)
    path = Path(value) if file is None else Path(file).parent / value
    try:
        grid = load_map(path)
    except BtnavError as err:
        raise WorldError(f"map {value}: {err.message}", **where) from None
    if abs(grid.origin.yaw) > 1e-9:
        raise WorldError(f"map {value}: a rotated map origin is not supported yet", **where)
    # occupied as map_server reads the image: at or above its occupied_thresh
    rects = occupied_rectangles(grid.data == 100).astype(float)
    res, ox, oy = grid.resolution, grid.origin.x, grid.origin.y
    boxes = np.column_stack(
        (
            ox + rects[:, 1] * res,
            oy + rects[:, 0] * res,
            ox + rects[:, 3] * res,
            oy + rects[:, 2] * res,
        )
    )
    if "bounds" not in doc:
        w, h = grid.size_m
        doc["bounds"] = [[ox, oy], [ox + w, oy + h]]
    return boxes


class WorldSpec(StrictModel):
    """A whole world file."""

    world: str = Field("world", max_length=200, description="the world's name")
    #: A map_server map (relative to the world file) whose occupied cells become static
    #: geometry: a world made from a map image (the bounds default to the map's extent).
    map: str | None = Field(None, min_length=1)
    bounds: Annotated[
        tuple[Point, Point], _numbers(2, "bounds are [[x_min, y_min], [x_max, y_max]]")
    ]
    walls: list[WallEntry] = Field(default_factory=list)
    obstacles: list[ObstacleEntry] = Field(default_factory=list)
    robot: RobotSpec
    #: Docks (`{name, type, pose}`): a static body each, and what a dock detector sees.
    docks: Docks = Field(default_factory=list)

    _doc: Any = PrivateAttr(default=None)
    _file: str | None = PrivateAttr(default=None)
    _warnings: list[BtnavWarning] = PrivateAttr(default_factory=list)
    #: (K, 4) x0, y0, x1, y1: the `map`'s occupied cells as rectangles (world metres)
    _map_boxes: np.ndarray = PrivateAttr(default_factory=lambda: np.zeros((0, 4)))
    #: The robot block when it was written outside the world file (see `use_robot`).
    _robot_doc: Any = PrivateAttr(default=None)

    @field_validator("bounds")
    @classmethod
    def _ordered(
        cls, v: tuple[tuple[float, float], tuple[float, float]]
    ) -> tuple[tuple[float, float], tuple[float, float]]:
        (x0, y0), (x1, y1) = v
        if not (x1 - x0 >= MIN_SIZE and y1 - y0 >= MIN_SIZE):
            raise ValueError("bounds are [[x_min, y_min], [x_max, y_max]] with max > min")
        return v

    @property
    def file(self) -> str | None:
        return self._file

    @property
    def map_boxes(self) -> np.ndarray:
        """The `map`'s occupied cells as (K, 4) rectangles x0, y0, x1, y1 (none without one)."""
        return self._map_boxes

    @property
    def load_warnings(self) -> list[BtnavWarning]:
        """What loading found odd but allowed (a moving obstacle's route through a wall);
        each was also given to `warnings.warn`, which the CLI prints as one line."""
        return list(self._warnings)

    def line_of(self, *path: str | int) -> int | None:
        """The line in the world file of the deepest part of `path` that exists (under
        `robot`, in `robot_file` when the robot was written elsewhere)."""
        if path[:1] == ("robot",) and self._robot_doc is not None:
            return line_at(self._robot_doc, path[1:])
        return line_at(self._doc, path) if self._doc is not None else None

    @property
    def robot_replaced(self) -> bool:
        """Whether the robot was written outside the world file (a mission's `robot:`)."""
        return self._robot_doc is not None

    @property
    def robot_file(self) -> str | None:
        """The file the robot block was written in (the world file, unless replaced)."""
        return file_of(self._robot_doc) if self._robot_doc is not None else self._file

    def use_robot(self, robot: RobotSpec, doc: Any) -> None:
        """Stand `robot` (validated from `doc`, a block of another file) in this world."""
        self.robot = robot
        self._robot_doc = doc

    @classmethod
    def from_doc(cls, doc: Any, file: str | PathLike[str] | None = None) -> WorldSpec:
        """Validate a loaded YAML document (keeps it for line lookups)."""
        name = None if file is None else str(file)
        if doc is None:
            raise WorldError("the world file is empty", file=name)
        if not isinstance(doc, dict):
            raise WorldError(
                f"a world file is a mapping (world, bounds, walls, obstacles, robot), "
                f"got {type(doc).__name__}",
                file=name,
                line=getattr(doc, "line", None),
            )
        boxes = None
        if doc.get("map") is not None:
            boxes = _map_geometry(doc, name)
        spec = validate(cls, doc, file=name, error_cls=WorldError)
        spec._doc = doc
        spec._file = name
        if boxes is not None:
            spec._map_boxes = boxes
        spec._warnings = route_crossings(spec)
        for warning in spec._warnings:
            warnings.warn(warning, stacklevel=2)
        return spec

    @classmethod
    def from_text(cls, text: str | bytes, file: str | PathLike[str] | None = None) -> WorldSpec:
        return cls.from_doc(load_yaml_text(text, file), file)


# -- moving obstacles' routes -------------------------------------------------------------

Vec = tuple[float, float]
#: Overlaps shallower than this (m) are touching, not crossing.
CROSSING_TOLERANCE = 1e-6


def _cross(o: Vec, a: Vec, b: Vec) -> float:
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])


def _point_segment_distance(p: Vec, a: Vec, b: Vec) -> float:
    dx, dy = b[0] - a[0], b[1] - a[1]
    length2 = dx * dx + dy * dy
    t = 0.0 if length2 == 0.0 else ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / length2
    t = min(1.0, max(0.0, t))
    return fmath.hypot(p[0] - a[0] - t * dx, p[1] - a[1] - t * dy)


def _segments_cross(a: Vec, b: Vec, c: Vec, d: Vec) -> bool:
    """Whether segments ab and cd cross at a point inside both (touching does not count)."""
    d1, d2 = _cross(c, d, a), _cross(c, d, b)
    d3, d4 = _cross(a, b, c), _cross(a, b, d)
    return ((d1 > 0 > d2) or (d1 < 0 < d2)) and ((d3 > 0 > d4) or (d3 < 0 < d4))


def _segment_distance(a: Vec, b: Vec, c: Vec, d: Vec) -> float:
    if _segments_cross(a, b, c, d):
        return 0.0
    return min(
        _point_segment_distance(a, c, d),
        _point_segment_distance(b, c, d),
        _point_segment_distance(c, a, b),
        _point_segment_distance(d, a, b),
    )


def _inside(p: Vec, poly: Sequence[Vec]) -> bool:
    """Strictly inside a simple polygon (even-odd rule)."""
    inside = False
    n = len(poly)
    for i in range(n):
        (x1, y1), (x2, y2) = poly[i], poly[(i + 1) % n]
        if (y1 > p[1]) != (y2 > p[1]):
            x = x1 + (p[1] - y1) * (x2 - x1) / (y2 - y1)
            if p[0] < x:
                inside = not inside
    return inside


def _edges(poly: Sequence[Vec]) -> list[tuple[Vec, Vec]]:
    return [(poly[i], poly[(i + 1) % len(poly)]) for i in range(len(poly))]


def _polygons_overlap(p: Sequence[Vec], q: Sequence[Vec]) -> bool:
    if any(_segments_cross(a, b, c, d) for a, b in _edges(p) for c, d in _edges(q)):
        return True
    return any(_inside(v, q) for v in p) or any(_inside(v, p) for v in q)


def _capsule_hits_polygon(a: Vec, b: Vec, r: float, poly: Sequence[Vec]) -> bool:
    """Whether the segment ab widened by r overlaps the polygon (r = 0: the segment itself)."""
    if _inside(a, poly) or _inside(b, poly):
        return True
    if r <= 0.0:
        return any(_segments_cross(a, b, c, d) for c, d in _edges(poly))
    return any(_segment_distance(a, b, c, d) < r - CROSSING_TOLERANCE for c, d in _edges(poly))


class _Shapes:
    """A solid's outline at one place: polygons, and capsules (a, b, r) for its circles."""

    def __init__(self) -> None:
        self.polygons: list[list[Vec]] = []
        self.capsules: list[tuple[Vec, Vec, float]] = []

    def box(self) -> tuple[float, float, float, float]:
        """The bounding box (x_min, y_min, x_max, y_max)."""
        xs = [x for p in self.polygons for x, _ in p]
        ys = [y for p in self.polygons for _, y in p]
        for (ax, ay), (bx, by), r in self.capsules:
            xs += [min(ax, bx) - r, max(ax, bx) + r]
            ys += [min(ay, by) - r, max(ay, by) + r]
        return (min(xs), min(ys), max(xs), max(ys)) if xs else (0.0, 0.0, -1.0, -1.0)

    def hits(self, other: _Shapes) -> bool:
        (x0, y0, x1, y1), (u0, v0, u1, v1) = self.box(), other.box()
        if x0 > u1 or u0 > x1 or y0 > v1 or v0 > y1:
            return False
        for a, b, r in self.capsules:
            for c, d, r2 in other.capsules:
                if _segment_distance(a, b, c, d) < r + r2 - CROSSING_TOLERANCE:
                    return True
            if any(_capsule_hits_polygon(a, b, r, q) for q in other.polygons):
                return True
        for p in self.polygons:
            if any(_capsule_hits_polygon(c, d, r, p) for c, d, r in other.capsules):
                return True
            if any(_polygons_overlap(p, q) for q in other.polygons):
                return True
        return False


def _placed(solid: Any, at: Vec) -> _Shapes:
    shapes = _Shapes()
    for outline in solid.outlines:
        shapes.polygons.append([(float(x) + at[0], float(y) + at[1]) for x, y in outline])
    for x, y, r in solid.circles:
        centre = (float(x) + at[0], float(y) + at[1])
        shapes.capsules.append((centre, centre, float(r)))
    return shapes


def _swept(solid: Any, a: Vec, b: Vec) -> _Shapes:
    """Everything `solid` covers while its reference point moves straight from a to b: its
    outline at both ends, the parallelogram each edge sweeps, each circle's capsule."""
    shapes = _Shapes()
    da, db = _placed(solid, a), _placed(solid, b)
    shapes.polygons += da.polygons + db.polygons
    for poly_a, poly_b in zip(da.polygons, db.polygons, strict=True):
        for (p, q), (p2, q2) in zip(_edges(poly_a), _edges(poly_b), strict=True):
            if _cross(p, q, q2) != 0.0:  # an edge moving along itself sweeps no area
                shapes.polygons.append([p, q, q2, p2])
    for (c, _, r), (c2, _, _) in zip(da.capsules, db.capsules, strict=True):
        shapes.capsules.append((c, c2, r))
    return shapes


def route_crossings(spec: WorldSpec) -> list[BtnavWarning]:
    """A warning for each moving obstacle whose route goes through a wall or a static
    obstacle: nothing stops a moving obstacle, so it passes through, which is seldom meant.

    The warning is placed at the mover's `moves` line and names the static one's line.
    """
    if not any(entry.moves is not None for entry in spec.obstacles):
        return []
    from .moving import Route  # they build on this module's specs
    from .scene import build_solids

    solids = build_solids(spec)
    static = [
        (s, _placed(s, (float(s.origin[0]), float(s.origin[1])))) for s in solids if s.moves is None
    ]
    found: list[BtnavWarning] = []
    for solid in solids:
        if solid.moves is None:
            continue
        points = [(float(x), float(y)) for x, y in Route(solid.origin, solid.moves).points]
        legs = list(itertools.pairwise(points)) or [(points[0], points[0])]
        swept = [(leg, _swept(solid, *leg)) for leg in legs]
        index = int(solid.key[1])
        kind = spec.obstacles[index].kind
        for other, shape in static:
            leg = next((leg for leg, covered in swept if covered.hits(shape)), None)
            if leg is None:
                continue
            group, at = other.key
            what = (
                f"walls[{at}]"
                if group == "walls"
                else f"the {spec.obstacles[int(at)].kind} {group}[{at}]"
            )
            line = spec.line_of(*other.key)
            (x0, y0), (x1, y1) = leg
            found.append(
                BtnavWarning(
                    f"the route of this moving {kind} goes through {what}"
                    f"{f' (line {line})' if line else ''} on its way from ({x0:g}, {y0:g}) to "
                    f"({x1:g}, {y1:g}); moving obstacles pass through whatever is in their way",
                    file=spec.file,
                    line=spec.line_of("obstacles", index, kind, "moves"),
                    key=["obstacles", index, kind, "moves"],
                )
            )
    return found


#: A Gazebo world's file names (`sdf_world_spec` reads them, not the YAML loader).
SDF_WORLD_SUFFIXES = (".world", ".sdf")


def robot_from_block(block: Any, pose: Any = None) -> tuple[RobotSpec, YamlMap]:
    """A robot block written outside a world file (a mission's `robot:`), validated and
    located in its own file, its paths relative to that file; `pose` stands in for a
    `pose` it leaves out ([0, 0, 0] when None). Returns the robot and the block read."""
    file = file_of(block)
    if not isinstance(block, dict):
        raise WorldError(
            "robot is a description file or a robot block {description: FILE, ...}",
            file=file,
            line=getattr(block, "line", None),
            key="robot",
        )
    data = YamlMap(block, file=file, line=getattr(block, "line", None))
    data.key_lines = dict(getattr(block, "key_lines", {}))
    if "pose" not in data:
        data["pose"] = list(pose) if pose is not None else [0.0, 0.0, 0.0]
    robot = validate(RobotSpec, data, file=file, key_prefix=["robot"], error_cls=WorldError)
    return robot, data


def _with_robot(doc: Any, path: Path, block: Any) -> WorldSpec:
    """The world file's scene with `block` as its robot (the world's own is not read); a
    block without a pose starts where the world's robot does."""
    own = doc.get("robot") if isinstance(doc, dict) else None
    pose = own.get("pose") if isinstance(own, dict) else None
    if isinstance(block, dict) and "pose" not in block and pose is None:
        raise WorldError(
            f"the robot needs a start pose and the world {path} gives none: give the "
            "mission an initial_pose (or the robot a pose)",
            file=file_of(block),
            line=getattr(block, "line", None),
            key="robot",
        )
    robot, data = robot_from_block(block, pose)
    if isinstance(doc, dict):
        scene = YamlMap(doc, file=file_of(doc), line=getattr(doc, "line", None))
        scene.key_lines = dict(getattr(doc, "key_lines", {}))
        scene["robot"] = robot
        doc = scene
    spec = WorldSpec.from_doc(doc, path)
    spec.use_robot(robot, data)
    return spec


def load_world_spec(path: str | PathLike[str], robot: Any = None) -> WorldSpec:
    """Read and validate a world file; any mistake is a located `BtnavError`.

    A Gazebo world (`.world`, `.sdf`, or a world YAML naming one with `sdf:`) is read by
    `sdf_world_spec`. `robot`, a robot block written in another file (a mission's
    `robot:`, paths relative to that file), replaces the world's robot; without a pose
    of its own it starts where the world's robot would.
    """
    p = Path(path)
    if p.suffix.lower() in SDF_WORLD_SUFFIXES:
        from .sdf_world_spec import load_sdf_world  # it builds on this module

        return load_sdf_world(p, robot)
    doc = load_yaml(p)
    if isinstance(doc, dict) and "sdf" in doc:
        from .sdf_world_spec import load_sdf_world

        return load_sdf_world(p, robot, ref=doc)
    if robot is not None:
        return _with_robot(doc, p, robot)
    return WorldSpec.from_doc(doc, p)
