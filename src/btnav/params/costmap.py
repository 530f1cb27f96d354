"""Server-level keys of Nav2's costmaps (local_costmap, global_costmap: one node type).

Layer sections (`inflation_layer:`, ...) are plugin sections named by `plugins`;
filter sections by `filters` (costmap filters: `btnav.costmap.filters`).
"""

from __future__ import annotations

from pydantic import Field

from .node import NodeParams
from .schema import Frame, Names, Points, Why, ignored


class CostmapParams(NodeParams):
    """A Nav2 costmap (Costmap2DROS). Defaults are Nav2's, for both costmaps."""

    update_frequency: float = Field(5.0, gt=0.0)
    publish_frequency: float = ignored(
        1.0, "costmap publishing for RViz: btnav reads the costmap directly", ge=0.0
    )
    global_frame: Frame = "map"
    robot_base_frame: Frame = "base_link"
    rolling_window: bool = False
    width: int = Field(5, gt=0, description="m")
    height: int = Field(5, gt=0, description="m")
    resolution: float = Field(0.1, gt=0.0, description="m per cell")
    origin_x: float = 0.0
    origin_y: float = 0.0
    robot_radius: float = Field(0.1, gt=0.0)
    footprint: Points = Field((), description='"[[x, y], ...]"; empty: a circle of robot_radius')
    footprint_padding: float = Field(0.01, ge=0.0)
    track_unknown_space: bool = False
    lethal_cost_threshold: int = Field(100, ge=0, le=255)
    unknown_cost_value: int = Field(255, ge=0, le=255)
    inscribed_obstacle_cost_value: int = Field(99, ge=0, le=255)
    trinary_costmap: bool = True
    use_maximum: bool = False
    plugins: Names = ["static_layer", "obstacle_layer", "inflation_layer"]
    filters: Names = []
    always_send_full_costmap: bool = ignored(False, "costmap publishing for RViz")
    transform_tolerance: float = ignored(0.3, Why.TF, ge=0.0)
    initial_transform_timeout: float = ignored(60.0, Why.TF, ge=0.0)
    map_vis_z: float = ignored(0.0, Why.VIZ)
    subscribe_to_stamped_footprint: bool = ignored(False, Why.QOS)
    map_topic: str = ignored("map", Why.TOPIC)  # Nav2 Humble read it here for the static layer
