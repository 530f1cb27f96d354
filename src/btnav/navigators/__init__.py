"""bt_navigator, waypoint_follower and the Python API (`BasicNavigator`) (above the trees)."""

from .bt_navigator import (
    BtNavigator,
    NavigateThroughPosesFeedback,
    NavigateThroughPosesGoal,
    NavigateToPoseFeedback,
    NavigateToPoseGoal,
)
from .navigator import BasicNavigator
from .waypoint_follower import (
    FollowWaypointsGoal,
    FollowWaypointsResult,
    MissedWaypoint,
    WaitAtWaypoint,
    WaypointFollower,
)

__all__ = [
    "BasicNavigator",
    "BtNavigator",
    "FollowWaypointsGoal",
    "FollowWaypointsResult",
    "MissedWaypoint",
    "NavigateThroughPosesFeedback",
    "NavigateThroughPosesGoal",
    "NavigateToPoseFeedback",
    "NavigateToPoseGoal",
    "WaitAtWaypoint",
    "WaypointFollower",
]
