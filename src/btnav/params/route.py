"""Keys of Nav2's route_server (nav2_route), with Nav2's names and defaults.

The plugin lists (`edge_cost_functions`, `operations`, and the single
`graph_file_loader` / `graph_file_saver`) name sections that the loader validates with
each plugin's own `Params`, as for the other servers. `graph_filepath` may hold
`$(find-pkg-share nav2_route)/graphs/...`: btnav's bundled `graphs/` folder stands in
for nav2_route's share folder. Nav2's launch fills it in from its `graph` argument;
a mission's `route_graph:` does that here.
"""

from __future__ import annotations

from pydantic import Field

from .node import NodeParams
from .schema import Frame, Names, Why, ignored


class RouteServerParams(NodeParams):
    """route_server: routes on a graph (ComputeRoute) and tracks them (ComputeAndTrackRoute)."""

    base_frame: Frame = "base_link"
    route_frame: Frame = "map"
    path_density: float = Field(0.05, gt=0.0, description="m between the dense path's poses")
    max_iterations: int = Field(0, ge=0, description="search iterations; 0: no limit")
    max_planning_time: float = ignored(
        2.0, "a warning when routing is slow: routing takes no sim time in btnav", ge=0.0
    )
    smooth_corners: bool = False
    smoothing_radius: float = Field(1.0, gt=0.0)
    smoothing_angle_threshold: float = Field(2.9, ge=0.0)
    costmap_topic: str = "global_costmap/costmap_raw"
    graph_filepath: str = ""
    graph_file_loader: str = "GeoJsonGraphFileLoader"
    graph_file_saver: str = "GeoJsonGraphFileSaver"
    edge_cost_functions: Names = ["DistanceScorer", "DynamicEdgesScorer"]
    operations: Names = ["AdjustSpeedLimit", "ReroutingService"]
    tracker_update_rate: float = Field(50.0, gt=0.0)
    aggregate_blocked_ids: bool = False
    boundary_radius_to_achieve_node: float = Field(1.0, ge=0.0)
    radius_to_achieve_node: float = Field(2.0, ge=0.0)
    max_prune_dist_from_edge: float = Field(8.0, ge=0.0)
    min_prune_dist_from_goal: float = Field(0.15, ge=0.0)
    min_prune_dist_from_start: float = Field(0.10, ge=0.0)
    prune_goal: bool = True
    enable_nn_search: bool = True
    max_nn_search_iterations: int = Field(10000, gt=0)
    num_nearest_nodes: int = Field(5, ge=0)
    transform_tolerance: float = ignored(0.1, Why.TF, ge=0.0)
