"""The mission file: what to run (world, params, map, tree, start, task, limits, outputs).

```yaml
mission: office_tour
world: ../worlds/small_office.yaml
params: ../params/nav2_params.yaml
map: ../maps/small_office.yaml
localization: ground_truth
initial_pose: [1.0, 1.0, 0.0]
odometry: {source: wheels}       # over the world's robot.odometry (laser: scan matching)
task:
  follow_waypoints: [[3, 2, 1.57], [6, 3, 0], [9, 1.5, 0]]
time_limit: 300
seed: 0
outputs: [report, trajectory, bt_log]
```

Paths are relative to the mission file. A pose is `[x, y, yaw]` (or `[x, y]`, yaw 0)
in the map frame. `task` holds exactly one of `navigate_to_pose`,
`navigate_through_poses`, `follow_waypoints` or `explore`. Every mistake is a
`MissionError` naming the file, line, key and the closest valid spelling.
"""

from __future__ import annotations

import json
import math
import os
from collections.abc import Mapping
from os import PathLike
from pathlib import Path
from typing import Annotated, Any

from pydantic import AfterValidator, BeforeValidator, Field, model_validator

from ..core.errors import BtnavError
from ..core.validation import StrictModel, validate
from ..core.yaml_io import YamlMap, line_at, load_yaml
from ..params.tree import copy_tree, set_path
from ..plugins import is_registered
from ..sim.world_spec import OdometrySpec
from .errors import MissionError
from .outputs import DEFAULT_OUTPUTS
from .stage_doc import STAGES, stage_doc, stage_names


def _pose(v: Any) -> Any:
    if isinstance(v, list | tuple) and len(v) == 2:
        return (*v, 0.0)
    return v


def _finite(v: tuple[float, float, float]) -> tuple[float, float, float]:
    if not all(math.isfinite(c) for c in v):
        raise ValueError("a pose is [x, y, yaw] in finite numbers")
    return v


Pose = Annotated[tuple[float, float, float], BeforeValidator(_pose), AfterValidator(_finite)]
Poses = Annotated[list[Pose], Field(min_length=1)]


def _drive_command(v: tuple[float, float, float]) -> tuple[float, float, float]:
    if not all(math.isfinite(c) for c in v) or v[2] < 0.0:
        raise ValueError("a drive command is [linear_x, angular_z, seconds], seconds >= 0")
    return v


DriveCommand = Annotated[tuple[float, float, float], AfterValidator(_drive_command)]


def _robot_entry(v: Any) -> Any:
    """`robot:` is a description file or a robot block (checked key by key once read)."""
    if v is None or isinstance(v, Mapping) or (isinstance(v, str) and v.strip()):
        return v
    raise ValueError(
        "robot is a description file (robot: ../robots/my_robot.urdf.xacro) or a robot "
        "block as a world file writes it (robot: {description: ..., pose: ...})"
    )


#: btnav's localisers whose map grows as the robot drives: exploring needs one.
SLAM = ("slam", "cartographer")


def builds_map(localization: str) -> bool:
    """Whether the localiser is SLAM (a `slam` plugin): its map grows as the robot drives."""
    return localization in SLAM or is_registered("slam", localization)


class ExploreTask(StrictModel):
    """`task: explore` (or `explore: {}`): the explore tree until no frontier is left."""


class DriveTask(StrictModel):
    """`drive:` teleop commands `[linear_x, angular_z, seconds]` (a bare list: unassisted);
    `assisted: true` drives them through Nav2's AssistedTeleop."""

    commands: Annotated[list[DriveCommand], Field(min_length=1)]
    assisted: bool = False

    @model_validator(mode="before")
    @classmethod
    def _bare_list(cls, value: Any) -> Any:
        return {"commands": value} if isinstance(value, list) else value


class DockTask(StrictModel):
    """`task: {dock: {dock_id: home_dock}}`: nav2_simple_commander's dockRobotByID, or with
    `dock_pose` (and `dock_type`) its dockRobotByPose. The docking server drives to the
    dock's staging pose first (NavigateToPose) unless `navigate_to_staging_pose` is false."""

    dock_id: str | None = Field(None, min_length=1)
    dock_pose: Pose | None = None
    dock_type: str = ""
    navigate_to_staging_pose: bool = True
    max_staging_time: float = Field(1000.0, gt=0.0, allow_inf_nan=False)

    @model_validator(mode="after")
    def _id_or_pose(self) -> DockTask:
        if (self.dock_id is None) == (self.dock_pose is None):
            raise ValueError("a dock task gives dock_id (a dock of the database) or dock_pose")
        return self


class TaskSpec(StrictModel):
    """Exactly one task."""

    navigate_to_pose: Pose | None = None
    navigate_through_poses: Poses | None = None
    follow_waypoints: Poses | None = None
    explore: ExploreTask | None = None
    drive: DriveTask | None = None
    dock: DockTask | None = None

    @model_validator(mode="before")
    @classmethod
    def _bare_name(cls, value: Any) -> Any:
        """`task: explore` is `task: {explore: {}}`; `explore:` with nothing under it too."""
        if value == "explore":
            return {"explore": {}}
        if isinstance(value, Mapping) and "explore" in value and value["explore"] is None:
            return {**value, "explore": {}}
        return value

    @model_validator(mode="after")
    def _exactly_one(self) -> TaskSpec:
        given = [name for name in type(self).model_fields if getattr(self, name) is not None]
        if len(given) != 1:
            raise ValueError(
                "a task is exactly one of navigate_to_pose, navigate_through_poses, "
                f"follow_waypoints, explore, drive, dock (got {', '.join(given) or 'none'})"
            )
        return self

    @property
    def kind(self) -> str:
        return next(n for n in type(self).model_fields if getattr(self, n) is not None)

    @property
    def poses(self) -> list[tuple[float, float, float]]:
        value = getattr(self, self.kind)
        if self.kind == "navigate_to_pose":
            return [value]
        return list(value) if self.kind in ("navigate_through_poses", "follow_waypoints") else []


class MissionSpec(StrictModel):
    """A whole mission file, as written (paths still relative to it)."""

    mission: str = Field("", max_length=200, description="the mission's name")
    world: str = Field(min_length=1)
    params: str | None = None
    map: str | None = None
    #: Any registered `localizer` or `slam` plugin (amcl, ground_truth, slam,
    #: cartographer, or a user's: checked once the mission's `plugins:` are loaded).
    localization: str = Field("ground_truth", min_length=1, max_length=200)
    #: Cartographer's options file for `localization: cartographer` (relative to the
    #: mission; default: btnav's params/cartographer_2d.lua).
    cartographer_config: str | None = None
    initial_pose: Pose | None = None
    #: The robot to place in the world, replacing the world's own: a description file
    #: (URDF, xacro, Gazebo SDF, `model://NAME`) or a robot block as a world file writes
    #: it (`{description: ..., footprint: ...}`), paths relative to the mission file. A
    #: Gazebo world, which has no btnav robot, takes this one.
    robot: Annotated[Any, AfterValidator(_robot_entry)] = None
    #: The robot's odometry over the world's `robot.odometry`: the keys given here replace
    #: the world's (`{source: laser}`: laser odometry publishes odom -> base_footprint).
    odometry: OdometrySpec | None = None
    tree: str | None = None
    task: TaskSpec
    time_limit: float = Field(
        600.0, gt=0.0, allow_inf_nan=False, description="sim seconds before the task is canceled"
    )
    seed: int = Field(0, ge=0)
    outputs: list[str] = Field(default_factory=lambda: list(DEFAULT_OUTPUTS))
    plugins: list[str] = Field(default_factory=list)
    #: A params key Nav2 skips (a ROS 1 name, an older distribution's, a BT port) is an
    #: error instead of a warning, as `btnav params check --strict` makes it.
    strict_params: bool = False
    #: nav2_bringup's zone launch arguments: `use_keepout_zones` / `use_speed_zones` write
    #: true into the params file's KEEPOUT_ZONE_ENABLED / SPEED_ZONE_ENABLED (the filters'
    #: `enabled`); `keepout_mask` / `speed_mask` (map_server YAMLs, relative to the mission)
    #: are the masks the zone's mask server serves, over its `yaml_filename`.
    use_keepout_zones: bool = False
    use_speed_zones: bool = False
    keepout_mask: str | None = None
    speed_mask: str | None = None
    #: nav2_bringup's `graph` launch argument: the route graph (Nav2's GeoJSON, relative to
    #: the mission) route_server loads, written into the params as its `graph_filepath`.
    route_graph: str | None = None


def mission_place(key: str) -> str:
    """Where a `--set` mission key writes: `mission.seed` -> `seed` (the prefix is optional)."""
    parts = key.split(".")
    return ".".join(parts[1:] if parts[0] == "mission" else parts)


def _apply_overrides(doc: YamlMap, overrides: Mapping[str, Any]) -> YamlMap:
    """`--set mission.KEY=VALUE`: write each value into a copy of the document."""
    doc = copy_tree(doc)
    for key, value in overrides.items():
        parts = mission_place(key).split(".")
        if not all(parts):
            raise MissionError(f"'{key}' is not a dotted mission key", key=key)
        try:
            set_path(doc, parts, value, key)
        except BtnavError as err:
            raise MissionError(err.message, key=key) from None
    return doc


def set_by(key: str | None, changed: Mapping[str, str]) -> str | None:
    """What set `key` or a section above it, from `changed` (dotted place -> `--set K=V`)."""
    if not key:
        return None
    for place, origin in changed.items():
        if key == place or key.startswith((place + ".", place + "[")):
            return origin
    return None


def set_option(key: str, value: Any) -> str:
    """`--set KEY=VALUE` as a user would have typed it (for errors about the value)."""
    text = value if isinstance(value, str) else json.dumps(value)
    return f"--set {key}={text}"


def override_origins(
    overrides: Mapping[str, Any], origins: Mapping[str, str] | None = None
) -> dict[str, str]:
    """Each override key -> where it came from: `origins[key]`, else `--set KEY=VALUE`."""
    given = origins or {}
    return {k: given.get(k) or set_option(k, v) for k, v in overrides.items()}


def load_mission_spec(
    path: str | PathLike[str],
    overrides: Mapping[str, Any] | None = None,
    origins: Mapping[str, str] | None = None,
    *,
    stage: str | None = None,
    stage_maps: Mapping[str, Path] | None = None,
) -> tuple[MissionSpec, Any]:
    """Read and validate a mission file (with `--set mission.*` overrides); the spec and document.

    `origins` says where each override came from (`--set mission.seed=3`, `--seed 3`); an
    error about an overridden value names that, not a line of the file it was never on.
    A mission with `stages:` is read one stage at a time (`stage`, see `stage_doc`).
    """
    file = str(path)
    doc = load_yaml(path)
    if not isinstance(doc, YamlMap):
        raise MissionError(
            "a mission file is a mapping (mission, world, params, map, task, ...)",
            file=file,
            line=getattr(doc, "line", None),
        )
    if stage is not None:
        doc = stage_doc(doc, stage, file, stage_maps)
    elif stage_names(doc, file):
        raise MissionError(
            "this mission runs in stages: run it with `btnav run` (or `run_stages`), or load "
            "one stage with Mission.load(path, stage=NAME)",
            file=file,
            line=doc.line_of(STAGES),
            key=STAGES,
        )
    where = override_origins(overrides or {}, origins)
    changed = {mission_place(k): origin for k, origin in where.items()}
    if overrides:
        try:
            doc = _apply_overrides(doc, overrides)
        except MissionError as err:
            raise err.located(file=where.get(err.key or "")) from None
    try:
        spec = validate(MissionSpec, doc, file=file, error_cls=MissionError)
    except MissionError as err:
        origin = set_by(err.key, changed)
        if origin is not None:
            raise MissionError(
                err.message, file=origin, key=err.key, suggestion=err.suggestion
            ) from None
        raise
    _check_task(spec, doc, file, changed)
    return spec, doc


def _check_task(spec: MissionSpec, doc: Any, file: str, changed: Mapping[str, str]) -> None:
    # A name no plugin has yet may be a mission plugin's: the mission checks it once loaded.
    if spec.task.kind == "explore" and is_registered("localizer", spec.localization):
        key = "task.explore"
        origin = set_by("localization", changed) or set_by(key, changed)
        raise MissionError(
            f"exploring needs a map that grows as the robot drives: localization: slam "
            f"(or cartographer), not {spec.localization}",
            file=origin or file,
            line=None if origin else line_at(doc, ["localization"]) or line_at(doc, ["task"]),
            key="localization",
        )


def resolve(base: Path, value: str) -> Path:
    """A path in a mission, relative to the mission file."""
    p = Path(value).expanduser()
    return Path(os.path.normpath(p if p.is_absolute() else base / p))
