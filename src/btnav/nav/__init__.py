"""Navigation runtime: the scheduler on sim time, actions, Nav2's error codes, localisers."""

from ..core.error_codes import (
    ERROR_CODES,
    NavErrorCode,
    NavResult,
    Outcome,
    error_codes,
    error_message,
)
from .actions import ActionClient, ActionServer, ActionServers, GoalHandle, GoalStatus
from .runtime import Component, Runtime, Stage

__all__ = [
    "ERROR_CODES",
    "ActionClient",
    "ActionServer",
    "ActionServers",
    "Component",
    "GoalHandle",
    "GoalStatus",
    "NavErrorCode",
    "NavResult",
    "Outcome",
    "Runtime",
    "Stage",
    "error_codes",
    "error_message",
]
