"""Fixtures for costmap tests: scans of simple scenes, frame trees, small maps."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pytest

from btnav.core.frames import FrameTree
from btnav.core.geometry import Pose2D
from btnav.core.messages import LaserScan


def wall_scan(
    distance: float | None, half_width: float = 0.5, beams: int = 360, range_max: float = 8.0
) -> LaserScan:
    """A full-circle scan seeing a wall `distance` ahead (x = distance in the laser frame)
    over |y| <= half_width; everything else is a no-return (+inf). None: nothing at all."""
    inc = 2 * np.pi / beams
    angles = -np.pi + inc * np.arange(beams)
    ranges = np.full(beams, np.inf, np.float32)
    if distance is not None:
        with np.errstate(divide="ignore"):
            r = distance / np.cos(angles)
        ahead = (np.cos(angles) > 0) & (np.abs(r * np.sin(angles)) <= half_width) & (r <= range_max)
        ranges[ahead] = r[ahead]
    return LaserScan(0.0, "laser", -np.pi, np.pi - inc, inc, 0.12, range_max, ranges)


@pytest.fixture
def scan_of() -> Callable[..., LaserScan]:
    return wall_scan


@pytest.fixture
def tree_at() -> Callable[..., FrameTree]:
    """`tree_at(x, y, yaw)`: REP-105 frames with the robot there (in odom = map) and a laser on it."""

    def make(x: float = 0.0, y: float = 0.0, yaw: float = 0.0) -> FrameTree:
        tree = FrameTree.rep105()
        tree.set_transform("odom", "base_footprint", Pose2D(x, y, yaw), 0.0)
        tree.set_static("base_link", "laser", Pose2D(0.0, 0.0, 0.0))
        return tree

    return make
