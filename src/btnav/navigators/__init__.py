"""bt_navigator, waypoint_follower and the Python API (`BasicNavigator`), above the trees.

Their actions' goals, feedback and results are in `btnav.core.nav2_msgs`.
"""

from .basic_navigator import BasicNavigator
from .bt_navigator import BtNavigator
from .waypoint_follower import WaitAtWaypoint, WaypointFollower

__all__ = ["BasicNavigator", "BtNavigator", "WaitAtWaypoint", "WaypointFollower"]
