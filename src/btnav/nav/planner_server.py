"""Nav2's planner_server: ComputePathToPose and ComputePathThroughPoses on the global costmap.

`PlannerServer(runtime, params, global_costmap)` builds the `planner_plugins` of its
params section and serves two actions (names as Nav2's):

- `compute_path_to_pose` (ComputePathToPose): goal `ComputePathToPoseGoal(goal,
  planner_id, start, use_start)`; the result's `value` is the `Path` in the global
  costmap's frame.
- `compute_path_through_poses` (ComputePathThroughPoses): one plan per leg, joined.

A planner's exception (`planning.exceptions`) becomes the action's error code and
message, never an exception in the caller: a goal in an obstacle is GOAL_OCCUPIED (or
NO_VALID_PATH when NavFn's `tolerance` lets it look round the goal and it finds
nothing), an unknown `planner_id` INVALID_PLANNER, a missing transform TF_ERROR.
Planning finishes within the server cycle the goal starts in (sim time does not
pass while a plan is computed), so `expected_planner_frequency` has nothing to time.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..core.error_codes import (
    ComputePathThroughPosesError,
    ComputePathToPoseError,
    NavErrorCode,
    NavResult,
)
from ..core.errors import FrameError
from ..core.geometry import Pose2D
from ..core.messages import Path, PoseStamped
from ..core.nav2_msgs import ComputePathThroughPosesGoal, ComputePathToPoseGoal, PoseLike
from ..planning.exceptions import PlannerException
from .actions import ActionServer, GoalHandle
from .server_plugins import PluginServer, pick


class _PlanError(Exception):
    def __init__(self, code_name: str, msg: str) -> None:
        super().__init__(msg)
        self.code_name = code_name


class PlannerServer(PluginServer):
    """planner_server: owns the planner plugins and the two planning actions."""

    kind = "planner"
    #: Plan into unknown space beyond the global costmap when a goal lies outside it,
    #: as if the map already reached the goal: set while SLAM builds the map, where
    #: Nav2 fails the goal (navigation2 #3992; docs/decisions/0001).
    grow_into_unknown: bool = False
    #: How far round the start and goal the grown map reaches, metres.
    unknown_margin: float = 1.0

    def action_servers(self) -> list[ActionServer[Any]]:
        self.to_pose: ActionServer[ComputePathToPoseGoal] = ActionServer(
            "ComputePathToPose", "compute_path_to_pose", on_start=self._to_pose
        )
        self.through_poses: ActionServer[ComputePathThroughPosesGoal] = ActionServer(
            "ComputePathThroughPoses", "compute_path_through_poses", on_start=self._through_poses
        )
        return [self.to_pose, self.through_poses]

    # -- the public call (also what the actions do) -----------------------------------------

    def create_plan(
        self, goal: PoseLike, planner_id: str = "", start: PoseLike | None = None
    ) -> Path:
        """Plan from `start` (the robot if None) to `goal` in the global frame; raises
        `PlannerException` (with `.error_code`) or `_PlanError` on failure."""
        planner = pick(self.plugins, planner_id)
        if planner is None:
            raise _PlanError(
                "INVALID_PLANNER",
                f"planner id '{planner_id}' is not one of: {', '.join(self.plugins)}",
            )
        start_pose = self._in_global(start) if start is not None else self._robot_pose()
        goal_pose = self._in_global(goal)
        costmap = self.costmap.costmap
        if self.grow_into_unknown:
            ends = [(start_pose.x, start_pose.y), (goal_pose.x, goal_pose.y)]
            costmap = costmap.grown_to_include(ends, self.unknown_margin)
        path = planner.create_plan(start_pose, goal_pose, costmap, lambda: False)
        if path is None or len(path) == 0:
            raise _PlanError("NO_VALID_PATH", f"planner '{planner.name}' returned an empty path")
        return Path(self.runtime.now, path.poses, self.costmap.global_frame)

    # -- actions ----------------------------------------------------------------------------

    def _to_pose(self, handle: GoalHandle[ComputePathToPoseGoal], now: float) -> NavResult:
        g = handle.goal
        return self._result(
            ComputePathToPoseError,
            lambda: self.create_plan(g.goal, g.planner_id, g.start if g.use_start else None),
        )

    def _through_poses(
        self, handle: GoalHandle[ComputePathThroughPosesGoal], now: float
    ) -> NavResult:
        g = handle.goal
        if not g.goals:
            return NavResult.failure(ComputePathThroughPosesError.NO_VIAPOINTS_GIVEN)

        def plan() -> Path:
            start = g.start if g.use_start else None
            legs: list[np.ndarray] = []
            for goal in g.goals:
                leg = self.create_plan(goal, g.planner_id, start)
                legs.append(leg.poses if not legs else leg.poses[1:])
                start = Pose2D.from_array(leg.poses[-1])
            return Path(now, np.concatenate(legs), self.costmap.global_frame)

        return self._result(ComputePathThroughPosesError, plan)

    def _result(self, codes: type[NavErrorCode], plan: Any) -> NavResult:
        try:
            return NavResult.success(plan())
        except PlannerException as exc:
            code = codes[exc.error_code.name]
            return NavResult.failure(code, str(exc) or code.message)
        except _PlanError as exc:
            return NavResult.failure(codes[exc.code_name], str(exc))
        except FrameError as exc:
            return NavResult.failure(codes["TF_ERROR"], str(exc))

    # -- frames -----------------------------------------------------------------------------

    def _robot_pose(self) -> Pose2D:
        return self.runtime.lookup(self.costmap.global_frame, self.costmap.robot_base_frame)

    def _in_global(self, pose: PoseLike) -> Pose2D:
        if isinstance(pose, PoseStamped):
            p, frame = pose.pose, pose.frame_id
        elif isinstance(pose, Pose2D):
            p, frame = pose, self.costmap.global_frame
        else:
            p, frame = Pose2D(*pose), self.costmap.global_frame
        if frame != self.costmap.global_frame:
            p = self.runtime.lookup(self.costmap.global_frame, frame) @ p
        return p

    # -- dynamic parameters -----------------------------------------------------------------
