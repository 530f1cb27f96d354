"""Names Nav2 no longer reads, or never read where they are written: a catalogue.

A params file carried over from ROS 1, from an older Nav2 release or from a tutorial
often holds keys Nav2 itself skips: ROS 1 names (move_base, dwa_local_planner and
base_local_planner, amcl), names Nav2 renamed between distributions, and ports of
Nav2's BT action nodes written into a server's section. Nav2 runs such a file without
reading them; btnav does the same and says so once per key, naming what reads that
setting now. A catalogue hit wins over did-you-mean: `goal_checker_plugin` is Foxy's
name, not a typo of `goal_checker_plugins`. The few old names Nav2 refuses outright
(`error_code_names`, a `nav2_recoveries/Spin` plugin, amcl's `robot_model_type:
differential`) stay errors, with the name to write instead.

Sources (facts about Nav2 and ROS 1, kept in one place): Nav2's migration guides
(docs.nav2.org, Dashing to Kilted), Nav2's source history, ROS 1 navigation's
dynamic_reconfigure files (move_base, dwa_local_planner, base_local_planner, amcl)
and ROS 1 dwb's parameter back-compatibility (locusrobotics/robot_navigation).

A scope says where a key was found: a server's name (`controller_server`), a plugin
section as `<kind>:<canonical type>` (`controller:dwb_core/DWBLocalPlanner`), or `/`
for a top-level node name. Entries match scopes by glob pattern.
"""

from __future__ import annotations

import fnmatch
from dataclasses import dataclass
from enum import Enum

from ..plugins import canonical


class Family(str, Enum):
    """Why Nav2 does not read a key."""

    ROS1 = "ROS 1"
    RENAMED = "renamed"
    BT_PORT = "BT port"
    MISPLACED = "misplaced"


@dataclass(frozen=True)
class LegacyKey:
    """A key Nav2 skips (or refuses), where it is found, and what reads that setting now."""

    name: str
    scopes: tuple[str, ...]
    family: Family
    #: What the name is, as a phrase: "a ROS 1 dwa_local_planner name".
    what: str = ""
    #: Its current equivalent, as a user writes it (None: Nav2 has none).
    now: str | None = None
    #: Nav2 refuses to start with it: an error, not a warning.
    refused: bool = False
    #: For a BT port: the BT nodes that have it (the tree sets it on one of them).
    nodes: tuple[str, ...] = ()

    def message(self, scope: str = "", value: object = None) -> str:
        """`<what>; Nav2 ignores it too (current equivalent: <now>)`; for a BT port, the
        node of the section it is in (`behavior:nav2_behaviors/Spin`) and its value."""
        if self.nodes:
            section = scope.rsplit("/", 1)[-1] if scope.startswith("behavior:") else ""
            node = section if section in self.nodes else self.nodes[0]
            one = node == section or len(self.nodes) == 1
            whose = f"the {node} BT node" if one else f"the {', '.join(self.nodes)} BT nodes"
            where = "the behavior_server" if self.scopes == BEHAVIORS else self.scopes[0]
            shown = value if isinstance(value, str | int | float) else "..."
            return (
                f"a port of {whose}, which {where} does not read; Nav2 ignores it "
                f'too (set it in the tree: <{node} {self.name}="{shown}"/>)'
            )
        text = f"{self.what}; " + (
            "Nav2 refuses to start with it" if self.refused else "Nav2 ignores it too"
        )
        if self.now:
            text += f" (current equivalent: {self.now})"
        return text


DWB = "controller:dwb_core/DWBLocalPlanner"
COSTMAPS = ("local_costmap", "global_costmap")
OBSTACLE_LAYERS = (
    "costmap_layer:nav2_costmap_2d/ObstacleLayer",
    "costmap_layer:nav2_costmap_2d/VoxelLayer",
)
#: Where a move_base key lands when a ROS 1 file is ported section by section.
NAVIGATION = ("bt_navigator", "controller_server", "planner_server", "behavior_server")
#: Every controller but DWB (DWB reads xy_goal_tolerance itself, for RotateToGoal).
OTHER_CONTROLLERS = (
    "controller:nav2_mppi_controller/*",
    "controller:nav2_regulated_pure_pursuit_controller/*",
    "controller:nav2_rotation_shim_controller/*",
    "controller:nav2_graceful_controller/*",
)
BEHAVIORS = ("behavior_server", "behavior:*")

_DWA = "a ROS 1 dwa_local_planner name"
_DWA_OR_BLP = "a ROS 1 dwa_local_planner/base_local_planner name"
_BLP = "a ROS 1 base_local_planner (TrajectoryPlannerROS) name"
_MOVE_BASE = "a ROS 1 move_base name"
_AMCL = "a ROS 1 amcl name"
_COSTMAP_ROS1 = "a ROS 1 costmap_2d name (before its layers)"
_CRITIC = "a critic's key in DWB: list the critic in critics: and set"
_GOAL_CHECKER = "the goal checker's section (goal_checker_plugins), e.g. goal_checker."


def _entries(
    family: Family, scopes: tuple[str, ...], what: str, names: dict[str, str | None]
) -> list[LegacyKey]:
    return [LegacyKey(n, scopes, family, what, now) for n, now in names.items()]


def _bt_ports(ports: dict[str, tuple[str, ...]]) -> list[LegacyKey]:
    """Ports of Nav2's behaviour BT nodes: the tree sends them with each goal, and no
    server reads them from its parameters."""
    return [
        LegacyKey(port, BEHAVIORS, Family.BT_PORT, nodes=nodes) for port, nodes in ports.items()
    ]


CATALOGUE: tuple[LegacyKey, ...] = (
    # -- ROS 1 dwa_local_planner / base_local_planner names in a DWB section --------------
    *_entries(
        Family.ROS1,
        (DWB,),
        _DWA,
        {
            "max_rot_vel": "max_vel_theta",
            "min_rot_vel": "min_speed_theta",
            "max_trans_vel": "max_speed_xy",
            "min_trans_vel": "min_speed_xy",
            "max_vel_trans": "max_speed_xy",
            "min_vel_trans": "min_speed_xy",
            "acc_lim_th": "acc_lim_theta",
            "acc_lim_trans": None,
            "vth_samples": "vtheta_samples",
            "path_distance_bias": f"{_CRITIC} PathDist.scale (and PathAlign.scale)",
            "goal_distance_bias": f"{_CRITIC} GoalDist.scale (and GoalAlign.scale)",
            "twirling_scale": f"{_CRITIC} Twirling.scale",
            "forward_point_distance": f"{_CRITIC} GoalAlign/PathAlign.forward_point_distance",
            "oscillation_reset_dist": f"{_CRITIC} Oscillation.oscillation_reset_dist",
            "oscillation_reset_angle": f"{_CRITIC} Oscillation.oscillation_reset_angle",
            "stop_time_buffer": None,
            "scaling_speed": None,
            "max_scaling_factor": None,
            "use_dwa": "trajectory_generator_name (how DWB samples velocities)",
            "theta_stopped_vel": f"{_GOAL_CHECKER}rot_stopped_velocity",
            "trans_stopped_vel": "trans_stopped_velocity",
            "yaw_goal_tolerance": f"{_GOAL_CHECKER}yaw_goal_tolerance",
            "latch_xy_goal_tolerance": f"{_GOAL_CHECKER}stateful",
            "restore_defaults": None,
        },
    ),
    *_entries(
        Family.ROS1,
        (DWB,),
        _DWA_OR_BLP,
        {
            "min_vel_theta": "min_speed_theta (|angular velocity| DWB never goes below)",
            "sim_granularity": "linear_granularity (time_granularity with discretize_by_time)",
            "angular_sim_granularity": "angular_granularity",
            "occdist_scale": f"{_CRITIC} BaseObstacle.scale",
        },
    ),
    *_entries(
        Family.ROS1,
        (DWB,),
        _BLP,
        {
            "min_in_place_vel_theta": "min_speed_theta",
            "pdist_scale": f"{_CRITIC} PathDist.scale",
            "gdist_scale": f"{_CRITIC} GoalDist.scale",
            "escape_vel": None,
            "escape_reset_dist": None,
            "escape_reset_theta": None,
            "heading_lookahead": None,
            "heading_scoring": None,
            "heading_scoring_timestep": None,
            "holonomic_robot": "min_vel_y/max_vel_y (and vy_samples) for a holonomic base",
            "y_vels": None,
            "dwa": "trajectory_generator_name (how DWB samples velocities)",
            "meter_scoring": None,
            "simple_attractor": None,
        },
    ),
    # The tutorial names of issue 34: no ROS 1 or Nav2 local planner reads them.
    *_entries(
        Family.ROS1,
        (DWB,),
        "a name no ROS 1 or Nav2 local planner has (dwa_local_planner's footprint scaling "
        "was scaling_speed, max_scaling_factor)",
        {"scaling_xy": None, "scaling_theta": None},
    ),
    # -- ROS 1 move_base names, ported into Nav2's servers --------------------------------
    *_entries(
        Family.ROS1,
        NAVIGATION,
        _MOVE_BASE,
        {
            "base_global_planner": "planner_server: planner_plugins and GridBased.plugin",
            "base_local_planner": "controller_server: controller_plugins and FollowPath.plugin",
            "recovery_behaviors": "behavior_server: behavior_plugins, called by the tree",
            "recovery_behavior_enabled": "the tree's recovery branch (RecoveryNode)",
            "clearing_rotation_allowed": "the tree's recovery branch (its Spin node)",
            "planner_frequency": "the tree's RateController hz around ComputePathToPose",
            "planner_patience": None,
            "controller_patience": "progress_checker.movement_time_allowance "
            "(and controller_server.failure_tolerance)",
            "max_planning_retries": "the tree's RecoveryNode number_of_retries",
            "conservative_reset_dist": "the tree's ClearCostmapExceptRegion reset_distance",
            "shutdown_costmaps": None,
            "oscillation_timeout": "progress_checker.movement_time_allowance",
            "oscillation_distance": "progress_checker.required_movement_radius",
            "make_plan_clear_costmap": None,
            "make_plan_add_unreachable_goal": None,
        },
    ),
    # -- ROS 1 amcl names -----------------------------------------------------------------
    *_entries(
        Family.ROS1,
        ("amcl",),
        _AMCL,
        {
            "odom_model_type": "robot_model_type (diff: nav2_amcl::DifferentialMotionModel, "
            "omni: nav2_amcl::OmniMotionModel)",
            **{f"odom_alpha{i}": f"alpha{i}" for i in range(1, 6)},
            "laser_max_beams": "max_beams",
            "laser_z_hit": "z_hit",
            "laser_z_short": "z_short",
            "laser_z_max": "z_max",
            "laser_z_rand": "z_rand",
            "laser_sigma_hit": "sigma_hit",
            "laser_lambda_short": "lambda_short",
            "kld_err": "pf_err",
            "kld_z": "pf_z",
            "initial_pose_x": "initial_pose.x, with set_initial_pose: true",
            "initial_pose_y": "initial_pose.y, with set_initial_pose: true",
            "initial_pose_a": "initial_pose.yaw, with set_initial_pose: true",
            "initial_cov_xx": None,
            "initial_cov_yy": None,
            "initial_cov_aa": None,
            "gui_publish_rate": None,
            "use_map_topic": None,
            "selective_resampling": None,
            "force_update_after_initialpose": None,
            "force_update_after_set_map": None,
            "std_warn_level_x": None,
            "std_warn_level_y": None,
            "std_warn_level_yaw": None,
            "bag_scan_period": None,
            "restore_defaults": None,
        },
    ),
    # -- ROS 1 costmap_2d names -----------------------------------------------------------
    *_entries(
        Family.ROS1,
        COSTMAPS,
        _COSTMAP_ROS1,
        {
            "map_type": "the layers in plugins:",
            "static_map": "a StaticLayer in plugins:",
            "inflation_radius": "inflation_layer.inflation_radius",
            "cost_scaling_factor": "inflation_layer.cost_scaling_factor",
            "observation_sources": "obstacle_layer.observation_sources",
            "obstacle_range": "obstacle_layer.<source>.obstacle_max_range",
            "raytrace_range": "obstacle_layer.<source>.raytrace_max_range",
        },
    ),
    *_entries(
        Family.RENAMED,
        OBSTACLE_LAYERS,
        "Nav2 Foxy's name, renamed in Galactic and read per observation source",
        {
            "obstacle_range": "<source>.obstacle_max_range",
            "raytrace_range": "<source>.raytrace_max_range",
        },
    ),
    # -- names Nav2 renamed between distributions -----------------------------------------
    LegacyKey(
        "goal_checker_plugin",
        ("controller_server",),
        Family.RENAMED,
        "Nav2 Foxy's name, replaced in Galactic by a list",
        "goal_checker_plugins",
    ),
    LegacyKey(
        "progress_checker_plugin",
        ("controller_server",),
        Family.RENAMED,
        "Nav2 Humble's name, replaced in Iron by a list, no longer read since Jazzy",
        "progress_checker_plugins",
    ),
    *_entries(
        Family.RENAMED,
        ("controller_server",),
        "Nav2 Eloquent's name",
        {
            "controller_plugin_ids": "controller_plugins",
            "controller_plugin_types": "<name>.plugin for each of controller_plugins",
        },
    ),
    *_entries(
        Family.RENAMED,
        ("planner_server",),
        "Nav2 Eloquent's name",
        {
            "planner_plugin_ids": "planner_plugins",
            "planner_plugin_types": "<name>.plugin for each of planner_plugins",
        },
    ),
    LegacyKey(
        "recovery_plugins",
        ("behavior_server",),
        Family.RENAMED,
        "Nav2 Galactic's name, renamed in Humble (Nav2 then runs its default behaviours)",
        "behavior_plugins",
    ),
    LegacyKey(
        "default_bt_xml_filename",
        ("bt_navigator",),
        Family.RENAMED,
        "Nav2 Foxy's name, renamed in Galactic",
        "default_nav_to_pose_bt_xml",
    ),
    LegacyKey(
        "enable_groot_monitoring",
        ("bt_navigator",),
        Family.RENAMED,
        "Nav2 Galactic's server-wide key; Nav2 now reads it per navigator",
        "navigate_to_pose.enable_groot_monitoring",
    ),
    *_entries(
        Family.RENAMED,
        ("bt_navigator",),
        "Nav2 Galactic's Groot (ZMQ) port, removed in Humble",
        {
            "groot_zmq_publisher_port": "navigate_to_pose.groot_server_port",
            "groot_zmq_server_port": "navigate_to_pose.groot_server_port",
        },
    ),
    LegacyKey(
        "error_code_names",
        ("bt_navigator",),
        Family.RENAMED,
        "Nav2 Iron's name, replaced in Kilted by prefixes (compute_path, not "
        "compute_path_error_code)",
        "error_code_name_prefixes",
        refused=True,
    ),
    LegacyKey(
        "viz_expansions",
        ("planner:nav2_smac_planner/*",),
        Family.RENAMED,
        "Nav2 Iron's name, renamed in Jazzy",
        "debug_visualizations",
    ),
    LegacyKey(
        "max_planning_time_ms",
        ("planner:nav2_smac_planner/*",),
        Family.RENAMED,
        "Nav2 Foxy's name (milliseconds), replaced in Galactic",
        "max_planning_time (seconds)",
    ),
    LegacyKey(
        "max_points",
        ("collision_monitor",),
        Family.RENAMED,
        "Nav2 Humble's name, replaced in Iron with a new meaning",
        "min_points = max_points + 1",
    ),
    LegacyKey(
        "use_approach_linear_velocity_scaling",
        ("controller:nav2_regulated_pure_pursuit_controller/*",),
        Family.RENAMED,
        "removed in Nav2 Humble: approach velocity scaling is always on",
    ),
    # -- keys read elsewhere than where they are written ----------------------------------
    LegacyKey(
        "controller_frequency",
        (DWB, *OTHER_CONTROLLERS, *COSTMAPS, "bt_navigator", "planner_server"),
        Family.MISPLACED,
        "a controller_server key",
        "controller_server.controller_frequency",
    ),
    *_entries(
        Family.MISPLACED,
        ("controller_server", *OTHER_CONTROLLERS),
        "a goal checker's key",
        {
            "xy_goal_tolerance": f"{_GOAL_CHECKER}xy_goal_tolerance",
            "yaw_goal_tolerance": f"{_GOAL_CHECKER}yaw_goal_tolerance",
        },
    ),
    LegacyKey(
        "robot_radius",
        ("controller_server", "planner_server", "bt_navigator", "behavior_server"),
        Family.MISPLACED,
        "a costmap key",
        "local_costmap/global_costmap robot_radius",
    ),
    LegacyKey(
        "use_astar",
        ("planner:nav2_smac_planner/*", "planner:nav2_theta_star_planner/*"),
        Family.MISPLACED,
        "a NavfnPlanner key (the Smac and Theta* planners always search with A*)",
    ),
    # -- ports of Nav2's BT action nodes, written into the behavior_server's sections -----
    *_bt_ports(
        {
            "spin_dist": ("Spin",),
            "backup_dist": ("BackUp",),
            "backup_speed": ("BackUp",),
            "dist_to_travel": ("DriveOnHeading",),
            "speed": ("DriveOnHeading",),
            "wait_duration": ("Wait",),
            "time_allowance": ("Spin", "BackUp", "DriveOnHeading", "AssistedTeleop"),
            "disable_collision_checks": ("Spin", "BackUp", "DriveOnHeading"),
            "is_recovery": ("Spin", "AssistedTeleop"),
        }
    ),
    LegacyKey(
        "target_yaw",
        BEHAVIORS,
        Family.BT_PORT,
        "a field of the Spin action's goal, which the tree's Spin node fills from its "
        "spin_dist port; the behavior_server does not read it from its parameters",
        'the tree\'s Spin node: <Spin spin_dist="..."/>',
    ),
    *(
        LegacyKey(port, (server,), Family.BT_PORT, nodes=(node,))
        for port, node, server in (
            ("controller_id", "FollowPath", "controller_server"),
            ("goal_checker_id", "FollowPath", "controller_server"),
            ("progress_checker_id", "FollowPath", "controller_server"),
            ("planner_id", "ComputePathToPose", "planner_server"),
            ("use_start", "ComputePathToPose", "planner_server"),
        )
    ),
    # -- top-level node names -------------------------------------------------------------
    LegacyKey(
        "recoveries_server",
        ("/",),
        Family.RENAMED,
        "Nav2 Galactic's node, renamed in Humble (its parameters are not read, and "
        "behavior_server runs with its own)",
        "behavior_server",
    ),
    LegacyKey(
        "move_base",
        ("/",),
        Family.ROS1,
        "ROS 1's navigation node; Nav2 has none of that name",
        "bt_navigator, planner_server, controller_server and behavior_server",
    ),
)

_BY_NAME: dict[str, list[LegacyKey]] = {}
for _entry in CATALOGUE:
    _BY_NAME.setdefault(_entry.name, []).append(_entry)


def legacy_key(scope: str, name: str) -> LegacyKey | None:
    """The catalogue's entry for `name` found in `scope`, or None."""
    for entry in _BY_NAME.get(name, ()):
        if any(fnmatch.fnmatchcase(scope, pattern) for pattern in entry.scopes):
            return entry
    return None


def plugin_scope(kind: str, type_name: str) -> str:
    """The scope of a plugin section: `controller:dwb_core/DWBLocalPlanner`."""
    return f"{kind}:{canonical(type_name)}"


@dataclass(frozen=True)
class LegacyType:
    """A plugin type name Nav2 renamed; pluginlib cannot load the old one, so Nav2 stops."""

    old: str
    new: str
    what: str

    def message(self, written: str) -> str:
        """The sentence for the type as `written`, naming the new one in the same spelling."""
        new = self.new.replace("/", "::") if "::" in written else self.new
        return (
            f"'{written}' is {self.what}; Nav2 cannot load that plugin any more (it stops "
            f"at start-up): write {new}"
        )


LEGACY_PLUGIN_TYPES: dict[str, LegacyType] = {
    canonical(t.old): t
    for t in (
        *(
            LegacyType(
                f"nav2_recoveries/{n}",
                f"nav2_behaviors/{n}",
                "Nav2 Galactic's name (Humble renamed nav2_recoveries to nav2_behaviors)",
            )
            for n in ("Spin", "BackUp", "Wait")
        ),
        LegacyType(
            "smac_planner/SmacPlanner",
            "nav2_smac_planner/SmacPlannerHybrid",
            "Nav2 Foxy's name (Galactic renamed it)",
        ),
        LegacyType(
            "smac_planner/SmacPlanner2D",
            "nav2_smac_planner/SmacPlanner2D",
            "Nav2 Foxy's name (Galactic renamed the package)",
        ),
    )
}


def legacy_plugin_type(type_name: str) -> LegacyType | None:
    return LEGACY_PLUGIN_TYPES.get(canonical(type_name))


#: Values Nav2 renamed, by (scope, key): old value -> the value to write.
LEGACY_VALUES: dict[tuple[str, str], dict[str, tuple[str, str]]] = {
    ("amcl", "robot_model_type"): {
        "differential": ("nav2_amcl::DifferentialMotionModel", "Nav2 Foxy's"),
        "omnidirectional": ("nav2_amcl::OmniMotionModel", "Nav2 Foxy's"),
    },
}


def legacy_value(scope: str, key: str, value: object) -> str | None:
    """Why `value` of `key` is an old spelling Nav2 refuses, naming the new one; or None."""
    found = LEGACY_VALUES.get((scope, key), {}).get(value) if isinstance(value, str) else None
    if found is None:
        return None
    new, whose = found
    return (
        f"'{value}' is {whose} name for {new}; Nav2 Galactic and later cannot load it "
        f"(it stops at start-up): write {new}"
    )
