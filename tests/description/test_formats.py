"""Descriptions as users have them: plain URDF, Gazebo SDF models, packages found without ROS."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from btnav.description import load_description

WHEEL = """
  <joint name="{side}_wheel_joint" type="continuous">
    <parent link="base_link"/><child link="{side}_wheel"/>
    <origin xyz="0.05 {y} 0.03" rpy="-1.5708 0 0"/><axis xyz="0 0 1"/>
  </joint>
  <link name="{side}_wheel">
    <collision><geometry><cylinder radius="0.04" length="0.02"/></geometry></collision>
  </link>
"""

URDF = f"""<?xml version="1.0"?>
<robot name="plain">
  <link name="base_link">
    <collision>
      <origin xyz="0 0 0.05" rpy="0 0 0.7853981633974483"/>
      <geometry><box size="0.2 0.2 0.1"/></geometry>
    </collision>
  </link>
  {WHEEL.format(side="left", y=0.11)}
  {WHEEL.format(side="right", y=-0.11)}
  <joint name="laser_joint" type="fixed">
    <parent link="base_link"/><child link="laser"/>
    <origin xyz="0.1 0 0.2" rpy="0 0 1.5707963267948966"/>
  </joint>
  <link name="laser"/>
  <gazebo reference="laser">
    <sensor type="gpu_ray" name="front">
      <pose>0.02 0 0.01 0 0 0</pose>
      <update_rate>12</update_rate>
      <ray>
        <scan><horizontal><samples>180</samples><resolution>2</resolution>
          <min_angle>-1.5</min_angle><max_angle>1.5</max_angle></horizontal></scan>
        <range><min>0.2</min><max>12</max></range>
      </ray>
    </sensor>
  </gazebo>
</robot>
"""


def test_a_plain_urdf_gives_a_diff_drive_from_its_wheel_joints(tmp_path):
    path = tmp_path / "plain.urdf"
    path.write_text(URDF)
    d = load_description(path)
    assert d.kind == "urdf" and d.base_frame == "base_link"
    assert d.drive is not None and d.drive.name == "diff_drive"
    assert d.drive.source == "joints left_wheel_joint, right_wheel_joint"
    assert d.drive.wheel_separation == pytest.approx(0.22)
    assert d.drive.wheel_radius == pytest.approx(0.04)
    # a 0.2 m box turned 45 degrees: a diamond reaching 0.1 * sqrt(2) on each axis
    assert d.footprint is not None
    r = 0.1 * math.sqrt(2)
    assert np.allclose(
        sorted(d.footprint.polygon), sorted([(-r, 0), (0, -r), (r, 0), (0, r)]), atol=1e-6
    )
    (lidar,) = d.lidars
    # the sensor's own <pose> composed after the joint: 0.02 along the laser's x (= base y)
    assert lidar.pose == pytest.approx((0.1, 0.02, math.pi / 2))
    assert lidar.z == pytest.approx(0.21)
    assert lidar.frame == "laser" and lidar.beams == 360  # samples x resolution
    assert (lidar.range_min, lidar.range_max, lidar.rate, lidar.noise_std) == (0.2, 12.0, 12.0, 0.0)


SDF = """<?xml version="1.0"?>
<sdf version="1.8">
  <model name="sdfbot">
    <link name="base_footprint"/>
    <link name="base_link">
      <pose>0 0 0.02 0 0 0</pose>
      <collision name="body">
        <pose>-0.05 0 0.05 0 0 0</pose>
        <geometry><box><size>0.3 0.2 0.1</size></box></geometry>
      </collision>
    </link>
    <link name="scan_link">
      <pose relative_to="base_link">0.1 0 0.15 0 0 0</pose>
      <sensor name="lidar" type="gpu_lidar">
        <pose>0 0 0.01 0 0 0</pose>
        <update_rate>8</update_rate>
        <gz_frame_id>scan</gz_frame_id>
        <lidar>
          <scan><horizontal><samples>720</samples><resolution>1</resolution>
            <min_angle>-3.14159</min_angle><max_angle>3.14159</max_angle></horizontal></scan>
          <range><min>0.15</min><max>6.0</max></range>
          <noise><type>gaussian</type><mean>0</mean><stddev>0.02</stddev></noise>
        </lidar>
      </sensor>
    </link>
    <joint name="base_joint" type="fixed"><parent>base_footprint</parent><child>base_link</child></joint>
    <joint name="scan_joint" type="fixed"><parent>base_link</parent><child>scan_link</child></joint>
    <plugin filename="gz-sim-diff-drive-system" name="gz::sim::systems::DiffDrive">
      <wheel_separation>0.25</wheel_separation>
      <wheel_radius>0.04</wheel_radius>
      <max_linear_velocity>0.4</max_linear_velocity>
      <max_angular_velocity>2.0</max_angular_velocity>
    </plugin>
  </model>
</sdf>
"""


def test_a_gazebo_model_folder_reads_its_model_sdf(tmp_path):
    folder = tmp_path / "sdfbot"
    folder.mkdir()
    (folder / "model.sdf").write_text(SDF)
    d = load_description(folder)
    assert d.kind == "sdf" and d.name == "sdfbot" and d.base_frame == "base_footprint"
    assert d.footprint is not None
    assert np.allclose(
        d.footprint.polygon, [(-0.2, -0.1), (0.1, -0.1), (0.1, 0.1), (-0.2, 0.1)], atol=1e-9
    )
    assert d.drive is not None and d.drive.source == "gz-sim-diff-drive-system"
    assert (d.drive.wheel_separation, d.drive.wheel_radius) == (0.25, 0.04)
    assert d.drive.limits == {"v_max": 0.4, "w_max": 2.0}
    (lidar,) = d.lidars
    assert lidar.frame == "scan" and lidar.beams == 720 and lidar.noise_std == 0.02
    assert lidar.pose == pytest.approx((0.1, 0.0, 0.0))
    assert lidar.z == pytest.approx(0.02 + 0.15 + 0.01)  # relative_to base_link, then the sensor's


def test_an_sdf_world_is_not_a_robot(tmp_path):
    path = tmp_path / "w.sdf"
    path.write_text('<sdf version="1.8">\n<world name="w"/>\n</sdf>\n')
    with pytest.raises(Exception, match="is a Gazebo world"):
        load_description(path)


PARTS = """<?xml version="1.0"?>
<robot xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:macro name="body" params="size">
    <link name="base_link">
      <collision><geometry><cylinder radius="${size}" length="0.1"/></geometry></collision>
    </link>
  </xacro:macro>
</robot>
"""
MAIN = """<?xml version="1.0"?>
<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:include filename="$(find my_parts)/urdf/parts.xacro"/>
  <xacro:body size="0.3"/>
</robot>
"""


def _package(root: Path, name: str) -> Path:
    pkg = root / name
    (pkg / "urdf").mkdir(parents=True)
    (pkg / "urdf" / "parts.xacro").write_text(PARTS)
    (pkg / "package.xml").write_text(f"<package><name>{name}</name></package>")
    return pkg


def test_find_resolves_through_package_paths_given(tmp_path, monkeypatch):
    monkeypatch.delenv("AMENT_PREFIX_PATH", raising=False)
    monkeypatch.delenv("ROS_PACKAGE_PATH", raising=False)
    pkg = _package(tmp_path / "elsewhere", "my_parts")
    main = tmp_path / "robot.urdf.xacro"
    main.write_text(MAIN)
    with pytest.raises(Exception, match="package 'my_parts' not found"):
        load_description(main)
    d = load_description(main, {"my_parts": pkg})
    assert d.footprint is not None and d.footprint.radius == pytest.approx(0.3)


def test_find_resolves_through_ros_package_path_and_ament_prefix_path(tmp_path, monkeypatch):
    main = tmp_path / "robot.urdf.xacro"
    main.write_text(MAIN)
    monkeypatch.delenv("AMENT_PREFIX_PATH", raising=False)
    monkeypatch.setenv("ROS_PACKAGE_PATH", str(tmp_path / "ws" / "src"))
    _package(tmp_path / "ws" / "src", "my_parts")
    assert load_description(main).footprint.radius == pytest.approx(0.3)  # type: ignore[union-attr]
    monkeypatch.delenv("ROS_PACKAGE_PATH")
    monkeypatch.setenv("AMENT_PREFIX_PATH", str(tmp_path / "install"))
    _package(tmp_path / "install" / "share", "my_parts")
    assert load_description(main).footprint.radius == pytest.approx(0.3)  # type: ignore[union-attr]


def test_find_resolves_the_package_the_description_sits_in(tmp_path, monkeypatch):
    monkeypatch.delenv("AMENT_PREFIX_PATH", raising=False)
    monkeypatch.delenv("ROS_PACKAGE_PATH", raising=False)
    pkg = _package(tmp_path, "my_parts")
    main = pkg / "urdf" / "robot.urdf.xacro"
    main.write_text(MAIN)
    assert load_description(main).footprint.radius == pytest.approx(0.3)  # type: ignore[union-attr]


def test_a_relative_include_is_found_beside_the_file_from_any_folder(tmp_path, monkeypatch):
    (tmp_path / "robot").mkdir()
    (tmp_path / "robot" / "parts.xacro").write_text(PARTS)
    main = tmp_path / "robot" / "r.urdf.xacro"
    main.write_text(MAIN.replace("$(find my_parts)/urdf/parts.xacro", "parts.xacro"))
    monkeypatch.chdir(tmp_path)
    d = load_description(Path("robot") / "r.urdf.xacro")
    assert d.footprint is not None and d.footprint.radius == pytest.approx(0.3)
