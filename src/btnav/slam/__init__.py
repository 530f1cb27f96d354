"""SLAM, by engine, as the two Nav2 users reach for lay themselves out.

- `karto/`: slam_toolbox (`slam_toolbox`, Nav2's default): Karto's mapper and correlative
  scan matcher (its `lib/karto_sdk`) and slam_toolbox's node around it: the scan gate,
  odometry fusion, continued mapping, localisation on a saved graph, graph files and the
  occupancy map.
- `cartographer/`: Cartographer's 2D SLAM (`cartographer`), configured by its `.lua`:
  options and the Lua sandbox, submaps, the real-time, Ceres-style and fast correlative
  matchers, local and global SLAM, the offline run.
- `graph/`: the pose graph and its sparse solver, which both engines optimise.
- `logs/`: recorded logs (CARMEN, ROS 1 / ROS 2 bags) that `btnav slam` maps offline.

Laser odometry is an odometry source, not SLAM (`btnav.odometry`); SLAM's scores live
beside the tests that use them (`btnav.testing.slam_metrics`).
"""
