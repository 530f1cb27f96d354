"""Docks as solids: a small static box behind each dock pose, seen by the lidar, touched
by a docked robot (a touch the world does not count as a collision)."""

from __future__ import annotations

import numpy as np

from ..core import fmath
from ..core.geometry import Pose2D
from .dock_spec import DockSpec
from .scene import Solid, box_corners
from .world_spec import FootprintSpec, WorldSpec


def front_extent(footprint: FootprintSpec) -> float:
    """How far the footprint reaches ahead of base_footprint (where a dock's face goes)."""
    if footprint.radius is not None:
        return float(footprint.radius)
    return float(max(x for x, _ in footprint.polygon or [(0.0, 0.0)]))


def face_distance(dock: DockSpec, spec: WorldSpec) -> float:
    return dock.face if dock.face is not None else front_extent(spec.robot.footprint)


def marker_pose(dock: DockSpec, spec: WorldSpec) -> Pose2D:
    """The middle of the dock's front face, facing the approaching robot's way (dock yaw)."""
    x, y, yaw = dock.pose
    s, c = fmath.sincos(float(yaw))
    d = face_distance(dock, spec)
    return Pose2D(x + c * d, y + s * d, yaw)


def dock_solids(spec: WorldSpec) -> list[Solid]:
    """One box per dock, after the world's walls and obstacles (keys `("docks", i)`)."""
    solids = []
    for i, dock in enumerate(spec.docks):
        x, y, yaw = dock.pose
        depth, width = dock.size
        s, c = fmath.sincos(float(yaw))
        ahead = face_distance(dock, spec) + depth / 2.0
        origin = np.array([x + c * ahead, y + s * ahead])
        corners = box_corners((0.0, 0.0), (depth, width), yaw)
        solids.append(
            Solid(f"docks[{i}] ({dock.name})", ("docks", i), origin, [corners], [corners])
        )
    return solids
