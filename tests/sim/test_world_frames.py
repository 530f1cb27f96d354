"""The frames a world implies: what `btnav world frames` prints."""

from __future__ import annotations

import pytest

from btnav.core.errors import FrameError
from btnav.core.resources import bundled_dir
from btnav.sim.frames import world_frame_tree

OFFICE = bundled_dir("worlds") / "small_office.yaml"


def test_office_frames_are_rep105_plus_the_laser_at_its_mount():
    tree = world_frame_tree(OFFICE)
    assert set(tree.frames) == {"map", "odom", "base_footprint", "base_link", "laser"}
    laser_in_map = tree.lookup("map", "laser")
    assert (laser_in_map.x, laser_in_map.y, laser_in_map.yaw) == pytest.approx((1.1, 1.0, 0.0))
    assert tree.parent("laser") == "base_link"
    with pytest.raises(FrameError, match="frames: base_footprint, base_link, laser"):
        tree.require("lidar_link")
