"""Nav2's pose filter over detections, and the 3D rotation the dock plugin undoes."""

from __future__ import annotations

import math

import pytest

from btnav.core.nav2_docking_msgs import PoseStamped3D
from btnav.core.quaternion import from_rpy, from_yaw, multiply, yaw_of
from btnav.docking.pose_filter import PoseFilter
from btnav.sim.dock_detector import TAG_AXES


def pose(t, x, yaw=0.0, frame="odom"):
    return PoseStamped3D(t, frame, (x, 0.0, 0.0), from_yaw(yaw))


def test_each_detection_moves_the_estimate_filter_coef_of_the_way():
    f = PoseFilter(0.1, timeout=1.0)
    assert f.update(pose(0.0, 1.0)).position[0] == 1.0  # the first one is taken as it is
    assert f.update(pose(0.1, 2.0, yaw=1.0)).position[0] == pytest.approx(1.1)
    assert yaw_of(f.pose.orientation) == pytest.approx(0.1)  # slerp by the same fraction


def test_a_stale_estimate_or_another_frame_restarts_the_filter():
    f = PoseFilter(0.1, timeout=1.0)
    f.update(pose(0.0, 1.0))
    assert f.update(pose(1.5, 3.0)).position[0] == 3.0
    assert f.update(pose(1.6, 5.0, frame="map")).position[0] == 5.0
    assert PoseFilter(0.0, 1.0).update(pose(2.0, 7.0)).position[0] == 7.0  # coef 0: no filter


@pytest.mark.parametrize("dock_yaw", [0.0, 0.7, -2.5, 3.0])
def test_nav2s_detection_rotation_turns_an_apriltag_back_into_the_dock_yaw(dock_yaw):
    """nav2_params.yaml's external_detection_rotation (roll -1.57, pitch -1.57, yaw 0) on
    the marker's apriltag axes (x right, y down, z into the tag) gives the dock's yaw."""
    tag = multiply(from_yaw(dock_yaw), TAG_AXES)
    turned = yaw_of(multiply(tag, from_rpy(-1.57, -1.57, 0.0)))
    assert math.cos(turned - dock_yaw) == pytest.approx(1.0, abs=1e-5)
