"""The frame tree a world implies at its start: REP-105, one frame per sensor mount and the
robot description's links."""

from __future__ import annotations

from collections.abc import Iterable
from os import PathLike
from typing import Any

from ..core.frames import BASE_FOOTPRINT, BASE_LINK, MAP, ODOM, FrameTree
from ..core.geometry import Pose2D
from .world import World
from .world_sensors import make_sensors


def world_frame_tree(world: World | str | PathLike[str], seed: int = 0) -> FrameTree:
    """`map -> odom -> base_footprint -> base_link -> <sensor frames>` at t = 0.

    Odometry starts at identity at the start pose, so `map -> odom` is the start
    pose (what a perfect localiser would publish) and `odom -> base_footprint` is
    identity. Sensor mounts come from the world file, validated by their plugins,
    so a bad sensor entry fails here as it would in a run.
    """
    w = world if isinstance(world, World) else World.from_file(world, seed=seed)
    tree = FrameTree()
    tree.set_transform(MAP, ODOM, Pose2D(*w.spec.robot.pose), stamp=w.time)
    tree.set_transform(ODOM, BASE_FOOTPRINT, Pose2D(), stamp=w.time)
    add_robot_frames(tree, w, make_sensors(w, seed))
    return tree


def add_robot_frames(tree: FrameTree, world: World, sensors: Iterable[Any]) -> None:
    """The robot's static frames: `base_footprint -> base_link`, each sensor's mount, and
    the robot description's other links under their own parents (its link names)."""
    tree.set_static(BASE_FOOTPRINT, BASE_LINK, Pose2D())
    for sensor in sensors:
        tree.set_static(BASE_LINK, sensor.frame_id, sensor.mount)
    described = world.spec.robot.description
    if described is not None:
        for parent, child, pose in described.tf_edges():
            if not tree.has(child):
                tree.set_static(parent, child, Pose2D(*pose))
