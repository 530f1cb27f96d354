"""Nav2's controller exceptions (nav2_core/controller_exceptions.hpp), each with FollowPath's code.

A controller raises one of these from `compute_velocity_commands` when it cannot
produce a command; the controller server turns it into the FollowPath action's
result: `error_code` (the class's `error_code`) and `error_msg` (the message).
These are navigation results, not user mistakes: they are not `BtnavError`s.

The codes are FollowPath.action's result constants (nav2_msgs), in its priority order.
"""

from __future__ import annotations

from ..core.error_codes import FollowPathError


class ControllerException(RuntimeError):
    """nav2_core::ControllerException: any controller failure (code UNKNOWN unless a subclass says)."""

    error_code: FollowPathError = FollowPathError.UNKNOWN

    def __init__(self, message: str = "") -> None:
        self.message = message or type(self).__name__
        super().__init__(self.message)


class InvalidController(ControllerException):
    """No controller plugin by the requested id."""

    error_code = FollowPathError.INVALID_CONTROLLER


class ControllerTFError(ControllerException):
    """A transform the controller needs is unavailable."""

    error_code = FollowPathError.TF_ERROR


class InvalidPath(ControllerException):
    """The path is empty, or cannot be followed (e.g. not in the costmap's frame)."""

    error_code = FollowPathError.INVALID_PATH


class PatienceExceeded(ControllerException):
    """The controller gave up waiting (e.g. blocked for longer than its patience)."""

    error_code = FollowPathError.PATIENCE_EXCEEDED


class FailedToMakeProgress(ControllerException):
    """The progress checker saw no progress for its time allowance."""

    error_code = FollowPathError.FAILED_TO_MAKE_PROGRESS


class NoValidControl(ControllerException):
    """No collision-free / admissible command exists (e.g. every trajectory collides)."""

    error_code = FollowPathError.NO_VALID_CONTROL


class ControllerTimedOut(ControllerException):
    """Computing a command took longer than the server allows."""

    error_code = FollowPathError.CONTROLLER_TIMED_OUT


__all__ = [
    "ControllerException",
    "ControllerTFError",
    "ControllerTimedOut",
    "FailedToMakeProgress",
    "FollowPathError",
    "InvalidController",
    "InvalidPath",
    "NoValidControl",
    "PatienceExceeded",
]
