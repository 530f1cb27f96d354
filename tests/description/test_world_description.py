"""A world's `robot: {description: FILE}`: the robot btnav builds from a URDF or xacro.

The description gives the footprint, the drive and its parameters, the lidars and the
drive plugin's limits; a key the world writes wins over it.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml

from btnav.cli import main
from btnav.core.error_codes import Outcome
from btnav.core.errors import BtnavError, BtnavWarning, WorldError
from btnav.core.messages import LaserScan
from btnav.mission import Mission
from btnav.sim.frames import world_frame_tree
from btnav.sim.world import World
from btnav.sim.world_sensors import make_sensors

from ..mission.missions import WORLD, write_mission

REPO = Path(__file__).resolve().parents[2]


def office_world(folder: Path, robot: dict[str, Any], name: str = "world.yaml") -> Path:
    """The small office with this robot, in folder/worlds/ beside a link to robots/."""
    (folder / "worlds").mkdir(exist_ok=True)
    if not (folder / "robots").exists():
        (folder / "robots").symlink_to(REPO / "robots")
    doc = yaml.safe_load(WORLD.read_text())
    doc["robot"] = robot
    path = folder / "worlds" / name
    path.write_text(yaml.safe_dump(doc, sort_keys=False))
    return path


BURGER = "../robots/turtlebot3_burger.urdf.xacro"


def line_of(path: Path, text: str) -> int:
    return next(i for i, line in enumerate(path.read_text().splitlines(), 1) if text in line)


def test_the_burger_world_takes_footprint_drive_and_lidar_from_the_xacro(tmp_path):
    world = World.from_file(office_world(tmp_path, {"description": BURGER, "pose": [1, 1, 0]}))
    robot = world.spec.robot
    assert robot.description.name == "turtlebot3_burger"
    assert robot.footprint.polygon == [
        (-0.102, -0.07),
        (0.038, -0.07),
        (0.038, 0.07),
        (-0.102, 0.07),
    ]
    assert robot.drive == "diff_drive"
    assert robot.limits.a_max == 1.0  # the diff-drive plugin's max_wheel_acceleration
    ((name, params, _),) = world.sensor_specs()
    assert name == "lidar" and params["frame"] == "base_scan"
    assert params["beams"] == 360 and params["range"] == [0.12, 3.5] and params["rate"] == 5.0
    tree = world_frame_tree(world)
    mount = tree.lookup("base_link", "base_scan")
    assert (mount.x, mount.y, mount.yaw) == pytest.approx((-0.032, 0.0, 0.0))


def test_keys_the_world_writes_win_over_the_description(tmp_path):
    robot = {
        "description": BURGER,
        "pose": [1, 1, 0],
        "footprint": {"radius": 0.105},  # Nav2's robot_radius for the Burger
        "limits": {"v_max": 0.22, "w_max": 2.84},
        "sensors": [{"lidar": {"frame": "laser", "beams": 90, "range": [0.1, 6.0]}}],
    }
    spec = World.from_file(office_world(tmp_path, robot)).spec.robot
    assert spec.footprint.radius == 0.105 and spec.footprint.polygon is None
    assert (spec.limits.v_max, spec.limits.w_max, spec.limits.a_max) == (0.22, 2.84, 1.0)
    assert [next(iter(s.values()))["frame"] for s in spec.sensors] == ["laser"]


def test_the_racecar_s_ackermann_params_fill_what_the_world_leaves_out(tmp_path):
    robot = {
        "description": "../robots/racecar.urdf.xacro",
        "pose": [2, 2, 0],
        "drive": {"ackermann": {"max_steering_angle": 0.3}},
        "limits": {"v_max": 0.4},
    }
    world = World.from_file(office_world(tmp_path, robot))
    drive = world.robot.drive
    assert drive.params.wheelbase == pytest.approx(0.325)  # from the description
    assert drive.params.max_steering_angle == pytest.approx(0.3)  # the world's
    assert drive.params.max_steering_speed == pytest.approx(3.0)  # the hinge joints'
    limits = world.spec.robot.limits
    assert (limits.v_max, limits.v_min, limits.a_max) == (0.4, -0.5, 1.0)
    ((_, params, _),) = world.sensor_specs()
    assert params["beams"] == 1081
    assert math.degrees(params["angle_max"] - params["angle_min"]) == pytest.approx(270)


def test_a_world_naming_another_drive_keeps_its_own(tmp_path):
    robot = {"description": BURGER, "pose": [1, 1, 0], "drive": "omni"}
    assert World.from_file(office_world(tmp_path, robot)).spec.robot.drive == "omni"


def test_a_description_without_collision_geometry_warns_and_keeps_the_default_disc(tmp_path):
    bare = tmp_path / "bare.urdf"
    bare.write_text('<robot name="bare">\n  <link name="base_link"/>\n</robot>\n')
    robot = {"description": str(bare), "pose": [1, 1, 0], "sensors": []}
    path = office_world(tmp_path, robot)
    with pytest.warns(BtnavWarning, match="no collision geometry") as caught:
        spec = World.from_file(path).spec.robot
    assert spec.footprint.radius == 0.22
    (warning,) = [w.message for w in caught if "collision" in str(w.message)]
    assert warning.file == str(path) and warning.line == line_of(path, "description:")


def test_a_missing_description_is_the_world_s_error_at_its_line(tmp_path):
    path = office_world(tmp_path, {"description": "../robots/nobot.urdf", "pose": [1, 1, 0]})
    with pytest.raises(WorldError) as info:
        World.from_file(path)
    err = info.value
    assert err.file == str(path) and err.key == "robot.description"
    assert err.line == line_of(path, "description:")
    assert "robot description not found" in err.message


def _robot_in_a_package(folder: Path) -> dict[str, Any]:
    """A xacro that includes `$(find my_robot)/body.xacro`, the package in folder/pkgs."""
    (folder / "pkgs" / "my_robot").mkdir(parents=True)
    (folder / "pkgs" / "my_robot" / "body.xacro").write_text(
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro"><link name="base_link">'
        '<collision><geometry><cylinder radius="0.17" length="0.1"/></geometry></collision>'
        "</link></robot>"
    )
    (folder / "robot.urdf.xacro").write_text(
        '<robot name="mine" xmlns:xacro="http://www.ros.org/wiki/xacro">'
        '<xacro:include filename="$(find my_robot)/body.xacro"/></robot>'
    )
    return {"description": "../robot.urdf.xacro", "pose": [1, 1, 0], "sensors": []}


def test_package_paths_in_the_world_resolve_from_its_folder(tmp_path):
    robot = {**_robot_in_a_package(tmp_path), "package_paths": {"my_robot": "../pkgs/my_robot"}}
    assert World.from_file(office_world(tmp_path, robot)).spec.robot.footprint.radius == 0.17


def test_a_broken_description_in_a_world_names_the_description_s_line(tmp_path):
    bad = tmp_path / "bad.urdf.xacro"
    bad.write_text(
        '<robot name="b" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <link name="base_link"/>\n  <xacro:wheel/>\n</robot>\n'
    )
    with pytest.raises(BtnavError) as info:
        World.from_file(office_world(tmp_path, {"description": str(bad), "pose": [1, 1, 0]}))
    assert (info.value.file, info.value.line) == (str(bad), 3)


def test_btnav_world_frames_lists_the_description_s_scan_frame(tmp_path, capsys):
    path = office_world(tmp_path, {"description": BURGER, "pose": [1, 1, 0]})
    assert main(["world", "frames", str(path)]) == 0
    assert "base_scan  [-0.032, 0.000, 0.000] (static)" in capsys.readouterr().out


def test_a_mission_drives_the_burger_with_its_lds_01(tmp_path):
    world = office_world(tmp_path, {"description": BURGER, "pose": [1, 1, 0]})
    mission = write_mission(tmp_path, world=str(world), task={"navigate_to_pose": [2.5, 1.0, 0.0]})
    nav = Mission.load(mission).navigator()
    scans: list[LaserScan] = []
    nav.runtime.subscribe("scan", scans.append)
    assert nav.go_to_pose([2.5, 1.0, 0.0])
    result = nav.wait_until_done(60.0)
    assert result is not None and result.outcome == Outcome.SUCCEEDED, result
    pose = nav.runtime.world.robot_pose
    assert math.hypot(pose.x - 2.5, pose.y - 1.0) < 0.3
    assert scans and {s.frame_id for s in scans} == {"base_scan"}
    assert {len(s.ranges) for s in scans} == {360}
    assert all(s.range_max == pytest.approx(3.5) for s in scans)
    # the LDS-01's 5 Hz: a scan every 0.2 s of sim time
    assert np.allclose(np.diff([s.stamp for s in scans]), 0.2)


LIDAR_ONLY = """<?xml version="1.0"?>
<robot name="r">
  <link name="base_link">
    <collision><geometry><cylinder radius="0.15" length="0.1"/></geometry></collision>
  </link>
  <joint name="scan_joint" type="fixed">
    <parent link="base_link"/><child link="scan"/><origin xyz="0.05 0 0.2"/>
  </joint>
  <link name="scan"/>
  <gazebo reference="scan">
    <sensor type="ray" name="lds">
      <update_rate>5</update_rate>
      <ray>
        <scan><horizontal><samples>360</samples><resolution>1</resolution>
          <min_angle>0.0</min_angle><max_angle>6.28319</max_angle></horizontal></scan>
        <range><min>0.12</min><max>3.5</max></range>
      </ray>
    </sensor>
  </gazebo>
</robot>
"""


def test_a_full_turn_written_as_6_28319_builds_a_360_degree_lidar(tmp_path):
    urdf = tmp_path / "r.urdf"
    urdf.write_text(LIDAR_ONLY)
    world = World.from_file(office_world(tmp_path, {"description": str(urdf), "pose": [1, 1, 0]}))
    (lidar,) = make_sensors(world)
    assert len(lidar.angles) == 360 and lidar.frame_id == "scan"
    assert lidar.angle_increment == pytest.approx(math.radians(1.0))
    assert (lidar.mount.x, lidar.mount.y) == pytest.approx((0.05, 0.0))


def test_a_description_without_a_lidar_says_the_robot_has_none(tmp_path):
    urdf = tmp_path / "r.urdf"
    urdf.write_text(
        LIDAR_ONLY.replace("<sensor", "<!--<sensor").replace("</sensor>", "</sensor>-->")
    )
    path = office_world(tmp_path, {"description": str(urdf), "pose": [1, 1, 0]})
    with pytest.warns(BtnavWarning, match="has no 2D lidar"):
        world = World.from_file(path)
    assert world.sensor_specs() == []


def test_package_on_the_command_line_resolves_a_world_robots_find(tmp_path, capsys):
    world = office_world(tmp_path, _robot_in_a_package(tmp_path))
    mission = write_mission(
        tmp_path, world=str(world), task={"navigate_to_pose": [2.0, 1.0, 0.0]}, time_limit=1.0
    )
    # without it: one error that names the option to give
    assert main(["frames", str(mission)]) == 2
    assert "--package my_robot=DIR" in capsys.readouterr().err
    package = f"my_robot={tmp_path / 'pkgs' / 'my_robot'}"
    assert main(["frames", str(mission), "--package", package]) == 0
    assert "base_link" in capsys.readouterr().out
    assert main(["run", str(mission), "--package", package, "-o", str(tmp_path / "out")]) in (0, 1)
    assert "robot description" not in capsys.readouterr().err


def test_a_package_folder_that_is_not_there_is_the_option_s_error(tmp_path, capsys):
    mission = write_mission(tmp_path, task={"navigate_to_pose": [2.0, 1.0, 0.0]}, time_limit=1.0)
    assert main(["run", str(mission), "--package", f"my_robot={tmp_path / 'nope'}"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("btnav: error: --package") and "is not a folder" in err
