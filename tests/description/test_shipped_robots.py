"""The robots btnav ships (robots/) read as their makers publish them."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from btnav.description import load_description

ROBOTS = Path(__file__).resolve().parents[2] / "robots"


def test_the_burger_has_its_published_footprint_wheels_and_lds_01():
    d = load_description(ROBOTS / "turtlebot3_burger.urdf.xacro")
    assert d.base_frame == "base_footprint"
    # base_link's 140 mm collision box, 32 mm behind the wheel axle
    assert d.footprint is not None and d.footprint.radius is None
    assert np.allclose(
        d.footprint.polygon,
        [(-0.102, -0.07), (0.038, -0.07), (0.038, 0.07), (-0.102, 0.07)],
        atol=1e-9,
    )
    assert d.drive is not None and d.drive.name == "diff_drive"
    assert d.drive.source == "libgazebo_ros_diff_drive.so"
    assert d.drive.wheel_separation == pytest.approx(0.160)
    assert d.drive.wheel_radius == pytest.approx(0.033)
    (lds,) = d.lidars
    assert lds.frame == "base_scan" and lds.link == "base_scan"
    assert (lds.beams, lds.range_min, lds.range_max, lds.rate) == (360, 0.12, 3.5, 5.0)
    assert lds.angle_max - lds.angle_min == pytest.approx(2 * math.pi)
    assert lds.noise_std == pytest.approx(0.01)
    # scan_joint: 32 mm behind base_link's origin, 172 mm above it, base_link 10 mm up
    assert lds.pose == pytest.approx((-0.032, 0.0, 0.0))
    assert lds.z == pytest.approx(0.182)
    assert d.frame("base_scan").parent == "base_link"


def test_the_waffle_drives_on_its_plugins_separation_not_its_joints():
    d = load_description(ROBOTS / "turtlebot3_waffle.urdf.xacro")
    assert d.footprint is not None
    assert np.allclose(
        d.footprint.polygon,
        [(-0.197, -0.133), (0.069, -0.133), (0.069, 0.133), (-0.197, 0.133)],
        atol=1e-9,
    )
    assert d.drive is not None and d.drive.name == "diff_drive"
    # the wheel joints sit at +/-0.144 m; the Gazebo plugin drives with 0.287 m
    assert d.drive.wheel_separation == pytest.approx(0.287)
    assert d.drive.wheel_radius == pytest.approx(0.033)
    (lds,) = d.lidars  # the R200 depth camera block is no lidar
    assert (lds.frame, lds.beams, lds.range_max, lds.rate) == ("base_scan", 360, 3.5, 5.0)
    assert lds.pose == pytest.approx((-0.064, 0.0, 0.0)) and lds.z == pytest.approx(0.132)
    assert {"camera_link", "camera_rgb_frame", "caster_back_left_link"} <= {
        f.name for f in d.frames
    }


def test_a_xacro_arg_drops_the_waffles_camera():
    d = load_description(ROBOTS / "turtlebot3_waffle.urdf.xacro", args={"camera": False})
    assert "camera_link" not in {f.name for f in d.frames}


def test_the_racecar_is_ackermann_through_find_btnav_robots():
    d = load_description(ROBOTS / "racecar.urdf.xacro")
    assert d.base_frame == "base_link"  # the rear axle's centre
    assert d.drive is not None and d.drive.name == "ackermann"
    assert d.drive.source == "gz-sim-ackermann-steering-system"
    assert d.drive.wheelbase == pytest.approx(0.325)
    assert d.drive.max_steering_angle == pytest.approx(0.34)
    assert d.drive.limits == {"v_max": 0.5, "v_min": -0.5, "a_max": 1.0}
    # the hinges come from racecar_macros.xacro, included through $(find btnav_robots)
    assert {"left_steering_hinge", "right_front_wheel"} <= {f.name for f in d.frames}
    (laser,) = d.lidars
    assert laser.frame == "laser" and laser.beams == 1081
    assert math.degrees(laser.angle_max - laser.angle_min) == pytest.approx(270.0)
    assert (laser.range_min, laser.range_max, laser.rate) == (0.06, 10.0, 40.0)
    assert laser.pose == pytest.approx((0.27, 0.0, 0.0))
    assert d.footprint is not None
    assert np.allclose(
        d.footprint.polygon, [(-0.12, -0.15), (0.45, -0.15), (0.45, 0.15), (-0.12, 0.15)], atol=1e-9
    )


def test_without_its_plugin_block_the_racecars_joints_give_the_same_car():
    d = load_description(ROBOTS / "racecar.urdf.xacro", args={"gz_plugins": "false"})
    assert d.drive is not None and d.drive.name == "ackermann"
    assert d.drive.source.startswith("joints left_steering_hinge_joint")
    assert d.drive.wheelbase == pytest.approx(0.325)
    assert d.drive.wheel_separation == pytest.approx(0.2)
    assert d.drive.wheel_radius == pytest.approx(0.05)
    assert d.drive.max_steering_angle == pytest.approx(0.34)  # the hinges' limit
    assert d.drive.max_steering_speed == pytest.approx(3.0)  # and their velocity
    assert d.drive.file is not None and d.drive.file.endswith("racecar_macros.xacro")


def test_the_fishbot_has_its_lidar_on_laser_link_above_a_disc_base():
    d = load_description(ROBOTS / "fishbot.urdf.xacro")
    assert d.footprint is not None and d.footprint.radius == pytest.approx(0.2)
    laser, base = d.frame("laser_link"), d.frame("base_link")
    assert laser.parent == "base_link"
    assert laser.z - base.z == pytest.approx(0.1)
    assert (laser.x, laser.y) == (0.0, 0.0)
    (lidar,) = d.lidars
    assert lidar.frame == "laser_link"
    assert (lidar.beams, lidar.range_min, lidar.range_max, lidar.rate) == (360, 0.1, 10.0, 10.0)
    assert (lidar.angle_min, lidar.angle_max) == pytest.approx((-math.pi, math.pi))
    assert d.drive is not None and d.drive.name == "diff_drive"
    assert d.drive.wheel_separation == pytest.approx(0.30)
    assert d.drive.wheel_radius == pytest.approx(0.05)


def test_the_links_join_btnav_s_frame_tree_where_the_joints_put_them():
    d = load_description(ROBOTS / "racecar.urdf.xacro")
    edges = {child: (parent, pose) for parent, child, pose in d.tf_edges()}
    assert "base_link" not in edges  # btnav's own
    parent, pose = edges["left_steering_hinge"]
    assert parent == "base_link" and pose == pytest.approx((0.325, 0.1, 0.0))
    parent, pose = edges["right_front_wheel"]  # under its hinge, where the hinge is
    assert parent == "right_steering_hinge" and pose == pytest.approx((0.0, 0.0, 0.0))
    burger = load_description(ROBOTS / "turtlebot3_burger.urdf.xacro")
    edges = {child: (parent, pose) for parent, child, pose in burger.tf_edges()}
    assert edges["wheel_left_link"] == ("base_link", pytest.approx((0.0, 0.08, 0.0)))
    assert "base_footprint" not in edges
