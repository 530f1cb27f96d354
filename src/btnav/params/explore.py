"""Keys of exploration: explore_lite's node (m-explore's ROS 2 port), as its params file spells them.

The defaults are those of explore_lite's own `params.yaml`, the file its users copy.
"""

from __future__ import annotations

from pydantic import Field

from .node import NodeParams
from .schema import Frame, ignored


class ExploreParams(NodeParams):
    """explore: frontier exploration on the global costmap, goals sent to bt_navigator's tree."""

    robot_base_frame: Frame = "base_footprint"
    planner_frequency: float = Field(
        0.15, gt=0.0, description="Hz: how often frontiers are searched again while a goal runs"
    )
    progress_timeout: float = Field(
        30.0, gt=0.0, description="s without getting closer to a goal before it is blacklisted"
    )
    potential_scale: float = Field(3.0, ge=0.0, description="weight of a frontier's distance")
    orientation_scale: float = ignored(0.0, "explore_lite leaves it unused too")
    gain_scale: float = Field(1.0, ge=0.0, description="weight of a frontier's size")
    min_frontier_size: float = Field(0.75, ge=0.0, description="m: smaller frontiers are ignored")
    return_to_init: bool = Field(False, description="drive back to the start when done")
    costmap_topic: str = ignored("costmap", "btnav searches the global costmap directly")
    costmap_updates_topic: str = ignored(
        "costmap_updates", "btnav searches the global costmap directly"
    )
    visualize: bool = ignored(False, "run.gif and run.png draw the map instead of RViz markers")
    transform_tolerance: float = ignored(0.3, "transforms are exact on sim time")
