"""`odometry:` in a mission: the world's robot odometry, replaced key by key (laser odometry).

A robot whose wheels the world makes useless still drives its mission when the mission
selects `odometry: {source: laser}`: odom -> base_footprint comes from the scans.
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np
import pytest
import yaml

from btnav.core.errors import BtnavError
from btnav.mission import Mission, run_mission

from .missions import WORLD, read_report, write_mission


def bad_wheels(folder: Path, *, lidar: bool = True) -> Path:
    """The small office with wheel odometry off by metres within a few metres of travel."""
    doc = yaml.safe_load(WORLD.read_text())
    doc["robot"]["odometry"] = {"noise": [2.0, 2.0, 2.0, 2.0], "rate": 50}
    if not lidar:
        doc["robot"]["sensors"] = []
    out = folder / "bad_wheels.yaml"
    out.write_text(yaml.safe_dump(doc, sort_keys=False))
    return out


def odom_errors(trajectory: Path) -> np.ndarray:
    """Each row's odom pose against the truth moved into the odom frame (the start's)."""
    with open(trajectory) as f:
        rows = [{k: float(v) for k, v in r.items()} for r in csv.DictReader(f)]
    x0, y0, yaw0 = rows[0]["gt_x"], rows[0]["gt_y"], rows[0]["gt_yaw"]
    c, s = math.cos(yaw0), math.sin(yaw0)
    out = []
    for r in rows:
        dx, dy = r["gt_x"] - x0, r["gt_y"] - y0
        tx, ty = c * dx + s * dy, -s * dx + c * dy
        out.append(math.hypot(r["odom_x"] - tx, r["odom_y"] - ty))
    return np.array(out)


def test_laser_odometry_chosen_by_the_mission_drives_the_odom_frame(tmp_path: Path) -> None:
    path = write_mission(
        tmp_path,
        world=str(bad_wheels(tmp_path)),
        initial_pose=[1.0, 1.0, 0.0],
        odometry={"source": "laser"},
        task={"navigate_to_pose": [3.0, 1.0, 0.0]},
        time_limit=40,
        outputs=["report", "trajectory"],
    )
    out = tmp_path / "out"
    report = run_mission(Mission.load(path), out)
    assert report.status == "succeeded", report.error_msg
    errors = odom_errors(out / "trajectory.csv")
    travelled = read_report(out)["path_length"]
    assert travelled > 1.5
    # wheels this noisy would be off by about a metre per metre (variance 2 per metre)
    assert errors.max() < 0.05, f"odom {errors.max():.3f} m from the truth"


def test_the_mission_keeps_the_world_s_other_odometry_keys(tmp_path: Path) -> None:
    path = write_mission(
        tmp_path,
        world=str(bad_wheels(tmp_path)),
        odometry={"source": "laser"},
        task={"navigate_to_pose": [3.0, 1.0, 0.0]},
    )
    odometry = Mission.load(path).world.robot.odometry
    assert odometry.source == "laser"
    assert odometry.noise == (2.0, 2.0, 2.0, 2.0) and odometry.rate == 50


def test_a_misspelt_source_names_the_mission_line_and_laser(tmp_path: Path) -> None:
    path = write_mission(
        tmp_path, odometry={"source": "lazer"}, task={"navigate_to_pose": [3.0, 1.0, 0.0]}
    )
    line = next(n for n, t in enumerate(path.read_text().splitlines(), 1) if "lazer" in t)
    with pytest.raises(BtnavError) as err:
        Mission.load(path)
    assert err.value.file == str(path) and err.value.line == line
    assert err.value.key == "odometry.source" and "did you mean 'laser'" in str(err.value)


def test_laser_odometry_without_a_lidar_blames_the_mission(tmp_path: Path) -> None:
    path = write_mission(
        tmp_path,
        world=str(bad_wheels(tmp_path, lidar=False)),
        odometry={"source": "laser"},
        task={"navigate_to_pose": [3.0, 1.0, 0.0]},
    )
    line = next(n for n, t in enumerate(path.read_text().splitlines(), 1) if "source" in t)
    with pytest.raises(BtnavError, match="needs a lidar") as err:
        Mission.load(path).navigator()
    assert err.value.file == str(path) and err.value.line == line
    assert err.value.key == "odometry.source"


RACECAR_MISSION = Path(__file__).resolve().parents[2] / "missions" / "racecar_parking.yaml"
RACECAR_WORLD = RACECAR_MISSION.parents[1] / "worlds" / "racecar_street.yaml"


@pytest.mark.parametrize("drive", ["ackermann", "omni", "diff_drive"])
def test_laser_odometry_follows_every_drive(tmp_path: Path, drive: str) -> None:
    """rf2o-style laser odometry needs nothing of the wheels: a car, an omni base and a
    diff drive with useless wheel odometry all keep odom on the truth."""
    world = yaml.safe_load(RACECAR_WORLD.read_text())
    robot = world["robot"]
    robot["description"] = str((RACECAR_WORLD.parent / robot["description"]).resolve())
    if drive != "ackermann":
        world["robot"]["drive"] = drive
    world["robot"]["odometry"] = {"noise": [2.0, 2.0, 2.0, 2.0], "rate": 50}
    (tmp_path / "world.yaml").write_text(yaml.safe_dump(world, sort_keys=False))
    doc = yaml.safe_load(RACECAR_MISSION.read_text())
    path = write_mission(
        tmp_path,
        world=str(tmp_path / "world.yaml"),
        params=str((RACECAR_MISSION.parent / doc["params"]).resolve()),
        map=str((RACECAR_MISSION.parent / doc["map"]).resolve()),
        odometry={"source": "laser"},
        task={"navigate_to_pose": [6.5, 1.8, 0.0]},
        time_limit=40,
        outputs=["report", "trajectory"],
    )
    out = tmp_path / "out"
    report = run_mission(Mission.load(path), out)
    assert report.status == "succeeded", report.error_msg
    assert read_report(out)["path_length"] > 3.0
    errors = odom_errors(out / "trajectory.csv")
    assert errors.max() < 0.05, f"odom {errors.max():.3f} m from the truth"
