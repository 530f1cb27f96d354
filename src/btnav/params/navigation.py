"""Server-level keys of Nav2's navigation servers, with Nav2's names, defaults and ranges.

Plugin sections (`FollowPath:`, `GridBased:`, ...) are not fields here: the loader
takes them out by the names in the `*_plugins` lists and validates each with its
plugin's own `Params`. The list fields default to Nav2's default plugin names.
"""

from __future__ import annotations

from pydantic import Field, model_validator

from ..core.resources import bundled_dir
from .node import NodeParams
from .schema import FieldProblem, Frame, Names, Why, ignored, one_of

#: Nav2's default error-code prefixes of bt_navigator (BtActionServer).
DEFAULT_ERROR_CODE_NAME_PREFIXES = [
    "assisted_teleop",
    "backup",
    "compute_path",
    "dock_robot",
    "drive_on_heading",
    "follow_object",
    "follow_path",
    "nav_thru_poses",
    "nav_to_pose",
    "spin",
    "undock_robot",
    "wait",
]


class BtNavigatorParams(NodeParams):
    """bt_navigator: runs the navigators (NavigateToPose, NavigateThroughPoses) and their trees."""

    global_frame: Frame = "map"
    robot_base_frame: Frame = "base_link"
    transform_tolerance: float = ignored(0.1, Why.TF, ge=0.0)
    odom_topic: str = ignored("odom", Why.TOPIC)
    filter_duration: float = Field(0.3, gt=0.0)
    plugin_lib_names: list[str] = ignored(
        [], "C++ BT plugin libraries: btnav's BT nodes come from its bt_node plugin registry"
    )
    navigators: Names = ["navigate_to_pose", "navigate_through_poses"]
    bt_loop_duration: int = Field(10, gt=0, description="ms between two ticks of the tree")
    default_server_timeout: int = Field(
        20, gt=0, description="ms a BT action node waits for its server"
    )
    default_cancel_timeout: int = Field(50, gt=0)
    wait_for_service_timeout: int = Field(1000, gt=0)
    always_reload_bt_xml: bool = False
    bt_log_idle_transitions: bool = True
    error_code_name_prefixes: list[str] = Field(
        default_factory=lambda: list(DEFAULT_ERROR_CODE_NAME_PREFIXES)
    )
    # Nav2 defaults these to its share/behavior_trees folder; btnav's bundled trees
    # are that folder, and a bare tree name finds the bundled tree of that name.
    bt_search_directories: list[str] = Field(default_factory=lambda: [str(bundled_dir("trees"))])
    default_nav_to_pose_bt_xml: str = "navigate_to_pose_w_replanning_and_recovery"
    default_nav_through_poses_bt_xml: str = "navigate_through_poses_w_replanning_and_recovery"
    allow_navigator_preemption: bool = False
    navigator_preemption_timeout: int = Field(500, ge=0)


class ControllerServerParams(NodeParams):
    """controller_server: follows a path with a controller, judged by goal/progress checkers."""

    controller_frequency: float = Field(20.0, gt=0.0)
    min_x_velocity_threshold: float = Field(0.0001, ge=0.0)
    min_y_velocity_threshold: float = Field(0.0001, ge=0.0)
    min_theta_velocity_threshold: float = Field(0.0001, ge=0.0)
    failure_tolerance: float = Field(
        0.0, ge=-1.0, description="s a controller may fail before FollowPath fails; -1: forever"
    )
    costmap_update_timeout: float = Field(0.30, ge=0.0)
    publish_zero_velocity: bool = True
    odom_duration: float = Field(0.3, gt=0.0)
    search_window: float = Field(2.0, gt=0.0)
    progress_checker_plugins: Names = ["progress_checker"]
    goal_checker_plugins: Names = ["goal_checker"]
    controller_plugins: Names = ["FollowPath"]
    path_handler_plugins: Names = ["PathHandler"]
    speed_limit_topic: str = Field("speed_limit", min_length=1)
    odom_topic: str = ignored("odom", Why.TOPIC)
    use_realtime_priority: bool = ignored(False, Why.REALTIME)


class PlannerServerParams(NodeParams):
    """planner_server: computes global paths with the planner plugins."""

    planner_plugins: Names = ["GridBased"]
    expected_planner_frequency: float = ignored(
        1.0, "only sets Nav2's overrun warning: btnav plans within one sim step", ge=0.0
    )
    costmap_update_timeout: float = Field(1.0, ge=0.0)
    allow_partial_planning: bool = False


class SmootherServerParams(NodeParams):
    """smoother_server: smooths paths with the smoother plugins."""

    smoother_plugins: Names = ["simple_smoother"]
    robot_base_frame: Frame = "base_link"
    costmap_topic: str = ignored("global_costmap/costmap_raw", Why.TOPIC)
    footprint_topic: str = ignored("global_costmap/published_footprint", Why.TOPIC)
    transform_tolerance: float = ignored(0.1, Why.TF, ge=0.0)


class BehaviorServerParams(NodeParams):
    """behavior_server: recoveries (Spin, BackUp, ...); these keys are shared by its behaviors."""

    behavior_plugins: Names = ["spin", "backup", "drive_on_heading", "wait"]
    cycle_frequency: float = Field(10.0, gt=0.0)
    local_frame: Frame = "odom"
    global_frame: Frame = "map"
    robot_base_frame: Frame = "base_link"
    simulate_ahead_time: float = Field(2.0, ge=0.0)
    max_rotational_vel: float = Field(1.0, gt=0.0)
    min_rotational_vel: float = Field(0.4, ge=0.0)
    rotational_acc_lim: float = Field(3.2, gt=0.0)
    projection_time: float = Field(1.0, gt=0.0)
    simulation_time_step: float = Field(0.1, gt=0.0)
    transform_tolerance: float = ignored(0.1, Why.TF, ge=0.0)
    local_costmap_topic: str = ignored("local_costmap/costmap_raw", Why.TOPIC)
    global_costmap_topic: str = ignored("global_costmap/costmap_raw", Why.TOPIC)
    local_footprint_topic: str = ignored("local_costmap/published_footprint", Why.TOPIC)
    global_footprint_topic: str = ignored("global_costmap/published_footprint", Why.TOPIC)
    cmd_vel_teleop: str = ignored("cmd_vel_teleop", Why.TOPIC)

    @model_validator(mode="after")
    def _rotational_limits(self) -> BehaviorServerParams:
        if self.min_rotational_vel > self.max_rotational_vel:
            raise FieldProblem(
                "min_rotational_vel",
                f"min_rotational_vel ({self.min_rotational_vel}) is above "
                f"max_rotational_vel ({self.max_rotational_vel})",
            )
        return self


class WaypointFollowerParams(NodeParams):
    """waypoint_follower: one NavigateToPose per waypoint, a task executor at each."""

    loop_rate: int = Field(20, gt=0)
    stop_on_failure: bool = True
    waypoint_task_executor_plugin: str = Field("wait_at_waypoint", min_length=1)
    global_frame_id: Frame = "map"


Feedback = one_of("OPEN_LOOP", "CLOSED_LOOP")


class VelocitySmootherParams(NodeParams):
    """velocity_smoother: limits velocity and acceleration of the commands sent to the base."""

    smoothing_frequency: float = Field(20.0, gt=0.0)
    feedback: Feedback = "OPEN_LOOP"
    scale_velocities: bool = False
    max_velocity: list[float] = Field(default_factory=lambda: [0.5, 0.0, 2.5])
    min_velocity: list[float] = Field(default_factory=lambda: [-0.5, 0.0, -2.5])
    max_accel: list[float] = Field(default_factory=lambda: [2.5, 0.0, 3.2])
    max_decel: list[float] = Field(default_factory=lambda: [-2.5, 0.0, -3.2])
    deadband_velocity: list[float] = Field(default_factory=lambda: [0.0, 0.0, 0.0])
    odom_duration: float = Field(0.1, gt=0.0)
    velocity_timeout: float = Field(1.0, ge=0.0)
    odom_topic: str = ignored("odom", Why.TOPIC)
    use_realtime_priority: bool = ignored(False, Why.REALTIME)

    @model_validator(mode="after")
    def _limits(self) -> VelocitySmootherParams:
        """Nav2's own checks, each pointed at the number that breaks it."""
        size = len(self.max_velocity)
        if size not in (3, 6):
            raise FieldProblem("max_velocity", f"needs 3 values (x, y, theta) or 6, got {size}")
        for name in ("min_velocity", "max_accel", "max_decel", "deadband_velocity"):
            if len(getattr(self, name)) != size:
                raise FieldProblem(
                    name, f"needs {size} values like max_velocity, got {len(getattr(self, name))}"
                )
        for i in range(size):
            if self.max_velocity[i] < 0.0:
                raise FieldProblem(("max_velocity", i), "max_velocity values must be >= 0")
            if self.min_velocity[i] > 0.0:
                raise FieldProblem(("min_velocity", i), "min_velocity values must be <= 0")
            if self.max_accel[i] < 0.0:
                raise FieldProblem(("max_accel", i), "max_accel values must be >= 0")
            if self.max_decel[i] > 0.0:
                raise FieldProblem(("max_decel", i), "max_decel values must be <= 0")
            if self.deadband_velocity[i] < 0.0:
                raise FieldProblem(("deadband_velocity", i), "deadband values must be >= 0")
        return self
