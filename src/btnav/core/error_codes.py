"""Nav2's result codes for every action btnav serves, and the result an action ends with.

The numbers are nav2_msgs' (`nav2_msgs/action/*.action`, current main branch), so a
report, a BT blackboard's `error_code_id` or a user's test reads the same code a Nav2
user sees. Each action has its own hundred (FollowPath 1xx, ComputePathToPose 2xx,
...); `NONE = 0` is success. `GOAL_REJECTED = 1` and `SEND_GOAL_FAILURE = 2` are set
by the client side (a BT action node) when a goal never reaches a server.

The messages are btnav's own words, a sentence a user can act on; servers may pass
a more specific `error_msg` (Nav2's servers do too).
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum, IntEnum
from typing import Any

from .errors import UnknownNameError
from .suggest import best_match


class NavErrorCode(IntEnum):
    """Base of each action's code table; `code.message` is btnav's sentence for it."""

    @property
    def message(self) -> str:
        return _MESSAGES.get(self.name, self.name.lower().replace("_", " "))

    @property
    def action(self) -> str:
        return type(self).__name__.removesuffix("Error")


class ComputePathToPoseError(NavErrorCode):
    NONE = 0
    GOAL_REJECTED = 1
    SEND_GOAL_FAILURE = 2
    UNKNOWN = 200
    INVALID_PLANNER = 201
    TF_ERROR = 202
    START_OUTSIDE_MAP = 203
    GOAL_OUTSIDE_MAP = 204
    START_OCCUPIED = 205
    GOAL_OCCUPIED = 206
    TIMEOUT = 207
    NO_VALID_PATH = 208


class ComputePathThroughPosesError(NavErrorCode):
    NONE = 0
    GOAL_REJECTED = 1
    SEND_GOAL_FAILURE = 2
    UNKNOWN = 300
    INVALID_PLANNER = 301
    TF_ERROR = 302
    START_OUTSIDE_MAP = 303
    GOAL_OUTSIDE_MAP = 304
    START_OCCUPIED = 305
    GOAL_OCCUPIED = 306
    TIMEOUT = 307
    NO_VALID_PATH = 308
    NO_VIAPOINTS_GIVEN = 309


class FollowPathError(NavErrorCode):
    NONE = 0
    GOAL_REJECTED = 1
    SEND_GOAL_FAILURE = 2
    UNKNOWN = 100
    INVALID_CONTROLLER = 101
    TF_ERROR = 102
    INVALID_PATH = 103
    PATIENCE_EXCEEDED = 104
    FAILED_TO_MAKE_PROGRESS = 105
    NO_VALID_CONTROL = 106
    CONTROLLER_TIMED_OUT = 107
    TIMEOUT = 108


class SmoothPathError(NavErrorCode):
    NONE = 0
    GOAL_REJECTED = 1
    SEND_GOAL_FAILURE = 2
    UNKNOWN = 500
    INVALID_SMOOTHER = 501
    TIMEOUT = 502
    SMOOTHED_PATH_IN_COLLISION = 503
    FAILED_TO_SMOOTH_PATH = 504
    INVALID_PATH = 505


class FollowWaypointsError(NavErrorCode):
    NONE = 0
    UNKNOWN = 600
    TASK_EXECUTOR_FAILED = 601
    NO_VALID_WAYPOINTS = 602
    STOP_ON_MISSED_WAYPOINT = 603


class SpinError(NavErrorCode):
    NONE = 0
    GOAL_REJECTED = 1
    SEND_GOAL_FAILURE = 2
    UNKNOWN = 700
    TIMEOUT = 701
    TF_ERROR = 702
    COLLISION_AHEAD = 703


class BackUpError(NavErrorCode):
    NONE = 0
    GOAL_REJECTED = 1
    SEND_GOAL_FAILURE = 2
    UNKNOWN = 710
    TIMEOUT = 711
    TF_ERROR = 712
    INVALID_INPUT = 713
    COLLISION_AHEAD = 714


class DriveOnHeadingError(NavErrorCode):
    NONE = 0
    GOAL_REJECTED = 1
    SEND_GOAL_FAILURE = 2
    UNKNOWN = 720
    TIMEOUT = 721
    TF_ERROR = 722
    COLLISION_AHEAD = 723
    INVALID_INPUT = 724


class AssistedTeleopError(NavErrorCode):
    NONE = 0
    GOAL_REJECTED = 1
    SEND_GOAL_FAILURE = 2
    UNKNOWN = 730
    TIMEOUT = 731
    TF_ERROR = 732


class ComputeRouteError(NavErrorCode):
    NONE = 0
    GOAL_REJECTED = 1
    SEND_GOAL_FAILURE = 2
    UNKNOWN = 400
    TF_ERROR = 401
    NO_VALID_GRAPH = 402
    INDETERMINANT_NODES_ON_GRAPH = 403
    TIMEOUT = 404
    NO_VALID_ROUTE = 405
    INVALID_EDGE_SCORER_USE = 407


class ComputeAndTrackRouteError(NavErrorCode):
    NONE = 0
    GOAL_REJECTED = 1
    SEND_GOAL_FAILURE = 2
    UNKNOWN = 400
    TF_ERROR = 401
    NO_VALID_GRAPH = 402
    INDETERMINANT_NODES_ON_GRAPH = 403
    TIMEOUT = 404
    NO_VALID_ROUTE = 405
    OPERATION_FAILED = 406
    INVALID_EDGE_SCORER_USE = 407


class DockRobotError(NavErrorCode):
    NONE = 0
    GOAL_REJECTED = 1
    SEND_GOAL_FAILURE = 2
    DOCK_NOT_IN_DB = 901
    DOCK_NOT_VALID = 902
    FAILED_TO_STAGE = 903
    FAILED_TO_DETECT_DOCK = 904
    FAILED_TO_CONTROL = 905
    FAILED_TO_CHARGE = 906
    TIMEOUT = 907
    UNKNOWN = 999


class UndockRobotError(NavErrorCode):
    NONE = 0
    GOAL_REJECTED = 1
    SEND_GOAL_FAILURE = 2
    DOCK_NOT_VALID = 902
    FAILED_TO_CONTROL = 905
    TIMEOUT = 907
    UNKNOWN = 999


class WaitError(NavErrorCode):
    NONE = 0
    GOAL_REJECTED = 1
    SEND_GOAL_FAILURE = 2
    UNKNOWN = 740
    TIMEOUT = 741


class NavigateToPoseError(NavErrorCode):
    NONE = 0
    GOAL_REJECTED = 1
    SEND_GOAL_FAILURE = 2
    UNKNOWN = 9000
    FAILED_TO_LOAD_BEHAVIOR_TREE = 9001
    TF_ERROR = 9002
    TIMEOUT = 9003


class NavigateThroughPosesError(NavErrorCode):
    NONE = 0
    GOAL_REJECTED = 1
    SEND_GOAL_FAILURE = 2
    UNKNOWN = 9100
    FAILED_TO_LOAD_BEHAVIOR_TREE = 9101
    TF_ERROR = 9102
    TIMEOUT = 9103


class ExploreError(NavErrorCode):
    """btnav's Explore action (explore_lite has no action): NavigateToPose's codes, 9200s."""

    NONE = 0
    GOAL_REJECTED = 1
    SEND_GOAL_FAILURE = 2
    UNKNOWN = 9200
    FAILED_TO_LOAD_BEHAVIOR_TREE = 9201
    TF_ERROR = 9202
    TIMEOUT = 9203


class DriveError(NavErrorCode):
    """btnav's Drive action (scripted teleop)."""

    NONE = 0
    GOAL_REJECTED = 1
    SEND_GOAL_FAILURE = 2
    UNKNOWN = 9300


#: Every action btnav serves, by Nav2's action name.
ERROR_CODES: dict[str, type[NavErrorCode]] = {
    cls.__name__.removesuffix("Error"): cls
    for cls in (
        ComputePathToPoseError,
        ComputePathThroughPosesError,
        FollowPathError,
        SmoothPathError,
        SpinError,
        BackUpError,
        DriveOnHeadingError,
        AssistedTeleopError,
        WaitError,
        NavigateToPoseError,
        NavigateThroughPosesError,
        FollowWaypointsError,
        ExploreError,
        DriveError,
        ComputeRouteError,
        ComputeAndTrackRouteError,
        DockRobotError,
        UndockRobotError,
    )
}

#: btnav's sentence for each code name (the same name means the same thing in every action).
_MESSAGES: dict[str, str] = {
    "NONE": "",
    "GOAL_REJECTED": "the server rejected the goal",
    "SEND_GOAL_FAILURE": "the goal could not be sent: no such server or it is not running",
    "UNKNOWN": "the server failed for a reason it did not name",
    "INVALID_PLANNER": "no planner plugin by that planner_id",
    "INVALID_CONTROLLER": "no controller plugin by that controller_id",
    "INVALID_SMOOTHER": "no smoother plugin by that smoother_id",
    "TF_ERROR": "a transform needed for the robot's pose is not available",
    "START_OUTSIDE_MAP": "the start pose is outside the costmap",
    "GOAL_OUTSIDE_MAP": "the goal pose is outside the costmap",
    "START_OCCUPIED": "the start pose is in an occupied (lethal or inscribed) cell",
    "GOAL_OCCUPIED": "the goal pose is in an occupied (lethal or inscribed) cell",
    "TIMEOUT": "the action did not finish within its allowed time",
    "NO_VALID_PATH": "no collision-free path connects the start and the goal",
    "NO_VIAPOINTS_GIVEN": "no poses were given to plan through",
    "INVALID_PATH": "the path is empty or not usable",
    "PATIENCE_EXCEEDED": "the controller could not find a valid command for too long",
    "FAILED_TO_MAKE_PROGRESS": "the robot did not move far enough within the progress checker's time",
    "NO_VALID_CONTROL": "the controller found no collision-free command",
    "CONTROLLER_TIMED_OUT": "the controller took longer than its control period allows",
    "SMOOTHED_PATH_IN_COLLISION": "the smoothed path runs through an obstacle",
    "FAILED_TO_SMOOTH_PATH": "the smoother could not smooth the path",
    "COLLISION_AHEAD": "the motion would collide within the look-ahead time; stopped",
    "INVALID_INPUT": "the goal's values are not valid (e.g. a speed of zero or a wrong sign)",
    "TASK_EXECUTOR_FAILED": "the waypoint task executor failed at a waypoint",
    "NO_VALID_WAYPOINTS": "no waypoints were given",
    "STOP_ON_MISSED_WAYPOINT": "a waypoint was missed and stop_on_failure is set",
    "FAILED_TO_LOAD_BEHAVIOR_TREE": "the behaviour tree could not be loaded",
    "NO_VALID_ROUTE": "no route on the graph joins the start and the goal",
    "NO_VALID_GRAPH": "no route graph is loaded, or an edge has no usable cost",
    "INDETERMINANT_NODES_ON_GRAPH": "no graph node could be found near the start or the goal",
    "INVALID_EDGE_SCORER_USE": "an edge scorer needs a request by poses",
    "OPERATION_FAILED": "a route operation failed while tracking",
    "DOCK_NOT_IN_DB": "the dock_id is not in the docking server's dock database",
    "DOCK_NOT_VALID": "no dock plugin of that dock_type (or nothing known to undock from)",
    "FAILED_TO_STAGE": "the robot did not reach the dock's staging pose",
    "FAILED_TO_DETECT_DOCK": "the dock was not detected (no fresh detected_dock_pose)",
    "FAILED_TO_CONTROL": "the docking controller could not drive the robot to its target",
    "FAILED_TO_CHARGE": "the robot is on the dock but charging did not start",
}


def error_codes(action: str) -> type[NavErrorCode]:
    """The code table of a Nav2 action by name; an unknown name lists the actions that exist."""
    try:
        return ERROR_CODES[action]
    except KeyError:
        raise UnknownNameError(
            f"unknown action '{action}'; actions: {', '.join(sorted(ERROR_CODES))}",
            suggestion=best_match(action, list(ERROR_CODES)),
        ) from None


def error_name(action: str, code: int) -> str:
    """`error_name("ComputePathToPose", 208) == "NO_VALID_PATH"` (or the number if unknown)."""
    try:
        return error_codes(action)(code).name
    except ValueError:
        return str(code)


def error_message(action: str, code: int) -> str:
    """btnav's sentence for `code` of `action` ("" for NONE, the number for an unknown code)."""
    try:
        return error_codes(action)(code).message
    except ValueError:
        return f"error code {code}"


class Outcome(str, Enum):
    """How an action ended, as a report says it (`status` in report.json)."""

    SUCCEEDED = "succeeded"
    FAILED = "failed"
    CANCELED = "canceled"

    def __str__(self) -> str:  # prints as report.json writes it
        return self.value


@dataclass(frozen=True)
class NavResult:
    """The result of an action: outcome, Nav2's `error_code` and `error_msg`, and its payload.

    `value` holds the action's own result fields (a `Path` for ComputePathToPose, the
    elapsed time for Spin, ...): what the BT node writes to its output ports.
    """

    outcome: Outcome
    error_code: int = 0
    error_msg: str = ""
    value: Any = None

    @classmethod
    def success(cls, value: Any = None) -> NavResult:
        return cls(Outcome.SUCCEEDED, 0, "", value)

    @classmethod
    def failure(cls, code: int, msg: str | None = None, value: Any = None) -> NavResult:
        """A failed (aborted) result; `msg` defaults to the code's sentence."""
        if msg is None:
            msg = code.message if isinstance(code, NavErrorCode) else ""
        return cls(Outcome.FAILED, int(code), msg, value)

    @classmethod
    def cancellation(cls, value: Any = None, msg: str = "") -> NavResult:
        return cls(Outcome.CANCELED, 0, msg, value)

    @property
    def succeeded(self) -> bool:
        return self.outcome is Outcome.SUCCEEDED

    @property
    def failed(self) -> bool:
        return self.outcome is Outcome.FAILED

    @property
    def canceled(self) -> bool:
        return self.outcome is Outcome.CANCELED

    def __str__(self) -> str:
        if self.failed:
            return f"failed ({self.error_code}): {self.error_msg}"
        return self.outcome.value
