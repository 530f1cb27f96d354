"""Goal checkers (nav2_controller's): has the robot reached the goal pose?

`SimpleGoalChecker` tests position within `xy_goal_tolerance`, then yaw within
`yaw_goal_tolerance`. With `stateful` (the default) it remembers once the
position was reached, and from then on checks only the yaw, so a small shift
while rotating in place (localisation noise) does not undo the goal. Nothing is
reached while the remaining path is longer than `path_length_tolerance` (a path
that loops back past its goal). `StoppedGoalChecker` also requires the robot to
have (nearly) stopped.
"""

from __future__ import annotations

import math

import numpy as np
from pydantic import Field

from ..core import fmath
from ..core.geometry import Pose2D, angle_diff
from ..core.messages import Path, Twist
from ..params.schema import ParamsModel
from ..plugins import Plugin, register


def path_length(path: Path | np.ndarray | None) -> float:
    """Length of a path's polyline (0 for None, one pose or none)."""
    if path is None:
        return 0.0
    poses = path.poses if isinstance(path, Path) else np.asarray(path)
    if len(poses) < 2:
        return 0.0
    d = poses[1:, :2] - poses[:-1, :2]  # np.diff, without its overhead
    return float(fmath.hypot(d[:, 0], d[:, 1]).sum())


class GoalChecker(Plugin):
    """Base of every `goal_checker` plugin (nav2_core::GoalChecker)."""

    class Params(ParamsModel):
        pass

    def __init__(self, name: str = "goal_checker", params: ParamsModel | None = None) -> None:
        super().__init__(name, params)

    def reset(self) -> None:
        """A new goal is coming: forget any state."""

    def is_goal_reached(
        self, pose: Pose2D, goal: Pose2D, velocity: Twist, transformed_plan: Path | None = None
    ) -> bool:
        raise NotImplementedError

    def is_goal_xy_reached(
        self, pose: Pose2D, goal: Pose2D, velocity: Twist, transformed_plan: Path | None = None
    ) -> bool:
        """Position part only (RPP asks it to decide when to rotate to the goal heading)."""
        raise NotImplementedError

    def get_tolerances(self) -> tuple[Pose2D, Twist, float]:
        """(pose tolerance, velocity tolerance, path length tolerance); -inf marks "not checked"."""
        raise NotImplementedError


@register(
    "goal_checker", "nav2_controller::SimpleGoalChecker", aliases=["dwb_plugins::SimpleGoalChecker"]
)
class SimpleGoalChecker(GoalChecker):
    class Params(ParamsModel):
        xy_goal_tolerance: float = Field(0.25, ge=0.0)
        yaw_goal_tolerance: float = Field(0.25, ge=0.0)
        path_length_tolerance: float = Field(1.0, ge=0.0)
        stateful: bool = True
        symmetric_yaw_tolerance: bool = False
        #: Once xy was reached (stateful), leaving xy_goal_tolerance + this buffer re-arms the xy check.
        xy_goal_tolerance_buffer: float = Field(0.0, ge=0.0)

    params: Params

    def __init__(self, name: str = "goal_checker", params: ParamsModel | None = None) -> None:
        super().__init__(name, params)
        self.check_xy = True

    def reset(self) -> None:
        self.check_xy = True

    def is_goal_xy_reached(
        self, pose: Pose2D, goal: Pose2D, velocity: Twist, transformed_plan: Path | None = None
    ) -> bool:
        p = self.params
        if path_length(transformed_plan) > p.path_length_tolerance:
            return False
        d2 = (pose.x - goal.x) ** 2 + (pose.y - goal.y) ** 2
        if self.check_xy:
            if d2 > p.xy_goal_tolerance**2:
                return False
            if p.stateful:
                self.check_xy = False
        elif (
            p.stateful
            and p.xy_goal_tolerance_buffer > 0.0
            and d2 > (p.xy_goal_tolerance + p.xy_goal_tolerance_buffer) ** 2
        ):
            self.check_xy = True
            return False
        return True

    def is_goal_reached(
        self, pose: Pose2D, goal: Pose2D, velocity: Twist, transformed_plan: Path | None = None
    ) -> bool:
        if not self.is_goal_xy_reached(pose, goal, velocity, transformed_plan):
            return False
        tol = self.params.yaw_goal_tolerance
        if abs(angle_diff(goal.yaw, pose.yaw)) <= tol:
            return True
        return bool(
            self.params.symmetric_yaw_tolerance
            and abs(angle_diff(goal.yaw + math.pi, pose.yaw)) <= tol
        )

    def get_tolerances(self) -> tuple[Pose2D, Twist, float]:
        p = self.params
        unchecked = -math.inf
        return (
            Pose2D(p.xy_goal_tolerance, p.xy_goal_tolerance, p.yaw_goal_tolerance),
            Twist(unchecked, unchecked, unchecked),
            p.path_length_tolerance,
        )


@register(
    "goal_checker",
    "nav2_controller::StoppedGoalChecker",
    aliases=["dwb_plugins::StoppedGoalChecker"],
)
class StoppedGoalChecker(SimpleGoalChecker):
    """SimpleGoalChecker that also needs |v| <= trans_stopped_velocity and |w| <= rot_stopped_velocity."""

    class Params(SimpleGoalChecker.Params):
        rot_stopped_velocity: float = Field(0.25, ge=0.0)
        trans_stopped_velocity: float = Field(0.25, ge=0.0)

    params: Params

    def is_goal_reached(
        self, pose: Pose2D, goal: Pose2D, velocity: Twist, transformed_plan: Path | None = None
    ) -> bool:
        if not super().is_goal_reached(pose, goal, velocity, transformed_plan):
            return False
        return (
            abs(velocity.angular_z) <= self.params.rot_stopped_velocity
            and fmath.hypot(velocity.linear_x, velocity.linear_y)
            <= self.params.trans_stopped_velocity
        )

    def get_tolerances(self) -> tuple[Pose2D, Twist, float]:
        pose, _, length = super().get_tolerances()
        p = self.params
        return (
            pose,
            Twist(p.trans_stopped_velocity, p.trans_stopped_velocity, p.rot_stopped_velocity),
            length,
        )
