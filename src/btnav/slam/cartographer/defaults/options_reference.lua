-- btnav's reference for the table a Cartographer configuration returns (btnav's own file,
-- Apache License 2.0 like the rest of btnav). It holds every key cartographer_ros reads
-- from that table (node_options.cc, trajectory_options.cc) and every optional section the
-- builders read when present, each with the value btnav behaves as. btnav runs it to learn
-- the keys and value types a configuration may hold; a configuration never includes it.
-- Which keys may be left out is listed in btnav/slam/cartographer/config.py (OPTIONAL).

include "map_builder.lua"
include "trajectory_builder.lua"

MAP_BUILDER.use_trajectory_builder_2d = true

-- Optional sections: absent unless a configuration sets them.
TRAJECTORY_BUILDER.pure_localization_trimmer = {
  max_submaps_to_keep = 3,
}
TRAJECTORY_BUILDER.pose_graph_odometry_motion_filter = {
  max_time_seconds = 0.,
  max_distance_meters = 0.,
  max_angle_radians = 0.,
}
POSE_GRAPH.overlapping_submaps_trimmer_2d = {
  fresh_submaps_count = 1,
  min_covered_area = 2.,
  min_added_submaps_count = 5,
}

return {
  map_builder = MAP_BUILDER,
  trajectory_builder = TRAJECTORY_BUILDER,
  map_frame = "map",
  tracking_frame = "base_link",
  published_frame = "base_link",
  odom_frame = "odom",
  provide_odom_frame = true,
  publish_frame_projected_to_2d = true,
  use_odometry = false,
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
  -- Optional (cartographer_ros reads them only when present).
  publish_to_tf = true,
  publish_tracked_pose = false,
  use_pose_extrapolator = true,
  ignore_out_of_order = false,
}
