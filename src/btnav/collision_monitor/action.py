"""What the monitor does to a command: Nav2's action types, the Action in force, and the
velocity arithmetic that compares and scales commands (nav2_collision_monitor/types.hpp)."""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import IntEnum

import numpy as np
from numpy.typing import NDArray

from ..core.messages import Twist


class ActionType(IntEnum):
    """Nav2's ActionType values (the numbers CollisionMonitorState carries)."""

    DO_NOTHING = 0
    STOP = 1
    SLOWDOWN = 2
    APPROACH = 3
    LIMIT = 4


_BY_NAME = {
    "none": ActionType.DO_NOTHING,
    "stop": ActionType.STOP,
    "slowdown": ActionType.SLOWDOWN,
    "approach": ActionType.APPROACH,
    "limit": ActionType.LIMIT,
}


def action_type_of(name: str) -> ActionType:
    """The ActionType a params file's `action_type` string names."""
    return _BY_NAME[name]


def _no_points() -> NDArray[np.float64]:
    return np.zeros((0, 2))


@dataclass
class Action:
    """The action in force: its type, the command it asks for and the polygon that asked
    ("invalid source" when a source's data is missing or too old)."""

    action_type: ActionType
    req_vel: Twist
    polygon_name: str = ""
    #: The sensed points (base frame) that made the polygon act.
    triggering_points: NDArray[np.float64] = field(default_factory=_no_points)


def speed_squared(v: Twist) -> float:
    """Nav2 ranks commands by x^2 + y^2 + w^2, so a turn in place counts as motion."""
    return v.linear_x * v.linear_x + v.linear_y * v.linear_y + v.angular_z * v.angular_z


def is_safer(a: Twist, b: Twist) -> bool:
    """Whether `a` is slower than `b` (Nav2's Velocity::operator<)."""
    return speed_squared(a) < speed_squared(b)


def scaled(v: Twist, ratio: float) -> Twist:
    """Every axis times `ratio`: the same curvature, a different speed."""
    return Twist(v.linear_x * ratio, v.linear_y * ratio, v.angular_z * ratio)


def is_zero(v: Twist) -> bool:
    return v.linear_x == 0.0 and v.linear_y == 0.0 and v.angular_z == 0.0
