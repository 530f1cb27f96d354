"""nav2_msgs' actions as dataclasses: each action's goal, feedback and result.

As nav2_msgs sits below every Nav2 package, this module sits below the servers: a
tree node, a navigator or a user's script builds a goal from here and never imports
the server that serves it. The plain messages (poses, paths, scans) are in
`core.messages`; the error codes in `core.error_codes`.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

from .geometry import Pose2D
from .messages import Path, PoseStamped

#: A pose as the actions take it: a Pose2D, a PoseStamped or (x, y, yaw).
PoseLike = Pose2D | PoseStamped | Sequence[float]


# -- planner_server, controller_server, smoother_server ---------------------------------


@dataclass
class ComputePathToPoseGoal:
    goal: PoseLike
    planner_id: str = ""
    start: PoseLike | None = None
    use_start: bool = False


@dataclass
class ComputePathThroughPosesGoal:
    goals: list[PoseLike] = field(default_factory=list)
    planner_id: str = ""
    start: PoseLike | None = None
    use_start: bool = False


@dataclass
class FollowPathGoal:
    path: Path
    controller_id: str = ""
    goal_checker_id: str = ""
    progress_checker_id: str = ""


@dataclass
class SmoothPathGoal:
    path: Path
    smoother_id: str = ""
    max_smoothing_duration: float = 1.0
    check_for_collisions: bool = True


# -- behavior_server ------------------------------------------------------------------------


@dataclass(frozen=True)
class SpinGoal:
    """nav2_msgs/action/Spin goal: radians to turn (sign = direction), seconds allowed."""

    target_yaw: float = 1.57
    time_allowance: float = 10.0
    disable_collision_checks: bool = False


@dataclass(frozen=True)
class SpinFeedback:
    angular_distance_traveled: float


@dataclass(frozen=True)
class DriveOnHeadingGoal:
    """nav2_msgs/action/DriveOnHeading goal. `target` is a Point (only x may be non-zero)
    or a number (x); `speed` has the sign of the motion (negative drives backwards)."""

    target: Any = 0.15
    speed: float = 0.025
    time_allowance: float = 10.0
    disable_collision_checks: bool = False


@dataclass(frozen=True)
class DriveOnHeadingFeedback:
    distance_traveled: float


@dataclass(frozen=True)
class BackUpGoal:
    """nav2_msgs/action/BackUp goal: `target` x (or a number) metres back at `speed` m/s."""

    target: Any = 0.15
    speed: float = 0.025
    time_allowance: float = 10.0
    disable_collision_checks: bool = False


#: BackUp's feedback has the same field as DriveOnHeading's.
BackUpFeedback = DriveOnHeadingFeedback


@dataclass(frozen=True)
class WaitGoal:
    """nav2_msgs/action/Wait goal: `time` in seconds."""

    time: float = 1.0


@dataclass(frozen=True)
class WaitFeedback:
    time_left: float


@dataclass(frozen=True)
class AssistedTeleopGoal:
    """nav2_msgs/action/AssistedTeleop goal: seconds of teleop allowed (0 or less: no limit)."""

    time_allowance: float = 10.0


@dataclass(frozen=True)
class AssistedTeleopFeedback:
    current_teleop_duration: float


@dataclass(frozen=True)
class BehaviorResult:
    """A behaviour action's result fields besides the error code (`total_elapsed_time`)."""

    total_elapsed_time: float


# -- bt_navigator, waypoint_follower ----------------------------------------------------


@dataclass
class NavigateToPoseGoal:
    pose: Any  # Pose2D, PoseStamped or (x, y, yaw)
    behavior_tree: str = ""


@dataclass
class NavigateThroughPosesGoal:
    poses: list[Any] = field(default_factory=list)
    behavior_tree: str = ""


@dataclass
class NavigateToPoseFeedback:
    current_pose: Pose2D
    navigation_time: float
    estimated_time_remaining: float
    number_of_recoveries: int
    distance_remaining: float


@dataclass
class NavigateThroughPosesFeedback(NavigateToPoseFeedback):
    number_of_poses_remaining: int = 0


@dataclass
class FollowWaypointsGoal:
    poses: list[Any] = field(default_factory=list)


@dataclass(frozen=True)
class MissedWaypoint:
    """nav2_msgs/MissedWaypoint."""

    index: int
    goal: Any
    error_code: int
    error_msg: str = ""


@dataclass
class FollowWaypointsFeedback:
    current_waypoint: int
    missed_waypoints: list[MissedWaypoint]


@dataclass
class FollowWaypointsResult:
    missed_waypoints: list[MissedWaypoint]

    @property
    def missed_indices(self) -> list[int]:
        return [m.index for m in self.missed_waypoints]


# -- btnav's own actions: exploring, and driving a teleop script -------------------------


@dataclass
class ExploreGoal:
    """Explore until no reachable frontier is left (explore_lite's job, as one action)."""

    behavior_tree: str = ""


@dataclass
class ExploreFeedback(NavigateToPoseFeedback):
    frontiers_left: int = 0
    explored_area: float = 0.0  # m^2 of free space mapped


@dataclass
class ExploreResult:
    explored_area: float  # m^2 of free space mapped
    blacklisted_frontiers: int


@dataclass
class DriveGoal:
    """Velocity commands `(linear_x, angular_z, seconds)`, one after the other (teleop);
    `assisted`: through Nav2's AssistedTeleop (published on `cmd_vel_teleop`)."""

    commands: list[tuple[float, float, float]] = field(default_factory=list)
    assisted: bool = False


@dataclass
class DriveFeedback:
    command_index: int
    time_left: float
