"""bt_navigator: NavigateToPose and NavigateThroughPoses, each an action server ticking a tree.

As Nav2's `BtActionServer` does for a new goal: the blackboard gets the goal (`goal`,
or `goals` for NavigateThroughPoses), every `<prefix>_error_code` of
`error_code_name_prefixes` is set to 0 and its `_error_msg` to "", and
`number_recoveries` to 0; then the tree is ticked every `bt_loop_duration` ms of sim
time until it leaves RUNNING. A failed tree's result carries the lowest non-zero
`<prefix>_error_code` on the blackboard (Nav2's `populateErrorCode`), else the
action's UNKNOWN. A cancel halts the tree (its action nodes cancel their servers).
A new goal for the running navigator preempts it as Nav2's `onPreempt` does: the goal
on the blackboard changes while the tree keeps running (the tree's GoalUpdated
replans); a goal naming another tree than the running one is rejected.

Feedback, each tick: `current_pose` (the robot in `global_frame`), `distance_remaining`
along the blackboard's `path` from the pose of it closest to the robot (within
`search_window` metres along the path of the last closest pose; `path_progress`),
`navigation_time` (sim seconds since the goal), `estimated_time_remaining` and
`number_of_recoveries`.
The blackboard is py_trees' (process-wide), so one tree runs at a time, as in Nav2.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

from py_trees.blackboard import Blackboard
from py_trees.common import Status
from pydantic import Field

from ..bt import blackboard, load_tree
from ..bt.base import R, S
from ..bt.bundled import find_tree
from ..bt.nav2_context import RECOVERIES_KEY, recovery_count
from ..core import fmath
from ..core.error_codes import NavigateThroughPosesError, NavigateToPoseError, NavResult
from ..core.errors import FrameError, PluginError
from ..core.geometry import Pose2D
from ..core.messages import Path
from ..core.nav2_msgs import (
    NavigateThroughPosesFeedback,
    NavigateThroughPosesGoal,
    NavigateToPoseFeedback,
    NavigateToPoseGoal,
)
from ..core.suggest import best_match
from ..nav.actions import ActionServer, GoalHandle
from ..nav.runtime import Runtime, Stage
from ..nav.server_plugins import make_plugin
from ..params.paramsfile import ParamsFile, ServerParams
from ..params.schema import ParamsModel, Why, ignored
from ..plugins import names, register
from .path_progress import PathProgress


def _pose(value: Any) -> Any:
    return value if hasattr(value, "x") or hasattr(value, "pose") else Pose2D(*value)


def blackboard_value(key: str, default: Any = None) -> Any:
    """The tree's blackboard entry `key` (py_trees' root namespace), or `default`."""
    if "." not in key and "/" not in key:  # a plain key
        return blackboard.read("/" + key, default)
    try:
        return Blackboard.get("/" + key)
    except KeyError:
        return default


def _blackboard_set(key: str, value: Any) -> None:
    blackboard.write("/" + key, value)


class NavigatorParams(ParamsModel):
    """A navigator's own section of bt_navigator's params (`navigate_to_pose:` ...)."""

    search_window: float = Field(
        2.0, gt=0.0, description="m along the path searched for the pose closest to the robot"
    )
    enable_groot_monitoring: bool = ignored(False, Why.GROOT)
    groot_server_port: int = ignored(1667, Why.GROOT)


class BehaviorTreeNavigator(ActionServer[Any]):
    """One of bt_navigator's navigators: an action server that runs a tree per goal.

    A `navigator` plugin, built as `cls(name, params)` and then `configure(bt_navigator)`
    (Nav2's `on_configure`), which gives it the runtime, the loop rate and its default tree.
    """

    stage = Stage.NAVIGATOR
    Params = NavigatorParams
    #: The action this navigator serves, and the bt_navigator key of its default tree.
    action_name = "NavigateToPose"
    default_tree_key = "default_nav_to_pose_bt_xml"
    goal_type: type = NavigateToPoseGoal
    feedback_type: type = NavigateToPoseFeedback

    def __init__(self, name: str, params: NavigatorParams | None = None) -> None:
        super().__init__(self.action_name, name)
        self.params = params if params is not None else self.Params()
        self.bt: Any = None
        self.default_tree = ""
        self.tree_file: str | None = None
        self.root: Any = None
        self.start_time = 0.0
        # distance_remaining along the blackboard's path (the window read when it is used)
        self.progress = PathProgress(lambda: self.search_window)
        self.ticks = 0
        self._cancel_deadline: float | None = None

    def configure(self, bt: BtNavigator) -> None:
        """Join `bt` (bt_navigator): its loop rate, and its default tree for this action."""
        self.bt = bt
        self.rate = 1000.0 / bt.params.bt_loop_duration
        self.default_tree = getattr(bt.params, self.default_tree_key)
        # read once, as Nav2's navigators read them on configure (a params model's attributes
        # are slow reads, and the feedback wants them every tick)
        self._pose_frames = (bt.params.global_frame, bt.params.robot_base_frame)

    # -- the tree -------------------------------------------------------------------------

    def load(self, tree: str = "") -> None:
        """Build `tree` (default: this navigator's default tree) unless it is the loaded one;
        a bad tree raises its located `BtnavError`."""
        name = tree or self.default_tree
        path = str(find_tree(name, base_dir=self.bt.base_dir))
        if path != self.tree_file or self.bt.params.always_reload_bt_xml:
            self.root = load_tree(path, clock=self.bt.runtime.clock, context=self.bt.context)
            self.tree_file = path
            self.bt.notify(self, self.bt.runtime.now)  # listeners meet the tree before its ticks

    def _halt(self) -> None:
        if self.root is not None and self.root.status == Status.RUNNING:
            self.root.stop(Status.INVALID)
            self.bt.notify(self, self.bt.runtime.now)

    # -- goals ------------------------------------------------------------------------------

    def validate_goal(self, goal: Any) -> str | None:
        try:
            find_tree(goal.behavior_tree or self.default_tree, base_dir=self.bt.base_dir)
        except Exception as exc:
            return f"behavior tree '{goal.behavior_tree}' could not be loaded: {exc}"
        return None

    def _set_goal(self, goal: Any) -> None:
        _blackboard_set("goal", _pose(goal.pose))

    def on_start(self, handle: GoalHandle[Any], now: float) -> NavResult | None:
        self.bt.halt_others(self)
        try:
            self.load(handle.goal.behavior_tree)
        except Exception as exc:
            return NavResult.failure(
                self.codes.FAILED_TO_LOAD_BEHAVIOR_TREE, f"{type(exc).__name__}: {exc}"
            )
        for prefix in self.bt.params.error_code_name_prefixes:
            _blackboard_set(f"{prefix}_error_code", 0)
            _blackboard_set(f"{prefix}_error_msg", "")
        self._begin_goal(handle, now)
        self.root.stop(Status.INVALID)  # a fresh tree (Nav2 halts it after every goal)
        return self.execute(handle, now)

    def _begin_goal(self, handle: GoalHandle[Any], now: float) -> None:
        self.start_time = now
        self._cancel_deadline = None
        self.progress.reset()
        _blackboard_set(RECOVERIES_KEY.strip("/"), 0)
        self._set_goal(handle.goal)

    def on_preempt(
        self, old: GoalHandle[Any], new: GoalHandle[Any], now: float
    ) -> NavResult | None:
        wanted = new.goal.behavior_tree
        same = not wanted or str(find_tree(wanted, base_dir=self.bt.base_dir)) == self.tree_file
        if not same or self.root is None:
            # Nav2 rejects a preempting goal that asks for another tree; the old one is gone
            # already here, so start the new one afresh.
            self._halt()
            return self.on_start(new, now)
        self._begin_goal(new, now)
        return self.execute(new, now)

    def execute(self, handle: GoalHandle[Any], now: float) -> NavResult | None:
        root = self.root
        root.tick_once()
        self.ticks += 1
        if self.bt.tick_listeners:
            self.bt.notify(self, now)
        status = root.status
        handle.publish_feedback(self._feedback(now), now)
        if status is R:
            return None
        if status is S:
            return NavResult.success()
        return self._failure()

    def on_cancel(self, handle: GoalHandle[Any], now: float) -> NavResult | None:
        """Halt the tree, then wait (up to `default_cancel_timeout`) for the servers its
        action nodes canceled to stop, as BtActionNode's halt waits for the cancel."""
        if self._cancel_deadline is None:
            self._halt()
            self._cancel_deadline = now + self.bt.params.default_cancel_timeout / 1000.0
        if self.bt.servers_busy() and now < self._cancel_deadline:
            return None
        self._cancel_deadline = None
        return NavResult.cancellation()

    def _failure(self) -> NavResult:
        """Nav2's `populateErrorCode`: the lowest non-zero `<prefix>_error_code`."""
        best: tuple[int, str] | None = None
        for prefix in self.bt.params.error_code_name_prefixes:
            code = blackboard_value(f"{prefix}_error_code", 0)
            if code and (best is None or int(code) < best[0]):
                best = (int(code), str(blackboard_value(f"{prefix}_error_msg", "") or ""))
        if best is None:
            return NavResult.failure(self.codes.UNKNOWN)
        return NavResult.failure(best[0], best[1] or None)

    # -- feedback ---------------------------------------------------------------------------

    def _feedback(self, now: float) -> Any:
        rt = self.bt.runtime
        global_frame, robot_base_frame = self._pose_frames
        try:
            pose = rt.robot_pose(global_frame, robot_base_frame)
        except FrameError:  # (a transform not published yet: a zero pose)
            pose = Pose2D()
        remaining = self._distance_remaining(pose)
        twist = rt.latest_odom.twist
        speed = fmath.hypot(twist.linear_x, twist.linear_y)
        eta = remaining / speed if speed > 0.01 and math.isfinite(remaining) else 0.0
        recoveries = recovery_count()
        return self._make_feedback(
            current_pose=pose,
            navigation_time=now - self.start_time,
            estimated_time_remaining=eta,
            number_of_recoveries=recoveries,
            distance_remaining=remaining,
        )

    def _make_feedback(self, **kw: Any) -> Any:
        """The action's feedback message from NavigateToPose's fields (a navigator adds its own)."""
        return NavigateToPoseFeedback(**kw)

    def _distance_remaining(self, pose: Pose2D) -> float:
        path = blackboard.read("/path")
        if not isinstance(path, Path) or len(path) == 0:
            goal = blackboard.read("/goal")
            goal = getattr(goal, "pose", goal)
            if goal is None or not hasattr(goal, "x"):
                return 0.0
            return fmath.hypot(goal.x - pose.x, goal.y - pose.y)
        return self.progress.remaining(path, pose.x, pose.y)

    @property
    def search_window(self) -> float:
        return float(self.params.search_window)


@register(
    "navigator",
    "btnav/NavigateToPoseNavigator",
    aliases=["nav2_bt_navigator::NavigateToPoseNavigator"],
)
class NavigateToPoseNavigator(BehaviorTreeNavigator):
    """nav2_bt_navigator::NavigateToPoseNavigator: `goal` on the blackboard."""


@register(
    "navigator",
    "btnav/NavigateThroughPosesNavigator",
    aliases=["nav2_bt_navigator::NavigateThroughPosesNavigator"],
)
class NavigateThroughPosesNavigator(BehaviorTreeNavigator):
    """nav2_bt_navigator::NavigateThroughPosesNavigator: `goals` on the blackboard."""

    action_name = "NavigateThroughPoses"
    default_tree_key = "default_nav_through_poses_bt_xml"
    goal_type = NavigateThroughPosesGoal

    def validate_goal(self, goal: Any) -> str | None:
        if not goal.poses:
            return "no poses to navigate through"
        return super().validate_goal(goal)

    def _set_goal(self, goal: Any) -> None:
        poses = [_pose(p) for p in goal.poses]
        _blackboard_set("goals", poses)
        # Nav2 sets only `goals`; `goal` is the last pose, for nodes that read it.
        _blackboard_set("goal", poses[-1])

    def _make_feedback(self, **kw: Any) -> Any:
        goals = blackboard_value("goals") or []
        return NavigateThroughPosesFeedback(**kw, number_of_poses_remaining=len(goals))


class BtNavigator:
    """bt_navigator: builds its navigators from its params and adds them to the runtime."""

    def __init__(
        self,
        runtime: Runtime,
        stack: Any,
        params: ParamsFile | ServerParams,
        *,
        base_dir: Any = None,
    ) -> None:
        server = params.server("bt_navigator") if isinstance(params, ParamsFile) else params
        self.server_params = server
        self.params = server.model
        self.runtime = runtime
        self.stack = stack
        self.base_dir = base_dir
        self.context = {
            "runtime": runtime,
            "stack": stack,
            "global_frame": self.params.global_frame,
            "robot_base_frame": self.params.robot_base_frame,
        }
        self.navigators: dict[str, BehaviorTreeNavigator] = {}
        #: Called as `listener(navigator, now)` when a tree is built and after every tick
        #: and halt of it (the mission's bt_log reads node statuses there).
        self.tick_listeners: list[Callable[[BehaviorTreeNavigator, float], None]] = []
        for section in server.plugins_of("navigator"):
            if section.cls is None:
                raise PluginError(
                    f"navigator '{section.name}' is a {section.type}, which btnav does not have",
                    line=section.line,
                    key=section.key,
                    suggestion=best_match(section.type, names("navigator", aliases=True)),
                )
            self.add_navigator(section.name, make_plugin(section))

    def add_navigator(self, name: str, navigator: BehaviorTreeNavigator) -> BehaviorTreeNavigator:
        """Configure `navigator` and serve its action on the runtime."""
        navigator.configure(self)
        self.navigators[name] = self.runtime.add(navigator)
        return navigator

    def notify(self, navigator: BehaviorTreeNavigator, now: float) -> None:
        for listener in self.tick_listeners:
            listener(navigator, now)

    def halt_others(self, starting: BehaviorTreeNavigator) -> None:
        """One tree at a time: a goal on one navigator aborts the other's running goal."""
        for nav in self.navigators.values():
            if nav is not starting and nav.current is not None and nav.current.active:
                nav._halt()
                nav._terminate(nav.current, f"{starting.name} started a goal")

    def servers_busy(self) -> bool:
        """Whether an action server the trees call (not a navigator) still runs a goal."""
        servers = self.runtime.action_servers
        for name in servers.names():
            server = servers.get(name)
            if server.action in ("NavigateToPose", "NavigateThroughPoses", "FollowWaypoints"):
                continue
            if server.is_active:
                return True
        return False

    def set_parameters(self, params: ServerParams) -> None:
        self.server_params = params
        self.params = params.model
        for nav in self.navigators.values():
            nav.configure(self)


__all__ = [
    "BtNavigator",
    "NavigateThroughPosesError",
    "NavigateThroughPosesFeedback",
    "NavigateThroughPosesGoal",
    "NavigateThroughPosesNavigator",
    "NavigateToPoseError",
    "NavigateToPoseFeedback",
    "NavigateToPoseGoal",
    "NavigateToPoseNavigator",
    "blackboard_value",
]
