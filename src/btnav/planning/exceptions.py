"""Nav2's planner and smoother exceptions (nav2_core's *_exceptions.hpp), with their action codes.

These are navigation *results*, not configuration mistakes, so they are not
`BtnavError`s: a planner raises one, the planner server catches it and reports
`error_code` in the ComputePathToPose result, as Nav2's planner_server does.
The codes are those of nav2_msgs/action/ComputePathToPose.action and
SmoothPath.action.
"""

from __future__ import annotations

from typing import ClassVar

from ..core.error_codes import ComputePathToPoseError, SmoothPathError


class PlannerException(Exception):
    """nav2_core::PlannerException: a planning failure, carrying its ComputePathToPose code."""

    error_code: ClassVar[ComputePathToPoseError] = ComputePathToPoseError.UNKNOWN

    @property
    def error_msg(self) -> str:
        return str(self)


class InvalidPlanner(PlannerException):
    error_code = ComputePathToPoseError.INVALID_PLANNER


class PlannerTFError(PlannerException):
    error_code = ComputePathToPoseError.TF_ERROR


class StartOutsideMapBounds(PlannerException):
    error_code = ComputePathToPoseError.START_OUTSIDE_MAP


class GoalOutsideMapBounds(PlannerException):
    error_code = ComputePathToPoseError.GOAL_OUTSIDE_MAP


class StartOccupied(PlannerException):
    error_code = ComputePathToPoseError.START_OCCUPIED


class GoalOccupied(PlannerException):
    error_code = ComputePathToPoseError.GOAL_OCCUPIED


class PlannerTimedOut(PlannerException):
    error_code = ComputePathToPoseError.TIMEOUT


class PlannerCancelled(PlannerTimedOut):
    """The `cancel_checker` returned True while planning (nav2_core::PlannerCancelled).

    ComputePathToPose has no "cancelled" code: a server that used the checker as a
    deadline reports TIMEOUT (this class's code); one that honoured a client's cancel
    request reports the action as cancelled instead.
    """


class NoValidPathCouldBeFound(PlannerException):
    error_code = ComputePathToPoseError.NO_VALID_PATH


class SmootherException(Exception):
    """nav2_core::SmootherException: a smoothing failure, carrying its SmoothPath code."""

    error_code: ClassVar[SmoothPathError] = SmoothPathError.UNKNOWN

    @property
    def error_msg(self) -> str:
        return str(self)


class InvalidSmoother(SmootherException):
    error_code = SmoothPathError.INVALID_SMOOTHER


class SmootherTimedOut(SmootherException):
    error_code = SmoothPathError.TIMEOUT


class SmoothedPathInCollision(SmootherException):
    error_code = SmoothPathError.SMOOTHED_PATH_IN_COLLISION


class FailedToSmoothPath(SmootherException):
    error_code = SmoothPathError.FAILED_TO_SMOOTH_PATH


class InvalidPath(SmootherException):
    error_code = SmoothPathError.INVALID_PATH
