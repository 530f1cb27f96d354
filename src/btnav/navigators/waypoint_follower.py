"""waypoint_follower: FollowWaypoints, one NavigateToPose per waypoint, a task at each.

As Nav2's WaypointFollower: waypoints are sent in order to `navigate_to_pose`; a
waypoint whose navigation fails is recorded in `missed_waypoints` (Nav2's
WaypointStatus: index, goal, error code and message, plus the sim time it was given
up) and, with `stop_on_failure`, ends the action ABORTED with
STOP_ON_MISSED_WAYPOINT; otherwise the follower goes on with the next one. After a
waypoint is reached the task executor (`waypoint_task_executor_plugin`) runs there;
a failed task is TASK_EXECUTOR_FAILED with `stop_on_failure`, a missed waypoint
otherwise. All waypoints done: SUCCEEDED, with the missed ones in the result. A
cancel cancels the running NavigateToPose. The server runs at `loop_rate` Hz.

Task executors are `waypoint_task_executor` plugins. Nav2's blocking
`processAtWaypoint(pose, index)` becomes `start(pose, index, now)` then `update(now)`
each cycle, returning None while busy, True when done, False when failed, so sim
time runs while a robot waits at a waypoint.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from pydantic import Field

from ..core.error_codes import FollowWaypointsError, NavResult
from ..core.geometry import Pose2D
from ..core.nav2_msgs import (
    FollowWaypointsFeedback,
    FollowWaypointsGoal,
    FollowWaypointsResult,
    MissedWaypoint,
    NavigateToPoseGoal,
)
from ..nav.actions import ActionServer, GoalHandle
from ..nav.runtime import Runtime, Stage
from ..nav.server_plugins import make_plugin
from ..params.paramsfile import ParamsFile, ServerParams
from ..params.schema import ParamsModel
from ..plugins import register


@register(
    "waypoint_task_executor",
    "btnav/WaitAtWaypoint",
    aliases=["nav2_waypoint_follower::WaitAtWaypoint"],
)
class WaitAtWaypoint:
    """Pause `waypoint_pause_duration` ms of sim time at each waypoint (when `enabled`)."""

    class Params(ParamsModel):
        enabled: bool = True
        waypoint_pause_duration: int = Field(0, ge=0, description="ms to wait at a waypoint")

    def __init__(self, name: str, params: Any = None) -> None:
        self.name = name
        self.params = params if params is not None else self.Params()
        self._until: float | None = None

    def start(self, pose: Any, index: int, now: float) -> bool | None:
        if not self.params.enabled:
            return True
        self._until = now + self.params.waypoint_pause_duration / 1000.0
        return self.update(now)

    def update(self, now: float) -> bool | None:
        if self._until is None or now + 1e-9 >= self._until:
            self._until = None
            return True
        return None

    def cancel(self) -> None:
        self._until = None


def _pose(value: Any) -> Any:
    return value if hasattr(value, "x") or hasattr(value, "pose") else Pose2D(*value)


@dataclass(frozen=True)
class MissedWaypointStatus(MissedWaypoint):
    """A missed waypoint as Nav2's WaypointStatus (FAILED) carries it, and `stamp`: the sim
    time its navigation (or task) ended, which a report places the failure by."""

    stamp: float = 0.0


class WaypointFollower(ActionServer[FollowWaypointsGoal]):
    """nav2_waypoint_follower: the `follow_waypoints` action server."""

    stage = Stage.NAVIGATOR

    def __init__(self, runtime: Runtime, params: ParamsFile | ServerParams) -> None:
        server = params.server("waypoint_follower") if isinstance(params, ParamsFile) else params
        super().__init__("FollowWaypoints", "follow_waypoints", rate=server.model.loop_rate)
        self.runtime = runtime
        self.set_parameters(server)
        self._index = 0
        self._nav: GoalHandle[Any] | None = None
        self._task_running = False
        self._missed: list[MissedWaypointStatus] = []

    def set_parameters(self, params: ServerParams) -> None:
        self.server_params = params
        self.params = params.model
        self.rate = float(self.params.loop_rate)
        section = params.plugins.get(self.params.waypoint_task_executor_plugin)
        self.executor = make_plugin(section) if section is not None and section.cls else None

    def validate_goal(self, goal: FollowWaypointsGoal) -> str | None:
        return None

    def on_start(self, handle: GoalHandle[FollowWaypointsGoal], now: float) -> NavResult | None:
        if not handle.goal.poses:
            return NavResult.failure(FollowWaypointsError.NO_VALID_WAYPOINTS)
        self._index = 0
        self._nav = None
        self._task_running = False
        self._missed = []
        return self.execute(handle, now)

    def _miss(self, handle: GoalHandle[Any], code: int, msg: str, stamp: float) -> None:
        goal = handle.goal.poses[self._index]
        self._missed.append(MissedWaypointStatus(self._index, goal, code, msg, stamp))

    def execute(self, handle: GoalHandle[FollowWaypointsGoal], now: float) -> NavResult | None:
        poses = handle.goal.poses
        while True:
            if self._index >= len(poses):
                return NavResult.success(FollowWaypointsResult(list(self._missed)))
            if self._task_running:
                done = self.executor.update(now) if self.executor is not None else True
                if done is None:
                    break
                self._task_running = False
                if not done:
                    if self.params.stop_on_failure:
                        return self._abort(FollowWaypointsError.TASK_EXECUTOR_FAILED)
                    self._miss(
                        handle, FollowWaypointsError.TASK_EXECUTOR_FAILED, "task failed", now
                    )
                self._index += 1
                self._nav = None
                continue
            if self._nav is None:
                goal = NavigateToPoseGoal(_pose(poses[self._index]))
                self._nav = self.runtime.action_client("navigate_to_pose").send_goal(goal)
            if not self._nav.done:
                break
            nav, self._nav = self._nav, None
            if nav.succeeded:
                pose = _pose(poses[self._index])
                done = self.executor.start(pose, self._index, now) if self.executor else True
                self._task_running = done is None
                if done is None:
                    break
                if not done:
                    if self.params.stop_on_failure:
                        return self._abort(FollowWaypointsError.TASK_EXECUTOR_FAILED)
                    self._miss(
                        handle, FollowWaypointsError.TASK_EXECUTOR_FAILED, "task failed", now
                    )
                self._index += 1
                continue
            ended = nav.end_time if nav.end_time is not None else now
            self._miss(handle, nav.error_code, nav.error_msg, ended)
            if self.params.stop_on_failure:
                return self._abort(FollowWaypointsError.STOP_ON_MISSED_WAYPOINT)
            self._index += 1
        handle.publish_feedback(FollowWaypointsFeedback(self._index, list(self._missed)), now)
        return None

    def _abort(self, code: FollowWaypointsError) -> NavResult:
        return NavResult.failure(code, None, FollowWaypointsResult(list(self._missed)))

    def on_cancel(self, handle: GoalHandle[FollowWaypointsGoal], now: float) -> NavResult | None:
        if self._nav is not None and self._nav.active:
            self._nav.cancel()
            return None  # finished once the navigator has stopped
        if self.executor is not None and hasattr(self.executor, "cancel"):
            self.executor.cancel()
        self._task_running = False
        return NavResult.cancellation(FollowWaypointsResult(list(self._missed)))
