"""Keys of the localisers: Nav2's amcl and slam_toolbox (Nav2's SLAM of choice)."""

from __future__ import annotations

from pydantic import Field, field_validator, model_validator

from ..core.suggest import best_match
from ..plugins import canonical
from .legacy_keys import legacy_value
from .nav2_known import AMCL_MOTION_MODELS
from .node import NodeParams
from .schema import FieldProblem, Frame, ParamsModel, Why, ignored, one_of

#: Why slam_toolbox's covariance scales do nothing in btnav.
_NO_COVARIANCE = (
    "btnav's slam publishes its pose without a covariance (all zeros): nothing to scale"
)

LaserModel = one_of("likelihood_field", "beam", "likelihood_field_prob")
SlamMode = one_of("mapping", "localization")


class InitialPose(ParamsModel):
    """amcl's `initial_pose.{x,y,z,yaw}` (used when set_initial_pose is true)."""

    x: float = 0.0
    y: float = 0.0
    z: float = 0.0
    yaw: float = 0.0


class AmclParams(NodeParams):
    """amcl: adaptive Monte Carlo localisation against a known map."""

    alpha1: float = Field(0.2, ge=0.0, description="rotation noise from rotation")
    alpha2: float = Field(0.2, ge=0.0, description="rotation noise from translation")
    alpha3: float = Field(0.2, ge=0.0, description="translation noise from translation")
    alpha4: float = Field(0.2, ge=0.0, description="translation noise from rotation")
    alpha5: float = Field(0.2, ge=0.0, description="strafe noise (omni model only)")
    base_frame_id: Frame = "base_footprint"
    global_frame_id: Frame = "map"
    odom_frame_id: Frame = "odom"
    beam_skip_distance: float = Field(0.5, ge=0.0)
    beam_skip_error_threshold: float = Field(0.9, ge=0.0, le=1.0)
    beam_skip_threshold: float = Field(0.3, ge=0.0, le=1.0)
    do_beamskip: bool = False
    lambda_short: float = Field(0.1, gt=0.0)
    laser_likelihood_max_dist: float = Field(2.0, gt=0.0)
    laser_max_range: float = Field(100.0, description="m; -1 uses the scan's range_max")
    laser_min_range: float = Field(-1.0, description="m; -1 uses the scan's range_min")
    laser_model_type: LaserModel = "likelihood_field"
    set_initial_pose: bool = False
    initial_pose: InitialPose = Field(default_factory=InitialPose)
    max_beams: int = Field(60, ge=2)
    max_particles: int = Field(2000, ge=1)
    min_particles: int = Field(500, ge=1)
    pf_err: float = Field(0.05, gt=0.0, lt=1.0)
    pf_z: float = Field(0.99, gt=0.0, lt=1.0)
    recovery_alpha_fast: float = Field(0.0, ge=0.0, le=1.0)
    recovery_alpha_slow: float = Field(0.0, ge=0.0, le=1.0)
    resample_interval: int = Field(1, ge=1)
    robot_model_type: str = "nav2_amcl::DifferentialMotionModel"
    sigma_hit: float = Field(0.2, gt=0.0)
    tf_broadcast: bool = True
    update_min_a: float = Field(0.2, ge=0.0)
    update_min_d: float = Field(0.25, ge=0.0)
    z_hit: float = Field(0.5, ge=0.0, le=1.0)
    z_max: float = Field(0.05, ge=0.0, le=1.0)
    z_rand: float = Field(0.5, ge=0.0, le=1.0)
    z_short: float = Field(0.05, ge=0.0, le=1.0)
    first_map_only: bool = False
    always_reset_initial_pose: bool = False
    freespace_downsampling: bool = False
    random_seed: int = Field(-1, description="-1: derived from the mission seed")
    save_pose_rate: float = ignored(0.5, "btnav does not save the pose between runs", ge=0.0)
    initialize_at_saved_pose: bool = ignored(False, "btnav does not save the pose between runs")
    saved_pose_filepath: str = ignored("/tmp/amcl_saved_pose", "btnav does not save the pose")
    transform_tolerance: float = ignored(1.0, Why.TF, ge=0.0)
    scan_topic: str = ignored("scan", Why.TOPIC)
    map_topic: str = ignored("map", Why.TOPIC)

    @field_validator("robot_model_type")
    @classmethod
    def _motion_model(cls, value: str) -> str:
        renamed = legacy_value("amcl", "robot_model_type", value)
        if renamed is not None:  # Foxy's `differential`: Nav2 stops at start-up on it
            raise FieldProblem((), renamed)
        if canonical(value) not in {canonical(m) for m in AMCL_MOTION_MODELS}:
            raise FieldProblem(
                (),
                f"unknown motion model '{value}'; Nav2's are {', '.join(AMCL_MOTION_MODELS)}",
                suggestion=best_match(value, AMCL_MOTION_MODELS),
            )
        return value

    @model_validator(mode="after")
    def _particles(self) -> AmclParams:
        if self.min_particles > self.max_particles:
            raise FieldProblem(
                "min_particles",
                f"min_particles ({self.min_particles}) is above max_particles ({self.max_particles})",
            )
        return self


class SlamToolboxParams(NodeParams):
    """slam_toolbox: Karto-style graph SLAM; the keys of its mapper and its ROS wrapper."""

    mode: SlamMode = "mapping"
    odom_frame: Frame = "odom"
    map_frame: Frame = "map"
    base_frame: Frame = "base_footprint"
    resolution: float = Field(0.05, gt=0.0)
    max_laser_range: float = Field(25.0, gt=0.0)
    throttle_scans: int = Field(1, ge=1)
    transform_publish_period: float = ignored(
        0.05,
        "btnav sets map -> odom once per processed scan and its frame tree keeps it: "
        "there is no publishing thread whose period this sets (not even 0, never)",
        ge=0.0,
    )
    map_update_interval: float = Field(10.0, gt=0.0)
    minimum_time_interval: float = Field(0.5, ge=0.0)
    position_covariance_scale: float = ignored(1.0, _NO_COVARIANCE, gt=0.0)
    yaw_covariance_scale: float = ignored(1.0, _NO_COVARIANCE, gt=0.0)
    map_start_pose: list[float] | None = Field(None, min_length=3, max_length=3)
    #: A serialised pose graph (`.npz`, the extension may be left out as slam_toolbox
    #: does): localised on with `mode: localization`, mapped on from (`map_start_pose`
    #: placing the first new scan) with `mode: mapping`.
    map_file_name: str = ""
    # Karto mapper
    use_scan_matching: bool = True
    #: Karto's reference pose for the distances between scans (near chains, loop
    #: candidates): the scan's barycenter, or (false) its pose.
    use_scan_barycenter: bool = True
    minimum_travel_distance: float = Field(0.5, ge=0.0)
    minimum_travel_heading: float = Field(0.5, ge=0.0)
    scan_buffer_size: int = Field(10, ge=1)
    scan_buffer_maximum_scan_distance: float = Field(10.0, gt=0.0)
    link_match_minimum_response_fine: float = Field(0.1, ge=0.0, le=1.0)
    link_scan_maximum_distance: float = Field(1.5, gt=0.0)
    loop_search_maximum_distance: float = Field(3.0, gt=0.0)
    do_loop_closing: bool = True
    loop_match_minimum_chain_size: int = Field(10, ge=1)
    loop_match_maximum_variance_coarse: float = Field(3.0, gt=0.0)
    loop_match_minimum_response_coarse: float = Field(0.35, ge=0.0, le=1.0)
    loop_match_minimum_response_fine: float = Field(0.45, ge=0.0, le=1.0)
    correlation_search_space_dimension: float = Field(0.5, gt=0.0)
    correlation_search_space_resolution: float = Field(0.01, gt=0.0)
    correlation_search_space_smear_deviation: float = Field(0.1, gt=0.0)
    loop_search_space_dimension: float = Field(8.0, gt=0.0)
    loop_search_space_resolution: float = Field(0.05, gt=0.0)
    loop_search_space_smear_deviation: float = Field(0.03, gt=0.0)
    distance_variance_penalty: float = Field(0.5, ge=0.0)
    angle_variance_penalty: float = Field(1.0, ge=0.0)
    fine_search_angle_offset: float = Field(0.00349, gt=0.0)
    coarse_search_angle_offset: float = Field(0.349, gt=0.0)
    coarse_angle_resolution: float = Field(0.0349, gt=0.0)
    minimum_angle_penalty: float = Field(0.9, ge=0.0)
    minimum_distance_penalty: float = Field(0.05, ge=0.0)
    use_response_expansion: bool = True
    # Accepted, not acted on
    solver_plugin: str = ignored(
        "solver_plugins::CeresSolver", "btnav's pose graph has its own solver"
    )
    ceres_linear_solver: str = ignored("SPARSE_NORMAL_CHOLESKY", "btnav's pose graph solver")
    ceres_preconditioner: str = ignored("JACOBI", "btnav's pose graph solver")
    ceres_trust_strategy: str = ignored("LM", "btnav's pose graph solver")
    ceres_dogleg_type: str = ignored("TRADITIONAL_DOGLEG", "btnav's pose graph solver")
    ceres_loss_function: str = ignored("None", "btnav's pose graph solver")
    scan_topic: str = ignored("/scan", Why.TOPIC)
    scan_queue_size: int = ignored(1, Why.QOS)
    map_name: str = ignored("/map", Why.TOPIC)
    use_map_saver: bool = ignored(True, "btnav writes the map itself (outputs: [map])")
    map_start_at_dock: bool = ignored(False, "btnav has no docks: use map_start_pose")
    debug_logging: bool = ignored(False, "slam_toolbox's console logging")
    transform_timeout: float = ignored(0.5, Why.TF, ge=0.0)
    tf_buffer_duration: float = ignored(30.0, Why.TF, ge=0.0)
    stack_size_to_use: int = ignored(40000000, "a C++ thread stack size")
    enable_interactive_mode: bool = ignored(False, Why.VIZ)
    use_lifecycle_manager: bool = ignored(False, Why.ROS)
    paused_new_measurements: bool = ignored(False, "a runtime service flag of slam_toolbox")
