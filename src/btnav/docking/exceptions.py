"""opennav_docking_core's exceptions: each failure of a docking step names its result code.

The docking server turns them into DockRobot's codes (DOCK_NOT_IN_DB, FAILED_TO_DETECT_DOCK,
...). A failure while approaching the dock or waiting for charge is retried up to
`max_retries` times; the others end the action at once, as in Nav2.
"""

from __future__ import annotations

from ..core.error_codes import DockRobotError


class DockingException(Exception):
    """A docking step failed; `code` is DockRobot's result code for it."""

    code = DockRobotError.UNKNOWN


class DockNotInDB(DockingException):
    code = DockRobotError.DOCK_NOT_IN_DB


class DockNotValid(DockingException):
    code = DockRobotError.DOCK_NOT_VALID


class FailedToStage(DockingException):
    code = DockRobotError.FAILED_TO_STAGE


class FailedToDetectDock(DockingException):
    code = DockRobotError.FAILED_TO_DETECT_DOCK


class FailedToControl(DockingException):
    code = DockRobotError.FAILED_TO_CONTROL


class FailedToCharge(DockingException):
    code = DockRobotError.FAILED_TO_CHARGE
