"""The servers btnav implements: their model and the plugin lists that name their sections.

Nav2 semantics kept here: when a `*_plugins` list is absent, or equals Nav2's
default list, the default names get Nav2's default plugin types even without a
section (`planner_server` with no `planner_plugins` runs `GridBased` =
NavfnPlanner). A name outside the defaults needs its section with `plugin:`.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from .collision_detector import CollisionDetectorParams
from .collision_monitor import CollisionMonitorParams
from .costmap import CostmapParams
from .costmap_filters import (
    FILTER_INFO_SERVERS,
    FILTER_MASK_SERVERS,
    CostmapFilterInfoServerParams,
    FilterMaskServerParams,
)
from .docking import DockingServerParams
from .explore import ExploreParams
from .localization import AmclParams, SlamToolboxParams
from .map_io import MapSaverParams, MapServerParams
from .navigation import (
    BehaviorServerParams,
    BtNavigatorParams,
    ControllerServerParams,
    PlannerServerParams,
    SmootherServerParams,
    VelocitySmootherParams,
    WaypointFollowerParams,
)
from .node import NodeParams
from .route import RouteServerParams


@dataclass(frozen=True)
class PluginList:
    """A key naming plugin sections (`controller_plugins: [FollowPath]`) and their kind."""

    key: str
    kind: str
    #: Nav2's default names and types (the names are also the model field's default).
    default_types: Mapping[str, str] = field(default_factory=dict)
    #: One name as a string (`waypoint_task_executor_plugin`), not a list.
    single: bool = False
    #: Nav2 declares the default types whatever the list holds (waypoint_follower).
    always_default_types: bool = False
    #: False: btnav has no such plugins at all; sections are ignored.
    implemented: bool = True


@dataclass(frozen=True)
class ServerSpec:
    """A Nav2 server btnav implements."""

    name: str
    model: type[NodeParams]
    plugin_lists: tuple[PluginList, ...] = ()
    #: Costmaps live in a namespace of their own name: `local_costmap: local_costmap:`.
    nested: bool = False

    def default_names(self, plist: PluginList) -> list[str]:
        default: Any = self.model.model_fields[plist.key].default
        return [default] if plist.single else list(default)


_COSTMAP_LISTS = (
    PluginList(
        "plugins",
        "costmap_layer",
        {
            "static_layer": "nav2_costmap_2d::StaticLayer",
            "obstacle_layer": "nav2_costmap_2d::ObstacleLayer",
            "inflation_layer": "nav2_costmap_2d::InflationLayer",
        },
    ),
    PluginList("filters", "costmap_filter"),
)

SERVERS: dict[str, ServerSpec] = {
    spec.name: spec
    for spec in (
        ServerSpec("amcl", AmclParams),
        ServerSpec(
            "bt_navigator",
            BtNavigatorParams,
            (
                PluginList(
                    "navigators",
                    "navigator",
                    {
                        "navigate_to_pose": "nav2_bt_navigator::NavigateToPoseNavigator",
                        "navigate_through_poses": "nav2_bt_navigator::NavigateThroughPosesNavigator",
                    },
                ),
            ),
        ),
        ServerSpec(
            "controller_server",
            ControllerServerParams,
            (
                PluginList(
                    "controller_plugins",
                    "controller",
                    {"FollowPath": "nav2_mppi_controller::MPPIController"},
                ),
                PluginList(
                    "progress_checker_plugins",
                    "progress_checker",
                    {"progress_checker": "nav2_controller::SimpleProgressChecker"},
                ),
                PluginList(
                    "goal_checker_plugins",
                    "goal_checker",
                    {"goal_checker": "nav2_controller::SimpleGoalChecker"},
                ),
                PluginList(
                    "path_handler_plugins",
                    "path_handler",
                    {"PathHandler": "nav2_controller::FeasiblePathHandler"},
                ),
            ),
        ),
        ServerSpec("local_costmap", CostmapParams, _COSTMAP_LISTS, nested=True),
        ServerSpec("global_costmap", CostmapParams, _COSTMAP_LISTS, nested=True),
        ServerSpec("map_server", MapServerParams),
        ServerSpec("map_saver", MapSaverParams),
        ServerSpec(
            "planner_server",
            PlannerServerParams,
            (
                PluginList(
                    "planner_plugins", "planner", {"GridBased": "nav2_navfn_planner::NavfnPlanner"}
                ),
            ),
        ),
        ServerSpec(
            "smoother_server",
            SmootherServerParams,
            (
                PluginList(
                    "smoother_plugins",
                    "smoother",
                    {"simple_smoother": "nav2_smoother::SimpleSmoother"},
                ),
            ),
        ),
        ServerSpec(
            "behavior_server",
            BehaviorServerParams,
            (
                PluginList(
                    "behavior_plugins",
                    "behavior",
                    {
                        "spin": "nav2_behaviors::Spin",
                        "backup": "nav2_behaviors::BackUp",
                        "drive_on_heading": "nav2_behaviors::DriveOnHeading",
                        "wait": "nav2_behaviors::Wait",
                    },
                ),
            ),
        ),
        ServerSpec(
            "waypoint_follower",
            WaypointFollowerParams,
            (
                PluginList(
                    "waypoint_task_executor_plugin",
                    "waypoint_task_executor",
                    {"wait_at_waypoint": "nav2_waypoint_follower::WaitAtWaypoint"},
                    single=True,
                    always_default_types=True,
                ),
            ),
        ),
        ServerSpec("velocity_smoother", VelocitySmootherParams),
        ServerSpec("collision_monitor", CollisionMonitorParams),
        ServerSpec("collision_detector", CollisionDetectorParams),
        ServerSpec("slam_toolbox", SlamToolboxParams),
        ServerSpec("explore", ExploreParams),
        ServerSpec(
            "docking_server",
            DockingServerParams,
            (PluginList("dock_plugins", "charging_dock"),),
        ),
        ServerSpec(
            "route_server",
            RouteServerParams,
            (
                PluginList(
                    "edge_cost_functions",
                    "edge_cost_function",
                    {
                        "DistanceScorer": "nav2_route::DistanceScorer",
                        "DynamicEdgesScorer": "nav2_route::DynamicEdgesScorer",
                    },
                ),
                PluginList(
                    "operations",
                    "route_operation",
                    {
                        "AdjustSpeedLimit": "nav2_route::AdjustSpeedLimit",
                        "ReroutingService": "nav2_route::ReroutingService",
                    },
                ),
                PluginList(
                    "graph_file_loader",
                    "graph_file_loader",
                    {"GeoJsonGraphFileLoader": "nav2_route::GeoJsonGraphFileLoader"},
                    single=True,
                ),
                PluginList(
                    "graph_file_saver",
                    "graph_file_saver",
                    {"GeoJsonGraphFileSaver": "nav2_route::GeoJsonGraphFileSaver"},
                    single=True,
                ),
            ),
        ),
        *(ServerSpec(name, FilterMaskServerParams) for name in FILTER_MASK_SERVERS),
        *(ServerSpec(name, CostmapFilterInfoServerParams) for name in FILTER_INFO_SERVERS),
    )
}
