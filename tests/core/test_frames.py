from __future__ import annotations

import math

import numpy as np
import pytest

from btnav.core.errors import FrameError
from btnav.core.frames import FrameTree
from btnav.core.geometry import Pose2D


def robot_tree() -> FrameTree:
    tree = FrameTree.rep105()
    tree.set_transform("map", "odom", Pose2D(1.0, 2.0, 0.1), stamp=3.0)
    tree.set_transform("odom", "base_footprint", Pose2D(0.5, 0.0, math.pi / 2), stamp=3.0)
    tree.set_static("base_link", "laser", Pose2D(0.1, 0.0, math.pi))
    return tree


def test_lookup_chains_the_transforms():
    tree = robot_tree()
    expected = Pose2D(1.0, 2.0, 0.1) @ Pose2D(0.5, 0.0, math.pi / 2) @ Pose2D(0.1, 0.0, math.pi)
    assert np.allclose(tree.lookup("map", "laser").as_array(), expected.as_array())
    back = tree.lookup("laser", "map")
    assert np.allclose((back @ tree.lookup("map", "laser")).as_array(), 0.0, atol=1e-12)
    # a point 1 m ahead of the (backwards-mounted) laser is behind the robot
    p = tree.lookup("base_link", "laser").transform_points([[1.0, 0.0]])
    assert np.allclose(p, [[-0.9, 0.0]])


def test_missing_frame_names_it_and_lists_the_frames():
    with pytest.raises(FrameError) as info:
        robot_tree().lookup("map", "base_scan")
    msg = str(info.value)
    assert "'base_scan'" in msg
    for frame in ("map", "odom", "base_footprint", "base_link", "laser"):
        assert frame in msg


def test_misspelt_frame_suggests_the_right_one():
    with pytest.raises(FrameError) as info:
        robot_tree().lookup("map", "base_foot_print")
    assert info.value.suggestion == "base_footprint"


def test_a_frame_has_one_parent_and_no_loops():
    tree = robot_tree()
    with pytest.raises(FrameError, match="one parent"):
        tree.set_static("map", "laser", Pose2D())
    with pytest.raises(FrameError, match="loop"):
        tree.set_static("laser", "map2", Pose2D())
        tree.set_static("map2", "map", Pose2D())


def test_static_frames_cannot_be_updated_as_stamped():
    with pytest.raises(FrameError, match="static"):
        robot_tree().set_transform("base_link", "laser", Pose2D(), stamp=1.0)


def test_disconnected_trees():
    tree = robot_tree()
    tree.set_static("world", "table", Pose2D())
    with pytest.raises(FrameError, match="not connected"):
        tree.lookup("map", "table")


def test_describe_reads_like_view_frames():
    text = robot_tree().describe()
    assert text.splitlines()[0] == "map"
    assert "    laser" in text or "laser" in text.splitlines()[-1]
