"""bt_navigator, waypoint_follower and the Python `Navigator` API (above the trees)."""

from .bt_navigator import (
    BtNavigator,
    NavigateThroughPosesFeedback,
    NavigateThroughPosesGoal,
    NavigateToPoseFeedback,
    NavigateToPoseGoal,
)
from .navigator import Navigator
from .waypoint_follower import (
    FollowWaypointsGoal,
    FollowWaypointsResult,
    MissedWaypoint,
    WaitAtWaypoint,
    WaypointFollower,
)

__all__ = [
    "BtNavigator",
    "FollowWaypointsGoal",
    "FollowWaypointsResult",
    "MissedWaypoint",
    "NavigateThroughPosesFeedback",
    "NavigateThroughPosesGoal",
    "NavigateToPoseFeedback",
    "NavigateToPoseGoal",
    "Navigator",
    "WaitAtWaypoint",
    "WaypointFollower",
]
