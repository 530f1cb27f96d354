"""The racecar turns round in a dead-end street: Hybrid-A* with Reeds-Shepp plans the
manoeuvre, RPP drives its legs forwards and backwards, and ground truth judges it."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import yaml

from btnav.mission import Mission
from btnav.mission.runner import run_mission

REPO = Path(__file__).resolve().parents[2]
MISSION = REPO / "missions" / "racecar_parking.yaml"
WORLD = REPO / "worlds" / "racecar_street.yaml"
#: wheelbase / tan(max_steering_angle) of the world's ackermann drive
R_MIN = 0.325 / math.tan(0.34)
XY_TOL, YAW_TOL = 0.25, 0.25  # the params file's general_goal_checker


def run(tmp_path: Path, start: tuple[float, float, float] | None = None) -> tuple[str, np.ndarray]:
    doc = yaml.safe_load(MISSION.read_text())
    for key in ("params", "map"):
        doc[key] = str((MISSION.parent / doc[key]).resolve())
    world = yaml.safe_load(WORLD.read_text())
    world["robot"]["description"] = str((WORLD.parent / world["robot"]["description"]).resolve())
    if start is not None:
        world["robot"]["pose"] = list(start)
    (tmp_path / "world.yaml").write_text(yaml.safe_dump(world, sort_keys=False))
    doc["world"] = str(tmp_path / "world.yaml")
    doc["outputs"] = ["report", "trajectory"]
    path = tmp_path / "mission.yaml"
    path.write_text(yaml.safe_dump(doc, sort_keys=False))
    report = run_mission(Mission.load(path), tmp_path / "out")
    assert report.collisions == 0, report.contacts
    track = np.genfromtxt(tmp_path / "out" / "trajectory.csv", delimiter=",", names=True)
    return report.status, track


def tightest_radius(track: np.ndarray, window: float = 0.05) -> float:
    """The smallest arc length per radian turned over any stretch of at least `window`
    metres of ground-truth travel (forwards and backwards both count as travel)."""
    x, y, yaw = track["gt_x"], track["gt_y"], np.unwrap(track["gt_yaw"])
    s = np.r_[0.0, np.cumsum(np.hypot(np.diff(x), np.diff(y)))]
    end = np.searchsorted(s, s + window)
    ok = end < len(s)
    i, j = np.flatnonzero(ok), end[ok]
    turned = np.abs(yaw[j] - yaw[i])
    travelled = s[j] - s[i]
    return float(np.min(travelled / np.maximum(turned, 1e-12)))


def legs(track: np.ndarray) -> int:
    """How many times the car set off in a new direction (forwards or backwards)."""
    v = track["cmd_v"]
    moving = np.sign(v[np.abs(v) > 0.02])
    return int(1 + np.count_nonzero(np.diff(moving)))


@pytest.mark.parametrize(
    "start", [None, (3.02, 1.52, 0.0), (3.0, 1.5, -0.04)], ids=["bundled", "offset", "skewed"]
)
def test_the_racecar_turns_round_by_reversing_without_touching_anything(tmp_path, start):
    status, track = run(tmp_path, start)
    assert status == "succeeded"
    x, y, yaw = track["gt_x"][-1], track["gt_y"][-1], track["gt_yaw"][-1]
    assert math.hypot(x - 3.0, y - 1.5) <= XY_TOL + 0.01
    assert abs(math.remainder(yaw - math.pi, math.tau)) <= YAW_TOL + 0.01
    assert legs(track) >= 3, "facing back down a 2.2 m street takes a three-point turn at least"
    # The car's own steering limit, not the planner's margin, bounds the path
    assert tightest_radius(track) >= R_MIN - 0.02


def test_the_path_measure_sees_a_turn_tighter_than_the_car(tmp_path):
    """The curvature measure can fail a path: an arc of 0.4 m is measured as 0.4 m."""
    t = np.linspace(0.0, 1.0, 50)
    track = np.zeros(50, dtype=[("gt_x", float), ("gt_y", float), ("gt_yaw", float)])
    track["gt_x"] = 0.4 * np.cos(t)  # an arc of radius 0.4 m
    track["gt_y"] = 0.4 * np.sin(t)
    track["gt_yaw"] = t + math.pi / 2
    assert tightest_radius(track) == pytest.approx(0.4, rel=0.02)
