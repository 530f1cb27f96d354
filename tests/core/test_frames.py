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


def _reference_lookup(tree: FrameTree, target: str, source: str) -> Pose2D:
    """lookup as Pose2D's own algebra spells it: inverse(target in root) @ (source in root)."""

    def to_root(frame: str) -> Pose2D:
        pose = Pose2D()
        while frame in tree._edges:
            edge = tree._edges[frame]
            pose = edge.transform @ pose
            frame = edge.parent
        return pose

    return to_root(target).inverse() @ to_root(source)


def _bits(p: Pose2D) -> tuple[str, ...]:
    return tuple(float(v).hex() if not math.isnan(v) else "nan" for v in (p.x, p.y, p.yaw))


def test_lookup_is_pose2d_algebra_bit_for_bit_signed_zeros_included():
    """The lookup's shortcuts (a root target, zero yaws) give Pose2D's bits, zeros' signs
    included, on random chains with zero, negative-zero and turned transforms."""
    rng = np.random.default_rng(7)
    values = [0.0, -0.0, 1.5, -2.25, 1e-300, -1e-300, 3.0, math.inf, -math.inf, math.nan]
    for _ in range(300):
        tree = FrameTree.rep105()

        def pick() -> Pose2D:
            x, y = (float(v) for v in rng.choice(values, 2))
            if rng.random() < 0.5:
                x, y = (float(v) for v in rng.normal(0.0, 5.0, 2))
            yaw = float(
                rng.choice([0.0, -0.0, math.pi, -3.0, 0.7, math.nan, float(rng.uniform(-3.1, 3.1))])
            )
            return Pose2D(x, y, yaw)

        tree.set_transform("map", "odom", pick(), stamp=1.0)
        tree.set_transform("odom", "base_footprint", pick(), stamp=1.0)
        tree.set_static("base_link", "laser", pick())
        tree.set_static("map", "marker", pick())
        frames = ["map", "odom", "base_footprint", "base_link", "laser", "marker"]
        for target in frames:
            for source in frames:
                got = tree.lookup(target, source)
                assert _bits(got) == _bits(_reference_lookup(tree, target, source)), (
                    target,
                    source,
                )
                assert tree.lookup(target, source) is got  # remembered until a change


def test_a_walk_to_the_root_skips_zero_transforms_bit_for_bit():
    """Zero transforms of either sign at the start of a walk (base_footprint -> base_link)
    are skipped: the lookups still give Pose2D's own bits."""
    zeros = [Pose2D(a, b, c) for a in (0.0, -0.0) for b in (0.0, -0.0) for c in (0.0, -0.0)]
    for zero in zeros:
        for odom in (Pose2D(1.0, -2.0, 0.5), Pose2D(-0.0, 0.0, -0.0), zero):
            tree = FrameTree.rep105()
            tree.set_transform("map", "odom", Pose2D(-0.0, 3.0, -0.0), stamp=1.0)
            tree.set_transform("odom", "base_footprint", odom, stamp=1.0)
            tree.set_static("base_link", "laser", zero)
            frames = ["map", "odom", "base_footprint", "base_link", "laser"]
            for target in frames:
                for source in frames:
                    got = tree.lookup(target, source)
                    want = _reference_lookup(tree, target, source)
                    assert _bits(got) == _bits(want), (zero, odom, target, source)
