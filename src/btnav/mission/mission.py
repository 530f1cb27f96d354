"""A mission loaded and checked: its files found, params read, plugins imported, tree built.

`Mission.load(path, seed=..., overrides=...)` does every check a run needs before
the clock starts, so a user's mistake anywhere (the mission, its world, params,
map or tree) is one located `BtnavError`, never a failure half-way through a run.
`--set` overrides go to the mission (`mission.seed=3`) or the params
(`local_costmap.local_costmap.inflation_layer.inflation_radius=0.4`).
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import partial
from os import PathLike
from pathlib import Path
from typing import Any, TypeVar

import numpy as np

from ..bt.bundled import find_tree
from ..core.errors import BtnavError, BtnavNote, BtnavWarning, ParamsError, WorldError
from ..core.frames import FrameTree
from ..core.geometry import Pose2D
from ..core.resources import bundled_dir
from ..core.suggest import best_match
from ..core.yaml_io import YamlMap, line_at
from ..localization.amcl.odometry_match import odometry_note
from ..maps.map_io import load_map
from ..maps.occupancy_grid import OCCUPIED, OccupancyGrid
from ..navigators.basic_navigator import BasicNavigator
from ..params.loader import ROS_PARAMETERS
from ..params.paramsfile import ParamsFile
from ..params.updates import _override_target, apply_overrides
from ..plugins import is_registered, load_plugins, names, primary_name
from ..sim.frames import world_frame_tree
from ..sim.world import World
from ..sim.world_spec import WorldSpec, load_world_spec
from .errors import MissionError
from .outputs import OUTPUT_NEEDS, check_outputs
from .param_frames import check_frames
from .route_graph import with_route_graph
from .spec import (
    MissionSpec,
    builds_map,
    load_mission_spec,
    mission_place,
    override_origins,
    resolve,
    set_by,
)
from .zones import load_zoned_params, with_zone_masks

N = TypeVar("N", bound=BasicNavigator)

#: The tree a task's goals run in, by the bt_navigator action that serves them.
TASK_ACTION = {
    "navigate_to_pose": "NavigateToPose",
    "follow_waypoints": "NavigateToPose",  # waypoint_follower sends NavigateToPose goals
    "navigate_through_poses": "NavigateThroughPoses",
    "explore": "Explore",
    "drive": "",  # teleop: no tree
    "dock": "NavigateToPose",  # the docking server's trip to the staging pose
}


def split_overrides(overrides: Mapping[str, Any]) -> tuple[dict[str, Any], dict[str, Any]]:
    """`--set` keys: `mission.*` for the mission file, the rest for the params file.

    A file a `--set` names (`mission.world`, `params`, `map`, and `tree` when it is a
    path rather than a bundled tree's name) is relative to the current directory, as
    any path typed on a command line; the mission file's own paths stay relative to it.
    """
    mission = {k: _from_cwd(k, v) for k, v in overrides.items() if k.split(".")[0] == "mission"}
    params = {k: v for k, v in overrides.items() if k.split(".")[0] != "mission"}
    return mission, params


_FILE_KEYS = ("world", "params", "map", "tree", "route_graph", "keepout_mask", "speed_mask")


def _from_cwd(key: str, value: Any) -> Any:
    if mission_place(key) not in _FILE_KEYS or not isinstance(value, str):
        return value
    path = Path(value).expanduser()
    if path.is_absolute() or (mission_place(key) == "tree" and not _looks_like_a_path(value)):
        return value
    return str(Path.cwd() / path)


def _looks_like_a_path(value: str) -> bool:
    return "/" in value or "\\" in value or value.endswith((".xml", ".yaml", ".yml"))


@dataclass
class Mission:
    spec: MissionSpec
    file: Path
    doc: Any
    world: WorldSpec
    params: ParamsFile
    map_file: Path | None
    tree: str | None
    #: What `--set`/`--seed` changed, by place (`mission.seed`, `amcl.base_frame_id`, in the
    #: spelling errors use) -> the option that did (`--set amcl.base_frame_id=base_foot`).
    set_by: dict[str, str] = field(default_factory=dict)
    #: The SLAM plugin's configuration when it is not a params-file section
    #: (`localization: cartographer`: the loaded `.lua`).
    slam_config: Any = None

    @property
    def name(self) -> str:
        return self.spec.mission or self.file.stem

    @property
    def seed(self) -> int:
        return self.spec.seed

    @property
    def task(self) -> str:
        return self.spec.task.kind

    def where(self, *key: str | int) -> dict[str, Any]:
        """file, line and key of `key` in the mission file, or the `--set` that gave it."""
        return _where(self.file, self.doc, self.set_by, *key)

    # -- loading --------------------------------------------------------------------------

    @classmethod
    def load(
        cls,
        path: str | PathLike[str],
        *,
        seed: int | None = None,
        overrides: Mapping[str, Any] | None = None,
        origins: Mapping[str, str] | None = None,
        stage: str | None = None,
        stage_maps: Mapping[str, Path] | None = None,
    ) -> Mission:
        """Read the mission and everything it names; any mistake is a located `BtnavError`.

        `origins` maps each override key to the option that gave it (`--set K=V` as typed;
        default: rendered from the value), which errors about that value name. One stage of
        a staged mission is `stage`, with `stage_maps` the maps its earlier stages saved.
        """
        file = find_mission(path)
        given = override_origins(dict(overrides or {}), origins)  # as typed
        mission_over, params_over = split_overrides(overrides or {})
        if seed is not None:
            mission_over["mission.seed"] = seed
            given["mission.seed"] = f"--seed {seed}"
        spec, doc = load_mission_spec(file, mission_over, given, stage=stage, stage_maps=stage_maps)
        base = file.parent
        changed = {"mission." + mission_place(k): given[k] for k in mission_over}
        where = partial(_where, file, doc, changed)

        if spec.plugins:
            load_plugins(spec.plugins, base, file=str(file))
        check_outputs(spec.outputs, lambda i: where("outputs", i))
        _check_localization(spec, where)
        _check_output_needs(spec, where)

        world_path = _existing(resolve(base, spec.world), "world", where)
        world = load_world_spec(world_path, robot=_robot_block(spec, doc, file, changed))
        if spec.initial_pose is not None:
            world.robot.pose = spec.initial_pose
        if spec.odometry is not None:  # the keys the mission gives replace the world's
            given = {k: getattr(spec.odometry, k) for k in spec.odometry.model_fields_set}
            world.robot.odometry = world.robot.odometry.model_copy(update=given)

        params_path = (
            _existing(resolve(base, spec.params), "params", where)
            if spec.params is not None
            else bundled_dir("params") / "nav2_params.yaml"
        )
        strict = f"strict_params: true in {file}" if spec.strict_params else None
        params = load_zoned_params(spec, params_path, strict=strict)
        if params_over:
            params, params_set = _override_params(params, params_over, given)
            changed.update(params_set)
        params = with_zone_masks(spec, base, params, where)
        params = with_route_graph(spec, base, params, where)
        if spec.task.kind == "dock" and "docking_server" not in params:
            raise MissionError(
                f"a dock task needs the docking_server, and {params_path} has no "
                "docking_server section (Nav2's nav2_params.yaml has one)",
                **where("task", "dock"),
            )

        map_file = None
        if spec.map is not None:
            map_file = _existing(resolve(base, spec.map), "map", where)
            grid = load_map(map_file)  # read once now, so a bad map is a load error
            for warning in task_pose_warnings(spec, grid, map_file, where):
                warnings.warn(warning, stacklevel=2)
            if spec.localization == "amcl":
                _check_amcl_start(spec, world, params, grid, map_file, where, changed)
        elif not builds_map(spec.localization):
            raise MissionError(
                f"localization '{spec.localization}' needs a map; give `map:` "
                "(or use localization: slam to make one)",
                **where("localization"),
            )

        tree = None
        if spec.tree is not None:
            try:
                tree = str(find_tree(spec.tree, base_dir=base))
            except BtnavError as err:
                raise _located(err, where("tree")) from None
        slam_config = _cartographer_config(spec, base, where)
        return cls(spec, file, doc, world, params, map_file, tree, changed, slam_config)

    # -- running --------------------------------------------------------------------------

    def build_world(self) -> World:
        try:
            return World(self.world, seed=self.seed, file=self.world.file)
        except WorldError as err:
            if self.spec.initial_pose is not None and err.key == "robot.pose":
                own = err.file == str(self.file)  # the mission's robot, at initial_pose
                where = "" if own else f" (in the world {err.file})"
                raise MissionError(f"{err.message}{where}", **self.where("initial_pose")) from None
            raise

    def frame_tree(self, world: World | None = None) -> FrameTree:
        """The robot's frame tree at t = 0 (REP-105 and its sensors' frames)."""
        return world_frame_tree(world if world is not None else self.build_world(), self.seed)

    def _odometry_error(self, err: WorldError) -> BtnavError:
        """A world error about the odometry's source, blamed on the mission when the
        mission chose that source (laser odometry on a robot with no lidar)."""
        odometry = self.spec.odometry
        if err.key != "robot.odometry.source" or odometry is None:
            return err
        if "source" not in odometry.model_fields_set:
            return err
        return MissionError(
            f"{err.message} (the world {err.file} has none)", **self.where("odometry", "source")
        )

    def _tree_key(self, action: str) -> dict[str, Any]:
        """Where the task's tree is named: the mission's `tree`, else bt_navigator's default."""
        if self.tree is not None:
            return self.where("tree")
        key = (
            "default_nav_through_poses_bt_xml"
            if action == "NavigateThroughPoses"
            else ("default_nav_to_pose_bt_xml")
        )
        origin = self.set_by.get(f"bt_navigator.{key}")
        raw = self.params.raw.get("bt_navigator")
        return dict(
            file=origin or str(self.params.path),
            line=line_at(raw, [ROS_PARAMETERS, key]) if raw is not None and not origin else None,
            key=f"bt_navigator.{key}",
        )

    def navigator(self, cls: type[N] = BasicNavigator) -> N:  # type: ignore[assignment]
        """The whole bring-up (world, servers, bt_navigator, waypoint_follower) at t = 0;
        first, every frame the params name is checked against the robot's frame tree."""
        world = self.build_world()
        check_frames(self.params, self.frame_tree(world), self.set_by)
        try:
            nav = cls.from_files(
                world,
                self.params,
                self.map_file,
                seed=self.seed,
                localization=self.spec.localization,
                slam_config=self.slam_config,
            )
        except WorldError as err:
            raise self._odometry_error(err) from None
        action = TASK_ACTION[self.task]
        try:  # the task's tree is built now, so a bad tree is a load error, not a failed run
            if action:
                nav.use_tree(self.tree, action)
        except BtnavError as err:
            raise _located(err, self._tree_key(action)) from None
        start = self.spec.initial_pose
        if start is None and self.spec.localization == "amcl" and not _amcl_sets_pose(self):
            start = self.world.robot.pose  # AMCL starts where the mission starts the robot
        if start is not None:
            nav.set_initial_pose(Pose2D(*start))
        self._note_amcl_alphas(nav)
        return nav

    def _note_amcl_alphas(self, nav: BasicNavigator) -> None:
        """The one `btnav: note:` for amcl alphas far from the world's odometry noise,
        once the bring-up cannot fail any more (a mistake stays a single line)."""
        if self.spec.localization != "amcl":
            return
        note = odometry_note(nav.world.spec.robot.odometry, nav.runtime.localizer.params)
        if note is not None:
            amcl = self.params.server("amcl") if "amcl" in self.params else None
            line = amcl.line if amcl is not None else None
            warnings.warn(
                BtnavNote(note, file=self.params.path, line=line, key="amcl"), stacklevel=3
            )


def _robot_block(spec: MissionSpec, doc: Any, file: Path, changed: Mapping[str, str]) -> Any:
    """The mission's `robot:` as a robot block of the mission file (a bare path is its
    `description`), starting at `initial_pose` unless it gives a pose; None without one."""
    given = doc.get("robot") if isinstance(doc, YamlMap) else None
    if spec.robot is None or given is None:
        return None
    origin = set_by("robot", changed)
    line = None if origin else line_at(doc, ["robot"])
    if isinstance(given, str):
        block = YamlMap({"description": given}, file=origin or str(file), line=line)
        block.key_lines = {"description": line} if line else {}
    else:
        block = YamlMap(given, file=getattr(given, "file", None) or str(file), line=line)
        block.key_lines = dict(getattr(given, "key_lines", {}))
    if "pose" not in block and spec.initial_pose is not None:
        block["pose"] = list(spec.initial_pose)
        pose_line = line_at(doc, ["initial_pose"])
        if pose_line:
            block.key_lines["pose"] = pose_line
    return block


def _amcl_sets_pose(mission: Mission) -> bool:
    """Whether Nav2's amcl section gives the initial pose itself (`set_initial_pose`)."""
    return "amcl" in mission.params and bool(mission.params.server("amcl").model.set_initial_pose)


def _map_problem(grid: OccupancyGrid, map_file: Path, x: float, y: float) -> str | None:
    """What is wrong with (x, y) on the map, for a message: off it, or in an occupied cell."""
    row, col = grid.world_to_cell([(x, y)])[0]
    if not grid.in_bounds(np.array([row, col])):
        (x0, y0), (x1, y1) = _map_extent(grid)
        return f"is outside the map ({map_file} covers x {x0:g} to {x1:g}, y {y0:g} to {y1:g})"
    if grid.data[row, col] >= OCCUPIED:
        return f"is inside an obstacle of the map ({map_file})"
    return None


def _check_amcl_start(
    spec: MissionSpec,
    world: WorldSpec,
    params: ParamsFile,
    grid: OccupancyGrid,
    map_file: Path,
    where: Any,
    changed: Mapping[str, str],
) -> None:
    """AMCL needs its initial pose on a free cell of the map: the mission's `initial_pose`
    (or the world's start pose), and amcl's `initial_pose` when `set_initial_pose`."""
    if "amcl" in params and params.server("amcl").model.set_initial_pose:
        ip = params.server("amcl").model.initial_pose
        problem = _map_problem(grid, map_file, ip.x, ip.y)
        if problem is not None:
            raw = params.raw.get("amcl")
            origin = set_by("amcl.initial_pose", changed)
            raise ParamsError(
                f"amcl's initial_pose [{ip.x:g}, {ip.y:g}, {ip.yaw:g}] {problem}; "
                "AMCL cannot start there",
                file=origin or str(params.path),
                line=None
                if origin or raw is None
                else line_at(raw, [ROS_PARAMETERS, "initial_pose"]),
                key="amcl.initial_pose",
            )
    pose = spec.initial_pose if spec.initial_pose is not None else tuple(world.robot.pose)
    problem = _map_problem(grid, map_file, pose[0], pose[1])
    if problem is None:
        return
    shown = "[" + ", ".join(f"{v:g}" for v in pose) + "]"
    message = f"the initial pose {shown} {problem}; AMCL cannot start there"
    if spec.initial_pose is not None:
        raise MissionError(message, **where("initial_pose"))
    raise MissionError(
        f"{message} (the world's robot.pose; give the mission an initial_pose)",
        file=str(world.file) if getattr(world, "file", None) else None,
        key="robot.pose",
    )


def task_pose_warnings(
    spec: MissionSpec, grid: OccupancyGrid, map_file: Path, where: Any
) -> list[BtnavWarning]:
    """A warning for each task pose in a lethal cell of the map or outside it.

    Not an error: Nav2 takes such a goal and fails it (the planner's GOAL_OCCUPIED or
    GOAL_OUTSIDE_MAP), and a run that shows that may be the point. `where(*key)` places
    a pose in the mission file (or on the `--set` that gave it).
    """
    kind = spec.task.kind
    poses = spec.task.poses
    if not poses:
        return []
    keys: list[tuple[str | int, ...]] = (
        [("task", kind)]
        if kind == "navigate_to_pose"
        else [("task", kind, i) for i in range(len(poses))]
    )
    found = []
    for pose, key in zip(poses, keys, strict=True):
        problem = _map_problem(grid, map_file, pose[0], pose[1])
        if problem is None:
            continue
        shown = "[" + ", ".join(f"{v:g}" for v in pose) + "]"
        found.append(
            BtnavWarning(f"task pose {shown} {problem}; Nav2 will try it and fail", **where(*key))
        )
    return found


def _map_extent(grid: OccupancyGrid) -> tuple[tuple[float, float], tuple[float, float]]:
    corners = grid.origin.transform_points(
        [(0.0, 0.0), (grid.size_m[0], 0.0), (0.0, grid.size_m[1]), grid.size_m]
    )
    (x0, y0), (x1, y1) = corners.min(axis=0), corners.max(axis=0)
    return (float(x0), float(y0)), (float(x1), float(y1))


def find_mission(name: str | PathLike[str]) -> Path:
    """A mission file, or a bundled mission's bare name (`office_tour`)."""
    path = Path(name)
    if path.is_file() or path.parent != Path(".") or path.suffix not in ("", ".yaml", ".yml"):
        return path  # a missing file here is load_yaml's located error
    folder = bundled_dir("missions")
    bundled = sorted(p.stem for p in folder.glob("*.yaml"))
    if path.stem in bundled:
        return folder / f"{path.stem}.yaml"
    raise MissionError(
        f"no mission file '{name}', nor a bundled mission of that name "
        f"(bundled: {', '.join(bundled) or 'none'})",
        suggestion=best_match(path.stem, bundled),
    )


def _where(file: Path, doc: Any, changed: Mapping[str, str], *key: str | int) -> dict[str, Any]:
    """file, line and key of `key` in the mission file for an error; for a value `--set`
    gave (`changed`: `mission.<place>` -> option), that option instead of a line."""
    dotted = "mission." + ".".join(str(k) for k in key)
    origin = set_by(dotted, changed)
    if origin is not None:
        return dict(file=origin, line=None, key=list(key))
    return dict(file=str(file), line=line_at(doc, key), key=list(key))


def _override_params(
    params: ParamsFile, overrides: Mapping[str, Any], given: Mapping[str, str]
) -> tuple[ParamsFile, dict[str, str]]:
    """`apply_overrides`, with an error about a value blamed on the `--set` that gave it.

    Also returns what each override changed, in the key spelling errors and frame
    checks use (`local_costmap.local_costmap.inflation_layer.inflation_radius`).
    """
    changed: dict[str, str] = {}
    try:
        for key in overrides:
            node_path, rest = _override_target(params.raw, key)
            changed[".".join([*node_path, *rest])] = given[key]
        return apply_overrides(params, overrides), changed
    except ParamsError as err:
        if err.file is not None:
            raise
        origin = set_by(err.key, changed) or given.get(err.key or "")
        if origin is None and len(overrides) == 1:
            origin = given[next(iter(overrides))]
        if origin is None:
            raise
        message = err.message.removesuffix(" (value given by --set)")
        raise ParamsError(message, file=origin, key=err.key, suggestion=err.suggestion) from None


def _located(err: BtnavError, where: dict[str, Any]) -> BtnavError:
    """An error from a file the mission names keeps its place; one without gets the mission's."""
    return err if err.file else err.located(**where)


def _existing(path: Path, key: str, where: Any) -> Path:
    if not path.is_file():
        raise MissionError(f"{key} file not found: {path}", **where(key))
    return path


#: Localisations that build their map (plugins of kind `slam`).


def _cartographer_config(spec: MissionSpec, base: Path, where: Any) -> Any:
    """The loaded `.lua` of `localization: cartographer` (its mistakes are load errors)."""
    if spec.localization != "cartographer":
        if spec.cartographer_config is not None:
            raise MissionError(
                "cartographer_config is read only with localization: cartographer",
                **where("cartographer_config"),
            )
        return None
    from ..slam.cartographer.config import load_cartographer_config

    if spec.cartographer_config is None:
        return load_cartographer_config(bundled_dir("params") / "cartographer_2d.lua")
    path = _existing(resolve(base, spec.cartographer_config), "cartographer_config", where)
    return load_cartographer_config(path)


def _check_output_needs(spec: MissionSpec, where: Any) -> None:
    """An output the localiser cannot give (`pose_graph` without slam_toolbox's graph)."""
    for i, name in enumerate(spec.outputs):
        need = OUTPUT_NEEDS.get(name)
        if need is None or primary_name("slam", spec.localization) in need:
            continue
        raise MissionError(
            f"output '{name}' is slam_toolbox's serialised pose graph: it needs "
            f"localization: {' or '.join(need)}, and localization: {spec.localization} "
            "keeps no graph that mode: localization can load",
            **where("outputs", i),
        )


def _check_localization(spec: MissionSpec, where: Any) -> None:
    """`localization:` names a registered localiser or SLAM plugin (a mission plugin's
    too); exploring needs one whose map grows."""
    name = spec.localization
    if not (is_registered("localizer", name) or is_registered("slam", name)):
        have = names("localizer") + names("slam")
        raise MissionError(
            f"unknown localization '{name}'; btnav has: {', '.join(have)} "
            "(or register a localizer plugin and list it under plugins:)",
            suggestion=best_match(
                name, names("localizer", aliases=True) + names("slam", aliases=True)
            ),
            **where("localization"),
        )
    if spec.task.kind == "explore" and not builds_map(name):
        raise MissionError(
            f"exploring needs a map that grows as the robot drives: localization: slam "
            f"(or cartographer), not {name}",
            **where("localization"),
        )
