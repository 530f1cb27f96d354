"""A mission's `robot:` puts that robot in the mission's world, replacing the world's own."""

from __future__ import annotations

import warnings
from pathlib import Path

import pytest

from btnav.cli import main
from btnav.core.errors import BtnavError, BtnavWarning
from btnav.description import load_description
from btnav.mission import Mission, run_mission
from btnav.sim.world_sensors import make_sensors

REPO = Path(__file__).resolve().parents[2]
BURGER = REPO / "robots" / "turtlebot3_burger.urdf.xacro"


def write_mission(
    tmp_path: Path, robot: str, world: str = "worlds/small_office.yaml", **keys
) -> Path:
    extra = "".join(f"{k}: {v}\n" for k, v in keys.items())
    path = tmp_path / "mission.yaml"
    path.write_text(
        f"mission: m\nworld: {REPO / world}\nparams: {REPO / 'params' / 'nav2_params.yaml'}\n"
        f"map: {REPO / 'maps' / 'small_office.yaml'}\nlocalization: ground_truth\n"
        f"{robot}{extra}task:\n  navigate_to_pose: [3.0, 2.0, 1.57]\ntime_limit: 120\n"
    )
    return path


def relative_burger(tmp_path: Path) -> str:
    """The Burger's xacro as the mission file would name it (relative to it)."""
    import os

    return os.path.relpath(BURGER, tmp_path)


def test_a_burger_from_its_xacro_replaces_the_office_s_robot(tmp_path):
    mission = Mission.load(write_mission(tmp_path, f"robot: {relative_burger(tmp_path)}\n"))
    robot, desc = mission.world.robot, load_description(BURGER)
    assert robot.footprint.polygon == [tuple(p) for p in desc.footprint.polygon]
    (lidar,) = robot.sensors
    assert lidar["lidar"]["frame"] == "base_scan" and lidar["lidar"]["range"] == [0.12, 3.5]
    assert robot.pose == (1.0, 1.0, 0.0)  # where the office starts its robot
    assert mission.world.obstacles and mission.world.world == "small_office"  # the scene stays
    world = mission.build_world()
    (sensor,) = make_sensors(world)
    assert sensor.frame_id == "base_scan" and sensor.params.range == (0.12, 3.5)
    assert "base_scan" in mission.frame_tree(world).frames


def test_a_robot_block_keeps_its_own_keys_over_the_description_and_starts_at_initial_pose(
    tmp_path,
):
    block = f"robot:\n  description: {relative_burger(tmp_path)}\n  footprint: {{radius: 0.12}}\n"
    mission = Mission.load(write_mission(tmp_path, block, initial_pose="[2.0, 6.0, 0.5]"))
    robot = mission.world.robot
    assert robot.footprint.radius == 0.12 and robot.pose == (2.0, 6.0, 0.5)
    assert robot.sensors[0]["lidar"]["frame"] == "base_scan"


def test_a_mistake_in_the_mission_s_robot_names_the_mission_file(tmp_path, capsys):
    path = write_mission(tmp_path, "robot:\n  footprnt: {radius: 0.2}\n")
    with pytest.raises(BtnavError) as info:
        Mission.load(path)
    err = info.value
    assert (err.file, err.line, err.suggestion) == (str(path), 7, "footprint")
    path = write_mission(tmp_path, "robot:\n  sensors:\n    - lidar: {frame: laser, beams: -3}\n")
    assert main(["run", str(path), "--out", str(tmp_path / "out")]) == 2
    assert f"{path}:8: robot.sensors[0].lidar.beams" in capsys.readouterr().err
    path = write_mission(tmp_path, "robot:\n  footprint: {radius: 1.5}\n")  # overlaps a wall
    with pytest.raises(BtnavError) as info:
        Mission.load(path).build_world()
    assert info.value.file == str(path) and "overlaps" in info.value.message


def test_a_gazebo_world_takes_the_mission_s_robot_and_else_btnav_s_default_with_a_warning(
    tmp_path,
):
    world = "worlds/sdf/cafe.world"
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        given = Mission.load(
            write_mission(tmp_path, f"robot: {relative_burger(tmp_path)}\n", world=world)
        )
    assert not [w for w in caught if issubclass(w.category, BtnavWarning)]
    assert given.world.robot.sensors[0]["lidar"]["frame"] == "base_scan"
    with pytest.warns(BtnavWarning, match="btnav's default robot stands in"):
        default = Mission.load(write_mission(tmp_path, "", world=world, initial_pose="[-4, 0, 0]"))
    assert default.world.robot.footprint.radius == 0.22
    assert default.world.robot.pose == (-4.0, 0.0, 0.0)


@pytest.mark.slow
def test_the_burger_drives_the_office_with_nav2_s_params(tmp_path):
    mission = Mission.load(write_mission(tmp_path, f"robot: {relative_burger(tmp_path)}\n"))
    report = run_mission(mission)
    assert report.status == "succeeded" and report.collisions == 0, report.summary()
