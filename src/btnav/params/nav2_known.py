"""What btnav knows of Nav2 without implementing it: plugin types, nodes, legacy names.

A params file written for Nav2 names many things btnav does not (yet) run: a
following server, a vector object server. Knowing their names lets btnav tell "not
implemented yet" (the file is fine, the key is listed as ignored) apart from a
typo (an error with the closest spelling). Names Nav2 itself no longer reads are
in `legacy_keys`. The names below are the
plugin class names Nav2 exports through pluginlib and the node names its launch
files start; they are facts about Nav2, kept in one table.
"""

from __future__ import annotations

import fnmatch

from ..plugins import canonical

#: Nav2's plugin type names per btnav plugin kind (`pkg::Class`; `pkg/Class` is the same).
NAV2_PLUGIN_TYPES: dict[str, tuple[str, ...]] = {
    "planner": (
        "nav2_navfn_planner::NavfnPlanner",
        "nav2_smac_planner::SmacPlanner2D",
        "nav2_smac_planner::SmacPlannerHybrid",
        "nav2_smac_planner::SmacPlannerLattice",
        "nav2_theta_star_planner::ThetaStarPlanner",
    ),
    "controller": (
        "nav2_mppi_controller::MPPIController",
        "dwb_core::DWBLocalPlanner",
        "nav2_regulated_pure_pursuit_controller::RegulatedPurePursuitController",
        "nav2_rotation_shim_controller::RotationShimController",
        "nav2_graceful_controller::GracefulController",
    ),
    "goal_checker": (
        "nav2_controller::SimpleGoalChecker",
        "nav2_controller::StoppedGoalChecker",
        "nav2_controller::PositionGoalChecker",
        "nav2_controller::AxisGoalChecker",
        "nav2_controller::AdaptiveToleranceGoalChecker",
        "dwb_plugins::SimpleGoalChecker",
        "dwb_plugins::StoppedGoalChecker",
    ),
    "progress_checker": (
        "nav2_controller::SimpleProgressChecker",
        "nav2_controller::PoseProgressChecker",
    ),
    "path_handler": ("nav2_controller::FeasiblePathHandler",),
    "smoother": (
        "nav2_smoother::SimpleSmoother",
        "nav2_smoother::SavitzkyGolaySmoother",
        "nav2_constrained_smoother/ConstrainedSmoother",
    ),
    "behavior": (
        "nav2_behaviors::Spin",
        "nav2_behaviors::BackUp",
        "nav2_behaviors::DriveOnHeading",
        "nav2_behaviors::Wait",
        "nav2_behaviors::AssistedTeleop",
        # (Galactic's nav2_recoveries::Spin etc. are in legacy_keys: Nav2 refuses them now.)
    ),
    "costmap_layer": (
        "nav2_costmap_2d::StaticLayer",
        "nav2_costmap_2d::ObstacleLayer",
        "nav2_costmap_2d::VoxelLayer",
        "nav2_costmap_2d::InflationLayer",
        "nav2_costmap_2d::LegacyInflationLayer",
        "nav2_costmap_2d::AsymmetricInflationLayer",
        "nav2_costmap_2d::RangeSensorLayer",
        "nav2_costmap_2d::DenoiseLayer",
        "nav2_costmap_2d::PluginContainerLayer",
        "nav2_costmap_2d::OrderLayer",
        "nav2_costmap_2d::ZoneParameterFilter",
    ),
    "costmap_filter": (
        "nav2_costmap_2d::KeepoutFilter",
        "nav2_costmap_2d::SpeedFilter",
        "nav2_costmap_2d::BinaryFilter",
    ),
    "navigator": (
        "nav2_bt_navigator::NavigateToPoseNavigator",
        "nav2_bt_navigator::NavigateThroughPosesNavigator",
    ),
    "charging_dock": (
        "opennav_docking::SimpleChargingDock",
        "opennav_docking::SimpleNonChargingDock",
    ),
    "edge_cost_function": (
        "nav2_route::DistanceScorer",
        "nav2_route::CostmapScorer",
        "nav2_route::TimeScorer",
        "nav2_route::PenaltyScorer",
        "nav2_route::SemanticScorer",
        "nav2_route::GoalOrientationScorer",
        "nav2_route::StartPoseOrientationScorer",
        "nav2_route::DynamicEdgesScorer",
    ),
    "route_operation": (
        "nav2_route::AdjustSpeedLimit",
        "nav2_route::ReroutingService",
        "nav2_route::CollisionMonitor",
        "nav2_route::TimeMarker",
        "nav2_route::TriggerEvent",
    ),
    "graph_file_loader": ("nav2_route::GeoJsonGraphFileLoader",),
    "graph_file_saver": ("nav2_route::GeoJsonGraphFileSaver",),
    "waypoint_task_executor": (
        "nav2_waypoint_follower::WaitAtWaypoint",
        "nav2_waypoint_follower::PhotoAtWaypoint",
        "nav2_waypoint_follower::InputAtWaypoint",
    ),
}

#: AMCL's motion models (`robot_model_type`): not a section, a type string.
AMCL_MOTION_MODELS: tuple[str, ...] = (
    "nav2_amcl::DifferentialMotionModel",
    "nav2_amcl::OmniMotionModel",
)

_KNOWN_CANONICAL: dict[str, dict[str, str]] = {
    kind: {canonical(t): t for t in types} for kind, types in NAV2_PLUGIN_TYPES.items()
}

_OTHER_ZONE_SERVER = (
    "a costmap filter server under a name of its own: btnav runs the names Nav2's launch "
    "files give them (keepout_filter_mask_server, speed_costmap_filter_info_server, ...)"
)
_LIFECYCLE = "btnav starts and stops every server itself: there is no lifecycle manager"
_OLD_HELPER = "a helper node of older Nav2 releases; current Nav2 and btnav read the server itself"

#: Nodes a Nav2 params file configures that btnav knows but does not run, and why.
NAV2_KNOWN_NODES: dict[str, str] = {
    "following_server": "Nav2's following server (opennav_following) is not implemented yet",
    "vector_object_server": "Nav2's vector object server is not implemented yet",
    "loopback_simulator": "btnav's own simulator (world YAML) replaces Nav2's loopback simulator",
    "robot_state_publisher": "btnav's frame tree comes from the world file's robot and sensors",
    "lifecycle_manager": _LIFECYCLE,
    "lifecycle_manager_navigation": _LIFECYCLE,
    "lifecycle_manager_localization": _LIFECYCLE,
    "lifecycle_manager_slam": _LIFECYCLE,
    "lifecycle_manager_map_server": _LIFECYCLE,
    "lifecycle_manager_keepout_zone": _LIFECYCLE,
    "lifecycle_manager_speed_zone": _LIFECYCLE,
    "/**": "wildcard parameters for every ROS node; btnav reads each server's own section",
}

#: Name patterns of nodes known the same way (helper nodes of older Nav2 releases).
NAV2_KNOWN_NODE_PATTERNS: dict[str, str] = {
    "lifecycle_manager_*": _LIFECYCLE,
    "*_rclcpp_node": _OLD_HELPER,
    "*_costmap_client": _OLD_HELPER,
    "amcl_map_client": _OLD_HELPER,
    "*_filter_mask_server": _OTHER_ZONE_SERVER,
    "*_costmap_filter_info_server": _OTHER_ZONE_SERVER,
}


def known_plugin_type(kind: str, type_name: str) -> str | None:
    """Nav2's spelling of `type_name` if it is a Nav2 plugin of `kind`, else None."""
    return _KNOWN_CANONICAL.get(kind, {}).get(canonical(type_name))


def known_plugin_types(kind: str) -> tuple[str, ...]:
    return NAV2_PLUGIN_TYPES.get(kind, ())


def known_node_reason(name: str) -> str | None:
    """Why btnav ignores the node `name`, or None when it is not a node btnav knows."""
    if name in NAV2_KNOWN_NODES:
        return NAV2_KNOWN_NODES[name]
    for pattern, reason in NAV2_KNOWN_NODE_PATTERNS.items():
        if fnmatch.fnmatchcase(name, pattern):
            return reason
    return None


def class_name(type_name: str) -> str:
    """`nav2_mppi_controller::MPPIController` -> `MPPIController` (for short reports)."""
    return canonical(type_name).rsplit("/", 1)[-1]
