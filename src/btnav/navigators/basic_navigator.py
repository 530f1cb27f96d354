"""The Python API: nav2_simple_commander's BasicNavigator in Python spelling.

`btnav.Navigator` (in `mission/`) is this class plus `from_mission`.

```python
nav = BasicNavigator.from_files("worlds/small_office.yaml", "params/nav2_params.yaml",
                           "maps/small_office.yaml", seed=0)
nav.go_to_pose((6.0, 3.0, 0.0))
while not nav.is_task_complete():      # each poll advances sim time (rclpy's spin)
    feedback = nav.get_feedback()
result = nav.get_result()              # NavResult: outcome, error_code, error_msg, value
```

One task at a time, as BasicNavigator: a new task replaces the handle the
navigator polls (the server preempts or aborts the old goal as Nav2 does).
`is_task_complete()` steps the runtime for up to `poll_period` sim seconds (0.1 s,
BasicNavigator's spin timeout) and says whether the task has ended. Synchronous
helpers (`get_path`, `cancel_task`) step until their answer is there.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from os import PathLike
from pathlib import Path as FilePath
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # typing.Self is 3.11+; the annotation is never evaluated
    from typing_extensions import Self

from ..core.error_codes import NavResult
from ..core.geometry import Pose2D
from ..core.messages import Path, Twist
from ..core.nav2_docking_msgs import DockRobotGoal, UndockRobotGoal
from ..core.nav2_msgs import (
    BackUpGoal,
    ComputePathToPoseGoal,
    DriveGoal,
    ExploreGoal,
    FollowWaypointsGoal,
    NavigateThroughPosesGoal,
    NavigateToPoseGoal,
    SpinGoal,
)
from ..maps.map_io import load_map, save_map
from ..nav.actions import GoalHandle
from ..nav.runtime import Runtime
from ..nav.stack import NavStack
from ..nav.teleop import DriveServer
from ..params.loader import load_params
from ..params.map_io import MapSaverParams
from ..params.paramsfile import ParamsFile, ServerParams
from ..plugins import is_registered, primary_name
from ..sim.world import World
from ..slam.karto.slam_toolbox import default_slam_params
from .bt_navigator import BtNavigator
from .explore_navigator import ExploreNavigator
from .waypoint_follower import WaypointFollower

PoseArg = Pose2D | Sequence[float]


def _pose(p: Any) -> Any:
    return p if hasattr(p, "x") or hasattr(p, "pose") else Pose2D(*p)


class BasicNavigator:
    """A whole Nav2 bring-up on one runtime, driven like BasicNavigator."""

    poll_period = 0.1

    def __init__(
        self,
        world: World,
        runtime: Runtime,
        stack: NavStack,
        bt_navigator: BtNavigator,
        waypoint_follower: WaypointFollower,
    ) -> None:
        self.world = world
        self.runtime = runtime
        self.stack = stack
        self.bt_navigator = bt_navigator
        self.waypoint_follower = waypoint_follower
        self.handle: GoalHandle[Any] | None = None

    @classmethod
    def from_files(
        cls,
        world: World | str | PathLike[str],
        params: str | PathLike[str] | ParamsFile,
        map: str | PathLike[str] | None = None,
        *,
        seed: int = 0,
        localization: str = "ground_truth",
        tree: str | None = None,
        slam_config: Any = None,
    ) -> Self:
        """World, params and map files (or a built `World`); `tree` replaces bt_navigator's
        default NavigateToPose tree (a file, or a bundled tree's bare name)."""
        w = world if isinstance(world, World) else World.from_file(world, seed=seed)
        rt = Runtime(w, seed=seed)
        pf = params if isinstance(params, ParamsFile) else load_params(params)
        kind = "slam" if is_registered("slam", localization) else "localizer"
        section = primary_name(kind, localization)  # slam_toolbox's section for `slam` too
        has_section = section in ("amcl", "slam_toolbox") and section in pf
        model = pf.server(section).model if has_section else None
        if section == "slam_toolbox" and model is None:  # Nav2's slam_launch.py default file
            model = default_slam_params()
        if localization == "cartographer":  # its .lua, not a params-file section
            model = slam_config
        rt.use_localizer(localization, model, kind=kind)
        grid = load_map(map) if map is not None else None
        stack = NavStack.build(rt, pf, grid, seed=seed)
        set_map = getattr(rt.localizer, "set_map", None)
        if set_map is not None:  # AMCL takes map_server's map, as Nav2's `map` topic
            stack.map_server.subscribe(set_map)
        subscribe_map = getattr(rt.localizer, "subscribe_map", None)
        if subscribe_map is not None:  # SLAM's map goes where map_server's would
            subscribe_map(stack.map_server.load_map)
            stack.planner_server.grow_into_unknown = True  # goals beyond the map so far
        bt = BtNavigator(rt, stack, pf, base_dir=FilePath.cwd())
        wf = rt.add(WaypointFollower(rt, pf))
        stack.servers["bt_navigator"] = bt
        stack.servers["waypoint_follower"] = wf
        nav = cls(w, rt, stack, bt, wf)
        if tree:
            nav.use_tree(tree)
        return nav

    def use_tree(self, tree: str | None, action: str = "NavigateToPose") -> None:
        """Make `tree` (None: keep bt_navigator's default) the default tree of the `action`
        navigators (NavigateToPose, which waypoint_follower's goals use too, or
        NavigateThroughPoses), built and validated now so a bad tree fails here and not
        at the first goal."""
        for navigator in self._navigators(action):
            if tree:
                navigator.default_tree = tree
            navigator.load()

    def _navigators(self, action: str) -> list[Any]:
        """bt_navigator's navigators of `action`; the Explore navigator is added when the
        params file lists none (Nav2's files do not know it)."""
        found = [n for n in self.bt_navigator.navigators.values() if n.action == action]
        if not found and action == ExploreNavigator.action_name:
            found = [self.bt_navigator.add_navigator("explore", ExploreNavigator("explore"))]
        return found

    # -- tasks ------------------------------------------------------------------------------

    def _send(self, server: str, goal: Any) -> bool:
        self.handle = self.runtime.action_client(server).send_goal(goal)
        return self.handle.accepted

    def go_to_pose(self, pose: PoseArg, behavior_tree: str = "") -> bool:
        """NavigateToPose; False if the goal was rejected."""
        return self._send("navigate_to_pose", NavigateToPoseGoal(_pose(pose), behavior_tree))

    def go_through_poses(self, poses: Sequence[PoseArg], behavior_tree: str = "") -> bool:
        """NavigateThroughPoses; False if the goal was rejected."""
        goal = NavigateThroughPosesGoal([_pose(p) for p in poses], behavior_tree)
        return self._send("navigate_through_poses", goal)

    def follow_waypoints(self, poses: Sequence[PoseArg]) -> bool:
        """FollowWaypoints (waypoint_follower): one NavigateToPose per pose."""
        return self._send("follow_waypoints", FollowWaypointsGoal([_pose(p) for p in poses]))

    def explore(self, behavior_tree: str = "") -> bool:
        """Explore until no reachable frontier is left (the bundled `explore` tree)."""
        navigator = self._navigators(ExploreNavigator.action_name)[0]
        return self._send(navigator.name, ExploreGoal(behavior_tree))

    def drive(self, commands: Sequence[Sequence[float]], *, assisted: bool = False) -> bool:
        """Teleop: hold each `(linear_x, angular_z, seconds)` in turn, then stop; `assisted`
        drives through Nav2's AssistedTeleop (BasicNavigator's assistedTeleop with the
        commands on `cmd_vel_teleop`)."""
        if "drive" not in self.runtime.action_servers:
            self.runtime.add(DriveServer(self.runtime))
        goal = DriveGoal([tuple(map(float, c)) for c in commands], assisted=assisted)
        return self._send("drive", goal)

    def dock_robot_by_id(
        self,
        dock_id: str,
        navigate_to_staging_pose: bool = True,
        max_staging_time: float = 1000.0,
    ) -> bool:
        """DockRobot at a dock of the docking server's database (dockRobotByID)."""
        goal = DockRobotGoal(
            dock_id=dock_id,
            navigate_to_staging_pose=navigate_to_staging_pose,
            max_staging_time=max_staging_time,
        )
        return self._send("dock_robot", goal)

    def dock_robot_by_pose(
        self,
        dock_pose: PoseArg,
        dock_type: str = "",
        navigate_to_staging_pose: bool = True,
        max_staging_time: float = 1000.0,
    ) -> bool:
        """DockRobot at a dock given by its pose in map and plugin type (dockRobotByPose)."""
        goal = DockRobotGoal(
            use_dock_id=False,
            dock_pose=_pose(dock_pose),
            dock_type=dock_type,
            navigate_to_staging_pose=navigate_to_staging_pose,
            max_staging_time=max_staging_time,
        )
        return self._send("dock_robot", goal)

    def undock_robot(self, dock_type: str = "") -> bool:
        """UndockRobot from the dock the robot is on (undockRobot)."""
        return self._send("undock_robot", UndockRobotGoal(dock_type=dock_type))

    def spin(self, spin_dist: float = 1.57, time_allowance: float = 10.0) -> bool:
        return self._send("spin", SpinGoal(spin_dist, time_allowance))

    def backup(
        self, backup_dist: float = 0.15, backup_speed: float = 0.025, time_allowance: float = 10.0
    ) -> bool:
        return self._send("backup", BackUpGoal(backup_dist, backup_speed, time_allowance))

    def is_task_complete(self) -> bool:
        """Advance sim time (up to `poll_period`) and say whether the task has ended."""
        h = self.handle
        if h is None or h.done:
            return True
        self.runtime.run_until(lambda: h.done, self.poll_period)
        return h.done

    def get_feedback(self) -> Any:
        return self.handle.feedback if self.handle is not None else None

    def get_result(self) -> NavResult | None:
        """The task's result (outcome, Nav2's error_code and error_msg, value), None while running."""
        return self.handle.result if self.handle is not None and self.handle.done else None

    def cancel_task(self, timeout: float = 5.0) -> bool:
        """Cancel the running task and step until the server has ended it and the base has
        stopped (with a velocity smoother the base ramps down after the server's zero)."""
        h = self.handle
        if h is None or h.done:
            return False
        h.cancel()
        ended = self.runtime.run_until(lambda: h.done, timeout)
        self.runtime.run_until(lambda: self.runtime.cmd_vel == Twist(), timeout)
        return ended

    def wait_until_done(
        self, timeout: float = 300.0, poll: Callable[[], None] | None = None
    ) -> NavResult | None:
        """Poll until the task ends or `timeout` sim seconds pass; the result (None: still
        running). `poll()` is called before each check (a live status; it must only read)."""
        h = self.handle
        if h is not None:
            if poll is None:
                self.runtime.run_until(lambda: h.done, timeout)
            else:

                def done() -> bool:
                    poll()
                    return h.done

                self.runtime.run_until(done, timeout)
        return self.get_result()

    def set_initial_pose(self, pose: PoseArg, covariance: Any = None) -> None:
        """The localiser's initial estimate in the map frame (BasicNavigator's
        /initialpose; `covariance` 3x3 over x, y, yaw, zeros by default as BasicNavigator
        sends); a localiser without one (ground truth) has nothing to set."""
        setter = getattr(self.runtime.localizer, "set_initial_pose", None)
        if setter is not None:
            setter(_pose(pose), covariance)

    def reinitialize_global_localization(self) -> bool:
        """AMCL's reinitialize_global_localization service: particles spread uniformly over
        the map's free space. False if the localiser has no such service."""
        service = getattr(self.runtime.localizer, "reinitialize_global_localization", None)
        if service is None:
            return False
        service()
        return True

    # -- services ---------------------------------------------------------------------------

    def get_path(
        self, start: PoseArg | None, goal: PoseArg, planner_id: str = "", use_start: bool = True
    ) -> Path | None:
        """ComputePathToPose from `start` (None: the robot) to `goal`; None if it failed."""
        h = self.runtime.action_client("compute_path_to_pose").send_goal(
            ComputePathToPoseGoal(
                _pose(goal),
                planner_id,
                _pose(start) if start is not None else None,
                use_start and start is not None,
            )
        )
        self.runtime.run_until(lambda: h.done, 5.0)
        if not h.succeeded or h.result is None:
            return None
        value = h.result.value
        return getattr(value, "path", value)

    def clear_all_costmaps(self) -> None:
        self.stack.clear_all_costmaps()

    def clear_local_costmap(self) -> None:
        self.stack.local_costmap.costmap_ros.clear_entirely()

    def clear_global_costmap(self) -> None:
        self.stack.global_costmap.costmap_ros.clear_entirely()

    def save_map(
        self,
        path: str | PathLike[str],
        *,
        mode: str = "trinary",
        image_format: str | None = None,
    ) -> tuple[FilePath, FilePath]:
        """`map_saver_cli -f PATH`: the map the stack serves, written as map_saver writes it
        (cells classified by the `map_saver:` section's `free_thresh_default` and
        `occupied_thresh_default`); returns the YAML's and the image's paths."""
        grid = self.stack.map_server.map
        if grid is None:
            raise RuntimeError("no map to save: map_server has none (and no SLAM runs)")
        params = self.stack.params
        saver = params.server("map_saver").model if "map_saver" in params else MapSaverParams()
        return save_map(
            grid,
            path,
            mode=mode,
            free_thresh=saver.free_thresh_default,
            occupied_thresh=saver.occupied_thresh_default,
            image_format=image_format,
        )

    def set_parameters(self, server: str, changes: Mapping[str, Any]) -> ServerParams:
        """Nav2's dynamic parameters on any server, validated like the file."""
        return self.stack.set_parameters(server, changes)

    # -- state ------------------------------------------------------------------------------

    @property
    def now(self) -> float:
        return self.runtime.now

    @property
    def robot_pose(self) -> Pose2D:
        """The ground-truth pose (for tests and metrics)."""
        return self.world.robot_pose
