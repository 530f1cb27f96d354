-- Values: Cartographer's documented defaults, from configuration_files/trajectory_builder.lua of
-- cartographer-project/cartographer (commit 877157a0d91788a7700221d87232d412cb3c1ef4).
-- Copyright 2016 The Cartographer Authors. Licensed under the Apache License, Version 2.0
-- (http://www.apache.org/licenses/LICENSE-2.0); distributed "AS IS", without warranties.
-- btnav ships this copy as data: `include "trajectory_builder.lua"` in a configuration finds it when the
-- configuration's own folder has no file of that name.

include "trajectory_builder_2d.lua"
include "trajectory_builder_3d.lua"

TRAJECTORY_BUILDER = {
  trajectory_builder_2d = TRAJECTORY_BUILDER_2D,
  trajectory_builder_3d = TRAJECTORY_BUILDER_3D,
  -- Optional, absent by default: pure_localization_trimmer = { max_submaps_to_keep = 3 },
  collate_fixed_frame = true,
  collate_landmarks = false,
}
