-- btnav's Cartographer configuration for its simulated robot (a diff-drive base with one
-- 360-beam planar lidar reaching 0.12 m to 8 m at 10 Hz, and wheel odometry at 50 Hz; see
-- worlds/*.yaml). It is written the way turtlebot3_cartographer's turtlebot3_lds_2d.lua
-- is: include Cartographer's defaults, build the options table cartographer_ros reads,
-- then override a few defaults. `btnav.slam.cartographer.config.load_cartographer_config`
-- runs it; `cartographer_node -configuration_basename cartographer_2d.lua` reads it as well.

include "map_builder.lua"
include "trajectory_builder.lua"

options = {
  map_builder = MAP_BUILDER,
  trajectory_builder = TRAJECTORY_BUILDER,
  map_frame = "map",
  tracking_frame = "base_link",
  -- The simulator publishes odom -> base_link, so Cartographer publishes map -> odom.
  published_frame = "odom",
  odom_frame = "odom",
  provide_odom_frame = false,
  publish_frame_projected_to_2d = true,
  use_odometry = true,
  use_nav_sat = false,
  use_landmarks = false,
  num_laser_scans = 1,
  num_multi_echo_laser_scans = 0,
  num_subdivisions_per_laser_scan = 1,
  num_point_clouds = 0,
  lookup_transform_timeout_sec = 0.2,
  submap_publish_period_sec = 0.3,
  pose_publish_period_sec = 5e-3,
  trajectory_publish_period_sec = 30e-3,
  rangefinder_sampling_ratio = 1.,
  odometry_sampling_ratio = 1.,
  fixed_frame_pose_sampling_ratio = 1.,
  imu_sampling_ratio = 1.,
  landmarks_sampling_ratio = 1.,
}

MAP_BUILDER.use_trajectory_builder_2d = true

-- The lidar's own limits; a beam with no return is free space out to its full reach.
TRAJECTORY_BUILDER_2D.min_range = 0.12
TRAJECTORY_BUILDER_2D.max_range = 8.
TRAJECTORY_BUILDER_2D.missing_data_ray_length = 8.
-- The simulated robot has no IMU.
TRAJECTORY_BUILDER_2D.use_imu_data = false
-- Search around the odometry guess before refining: wheel odometry drifts.
TRAJECTORY_BUILDER_2D.use_online_correlative_scan_matching = true
TRAJECTORY_BUILDER_2D.motion_filter.max_angle_radians = math.rad(1.)

POSE_GRAPH.constraint_builder.min_score = 0.65
POSE_GRAPH.constraint_builder.global_localization_min_score = 0.7

-- The simulated wheels slip (metres of drift a lap): in the optimisation, trust local
-- SLAM's relative poses ten times more than odometry's (Cartographer's tuning guide).
POSE_GRAPH.optimization_problem.odometry_translation_weight = 1e4
POSE_GRAPH.optimization_problem.odometry_rotation_weight = 1e4

return options
