"""nav2_msgs' DockRobot and UndockRobot actions, and the pose a dock detector publishes.

The result codes (DockRobot.action's and UndockRobot.action's 9xx) are in
`core.error_codes` with every other action's. A detector's pose is geometry_msgs/PoseStamped with its 3D
orientation kept (an apriltag's frame is not a ground-plane pose: the dock plugin turns
it into one with its `external_detection_rotation_*`).
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import IntEnum
from typing import Any


class DockingState(IntEnum):
    """DockRobot.action's feedback `state`."""

    NONE = 0
    NAV_TO_STAGING_POSE = 1
    INITIAL_PERCEPTION = 2
    CONTROLLING = 3
    WAIT_FOR_CHARGE = 4
    RETRY = 5


@dataclass
class DockRobotGoal:
    """Dock at `dock_id` (from the database) or, with `use_dock_id` false, at `dock_pose`
    (a PoseStamped, Pose2D or (x, y, yaw) in map) of plugin `dock_type`."""

    use_dock_id: bool = True
    dock_id: str = ""
    dock_pose: Any = None
    dock_type: str = ""
    max_staging_time: float = 1000.0
    navigate_to_staging_pose: bool = True


@dataclass
class DockRobotFeedback:
    state: DockingState
    docking_time: float
    num_retries: int


@dataclass
class DockRobotResult:
    """The result's fields besides the error code (a failure carries them too)."""

    success: bool
    num_retries: int


@dataclass
class UndockRobotGoal:
    dock_type: str = ""
    max_undocking_time: float = 30.0


@dataclass
class UndockRobotResult:
    success: bool


@dataclass(frozen=True)
class PoseStamped3D:
    """geometry_msgs/PoseStamped: `position` (x, y, z) and `orientation` as a quaternion
    (x, y, z, w), in `frame_id` at `stamp`."""

    stamp: float
    frame_id: str
    position: tuple[float, float, float]
    orientation: tuple[float, float, float, float]


@dataclass(frozen=True)
class DockDetection:
    """What a dock detector reports each measurement: the marker's pose (`detected_dock_pose`)
    of the dock it sees, or None when no dock is in view."""

    stamp: float
    frame_id: str
    pose: PoseStamped3D | None = None
    dock: str = ""
