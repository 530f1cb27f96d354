"""SLAM: scan matching, the pose graph, occupancy mapping and laser odometry (slam_toolbox / Karto)."""
