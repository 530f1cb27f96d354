-- Values: Cartographer's documented defaults, from configuration_files/map_builder.lua of
-- cartographer-project/cartographer (commit 877157a0d91788a7700221d87232d412cb3c1ef4).
-- Copyright 2016 The Cartographer Authors. Licensed under the Apache License, Version 2.0
-- (http://www.apache.org/licenses/LICENSE-2.0); distributed "AS IS", without warranties.
-- btnav ships this copy as data: `include "map_builder.lua"` in a configuration finds it when the
-- configuration's own folder has no file of that name.

include "pose_graph.lua"

-- btnav builds 2D maps only: a configuration must set use_trajectory_builder_2d = true
-- (Cartographer, too, needs exactly one of the two builders switched on).
MAP_BUILDER = {
  use_trajectory_builder_2d = false,
  use_trajectory_builder_3d = false,
  num_background_threads = 4,
  pose_graph = POSE_GRAPH,
  collate_by_trajectory = false,
}
