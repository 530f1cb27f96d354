"""Nav2's collision monitor and detector without ROS: zones around the robot, the points
sensed in them, and the action that makes the command safe (nav2_collision_monitor).

A layer beside `control`: it reads sensor messages, the frame tree and a costmap, and
knows nothing of servers. `nav/collision_monitor_server.py` puts it on the command
chain (`CollisionMonitorServer`) and runs the report-only detector
(`CollisionDetectorServer`).

- zones: `Polygon` (`points`, or the robot footprint for `approach`), `Circle`,
  `VelocityPolygon` (a sub-polygon chosen by the commanded velocity);
- actions (`ActionType`): stop, slowdown, limit, approach (`Polygon.collision_time`),
  none; `decide` picks the safest command the zones ask for;
- sources: `ScanSource` (LaserScan), `PolygonSource` (polygons handed to it),
  `CostmapSource` (cells at or above `cost_threshold`), each masked by its
  `ExclusionZone`s. Nav2's `pointcloud` and `range` sources need sensors a 2D
  simulation does not have.

Points are (N, 2) arrays in the robot base frame, one per source; every inside test
runs over all of them at once.
"""

from .action import Action, ActionType, action_type_of
from .build import make_polygons, make_sources
from .circle import Circle
from .costmap_source import CostmapSource
from .decide import decide
from .exclusion_zone import ExclusionZone
from .polygon import Polygon
from .polygon_source import PolygonInstance, PolygonSource
from .scan_source import ScanSource
from .source import Source, SourceFrames
from .velocity_polygon import VelocityPolygon

__all__ = [
    "Action",
    "ActionType",
    "Circle",
    "CostmapSource",
    "ExclusionZone",
    "Polygon",
    "PolygonInstance",
    "PolygonSource",
    "ScanSource",
    "Source",
    "SourceFrames",
    "VelocityPolygon",
    "action_type_of",
    "decide",
    "make_polygons",
    "make_sources",
]
