"""Robot descriptions as users have them: URDF, xacro and Gazebo SDF models, without ROS.

`load_description(FILE, package_paths, args, model_paths)` reads one (xacro through
xacrodoc; `model://NAME` and SDF `<include>`s through Gazebo's model paths) into a
`RobotDescription`: the frame tree with the description's own link names, the
footprint (the base link's collision geometry seen from above; meshes through trimesh
when the `btnav[meshes]` extra is installed), the drive (a Gazebo drive plugin's block,
else the wheel and steering joints) and every 2D lidar from its Gazebo sensor block,
mounted where the joint chain puts it. A broken description is a `DescriptionError`
naming the user's file and line. This package sits at the layer of `maps` and
`params`: it imports only `core`.
"""

from __future__ import annotations

from .errors import DescriptionError
from .load import load_description
from .model_paths import ModelPaths
from .packages import BTNAV_ROBOTS, PackagePaths, robots_dir
from .robot_description import (
    DriveDescription,
    FootprintDescription,
    LidarDescription,
    LinkFrame,
    RobotDescription,
)

__all__ = [
    "BTNAV_ROBOTS",
    "DescriptionError",
    "DriveDescription",
    "FootprintDescription",
    "LidarDescription",
    "LinkFrame",
    "ModelPaths",
    "PackagePaths",
    "RobotDescription",
    "load_description",
    "robots_dir",
]
