-- btnav's stand-in for Cartographer's configuration_files/trajectory_builder_3d.lua
-- (cartographer-project/cartographer, Apache License 2.0, Copyright 2016 The Cartographer
-- Authors). btnav builds 2D maps only, so this file is deliberately minimal: it exists so
-- that trajectory_builder.lua's include resolves and a 2D configuration copied from
-- Cartographer runs unchanged. btnav accepts whatever a configuration puts in
-- TRAJECTORY_BUILDER_3D without checking it and lists every such key as ignored;
-- MAP_BUILDER.use_trajectory_builder_3d = true is an error.

MAX_3D_RANGE = 60.
INTENSITY_THRESHOLD = 40

TRAJECTORY_BUILDER_3D = {}
