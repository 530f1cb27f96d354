"""Nav2's planner and smoother exceptions (nav2_core's *_exceptions.hpp), with their action codes.

These are navigation *results*, not configuration mistakes, so they are not
`BtnavError`s: a planner raises one, the planner server catches it and reports
`error_code` in the ComputePathToPose result, as Nav2's planner_server does.
The codes are those of nav2_msgs/action/ComputePathToPose.action and
SmoothPath.action.
"""

from __future__ import annotations

from enum import IntEnum
from typing import ClassVar


class ComputePathToPoseCode(IntEnum):
    """ComputePathToPose.action's error codes."""

    NONE = 0
    UNKNOWN = 200
    INVALID_PLANNER = 201
    TF_ERROR = 202
    START_OUTSIDE_MAP = 203
    GOAL_OUTSIDE_MAP = 204
    START_OCCUPIED = 205
    GOAL_OCCUPIED = 206
    TIMEOUT = 207
    NO_VALID_PATH = 208


class SmoothPathCode(IntEnum):
    """SmoothPath.action's error codes."""

    NONE = 0
    UNKNOWN = 500
    INVALID_SMOOTHER = 501
    TIMEOUT = 502
    SMOOTHED_PATH_IN_COLLISION = 503
    FAILED_TO_SMOOTH_PATH = 504
    INVALID_PATH = 505


class PlannerException(Exception):
    """nav2_core::PlannerException: a planning failure, carrying its ComputePathToPose code."""

    error_code: ClassVar[ComputePathToPoseCode] = ComputePathToPoseCode.UNKNOWN

    @property
    def error_msg(self) -> str:
        return str(self)


class InvalidPlanner(PlannerException):
    error_code = ComputePathToPoseCode.INVALID_PLANNER


class PlannerTFError(PlannerException):
    error_code = ComputePathToPoseCode.TF_ERROR


class StartOutsideMapBounds(PlannerException):
    error_code = ComputePathToPoseCode.START_OUTSIDE_MAP


class GoalOutsideMapBounds(PlannerException):
    error_code = ComputePathToPoseCode.GOAL_OUTSIDE_MAP


class StartOccupied(PlannerException):
    error_code = ComputePathToPoseCode.START_OCCUPIED


class GoalOccupied(PlannerException):
    error_code = ComputePathToPoseCode.GOAL_OCCUPIED


class PlannerTimedOut(PlannerException):
    error_code = ComputePathToPoseCode.TIMEOUT


class PlannerCancelled(PlannerTimedOut):
    """The `cancel_checker` returned True while planning (nav2_core::PlannerCancelled).

    ComputePathToPose has no "cancelled" code: a server that used the checker as a
    deadline reports TIMEOUT (this class's code); one that honoured a client's cancel
    request reports the action as cancelled instead.
    """


class NoValidPathCouldBeFound(PlannerException):
    error_code = ComputePathToPoseCode.NO_VALID_PATH


class SmootherException(Exception):
    """nav2_core::SmootherException: a smoothing failure, carrying its SmoothPath code."""

    error_code: ClassVar[SmoothPathCode] = SmoothPathCode.UNKNOWN

    @property
    def error_msg(self) -> str:
        return str(self)


class InvalidSmoother(SmootherException):
    error_code = SmoothPathCode.INVALID_SMOOTHER


class SmootherTimedOut(SmootherException):
    error_code = SmoothPathCode.TIMEOUT


class SmoothedPathInCollision(SmootherException):
    error_code = SmoothPathCode.SMOOTHED_PATH_IN_COLLISION


class FailedToSmoothPath(SmootherException):
    error_code = SmoothPathCode.FAILED_TO_SMOOTH_PATH


class InvalidPath(SmootherException):
    error_code = SmoothPathCode.INVALID_PATH
