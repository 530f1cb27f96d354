"""`btnav robot show FILE [--package N=DIR] [--arg N=V] [--json]`: what btnav read, printed."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from btnav.cli import main

ROBOTS = Path(__file__).resolve().parents[2] / "robots"
KEYS = {"drive", "footprint", "wheel_separation", "wheel_radius", "wheelbase", "sensors"}
SENSOR_KEYS = {
    "frame",
    "pose",
    "beams",
    "angle_min",
    "angle_max",
    "range_min",
    "range_max",
    "rate",
    "noise_std",
}


def show_json(capsys: pytest.CaptureFixture[str], *args: str) -> dict:
    assert main(["robot", "show", *args, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_json_of_the_burger(capsys):
    out = show_json(capsys, str(ROBOTS / "turtlebot3_burger.urdf.xacro"))
    assert set(out) >= KEYS
    assert out["drive"] == "diff_drive"
    assert out["footprint"] == {
        "polygon": [[-0.102, -0.07], [0.038, -0.07], [0.038, 0.07], [-0.102, 0.07]]
    }
    assert (out["wheel_separation"], out["wheel_radius"], out["wheelbase"]) == (0.16, 0.033, None)
    (lidar,) = out["sensors"]
    assert set(lidar) >= SENSOR_KEYS
    assert lidar["frame"] == "base_scan" and lidar["pose"] == [-0.032, 0.0, 0.0]
    assert (lidar["beams"], lidar["range_min"], lidar["range_max"]) == (360, 0.12, 3.5)
    assert (lidar["rate"], lidar["noise_std"]) == (5.0, 0.01)
    assert lidar["angle_max"] - lidar["angle_min"] == pytest.approx(2 * math.pi)


def test_json_of_the_racecar_has_its_wheelbase(capsys):
    out = show_json(capsys, str(ROBOTS / "racecar.urdf.xacro"), "--arg", "gz_plugins=false")
    assert out["drive"] == "ackermann" and out["wheelbase"] == pytest.approx(0.325)
    assert out["sensors"][0]["beams"] == 1081


def test_text_of_the_fishbot(capsys):
    assert main(["robot", "show", str(ROBOTS / "fishbot.urdf.xacro")]) == 0
    text = capsys.readouterr().out
    assert "drive: diff_drive, from libgazebo_ros_diff_drive.so" in text
    assert "wheel separation 0.3 m, wheel radius 0.05 m" in text
    assert "footprint: radius 0.2 m (base_link's cylinder" in text
    assert "lidar 'laser' in frame laser_link" in text
    assert "360 beams from -3.14159 to 3.14159 rad; range 0.1-10 m; 10 Hz" in text
    assert "      laser_link  [0, 0, 0.2] yaw 0" in text  # under base_link, under base_footprint


def test_package_names_a_folder_for_find(tmp_path, capsys):
    (tmp_path / "parts").mkdir()
    (tmp_path / "parts" / "body.xacro").write_text(
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro"><link name="base_link">'
        '<collision><geometry><box size="0.4 0.2 0.1"/></geometry></collision></link></robot>'
    )
    main_file = tmp_path / "r.urdf.xacro"
    main_file.write_text(
        '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">'
        '<xacro:include filename="$(find my_parts)/body.xacro"/></robot>'
    )
    assert main(["robot", "show", str(main_file)]) == 2
    assert "package 'my_parts' not found" in capsys.readouterr().err
    out = show_json(capsys, str(main_file), "--package", f"my_parts={tmp_path / 'parts'}")
    assert out["footprint"] == {"polygon": [[-0.2, -0.1], [0.2, -0.1], [0.2, 0.1], [-0.2, 0.1]]}


def test_a_malformed_option_is_a_user_error(capsys):
    assert main(["robot", "show", str(ROBOTS / "fishbot.urdf.xacro"), "--package", "x"]) == 2
    assert capsys.readouterr().err.strip() == "btnav: error: --package x: expected NAME=DIR"
