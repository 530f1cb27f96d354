"""MPPI with Nav2's AckermannMotionModel drives the racecar in its street, judged by
ground truth: a forward 1.2 m curve is followed to within centimetres, and the
three-point turn of missions/racecar_parking.yaml succeeds without a contact, the car
never turning tighter than it can (params/racecar_nav2_params_mppi.yaml)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import yaml

from btnav.mission import Mission
from btnav.mission.runner import run_mission

REPO = Path(__file__).resolve().parents[3]
MISSION = REPO / "missions" / "racecar_parking.yaml"
WORLD = REPO / "worlds" / "racecar_street.yaml"
PARAMS = REPO / "params" / "racecar_nav2_params_mppi.yaml"
#: wheelbase / tan(max_steering_angle) of the world's ackermann drive
R_MIN = 0.325 / math.tan(0.34)
#: the params file's ackermann.min_turning_r
MIN_TURNING_R = 0.95
XY_TOL, YAW_TOL = 0.25, 0.25  # the params file's general_goal_checker


def run(
    tmp_path: Path,
    start: tuple[float, float, float] | None = None,
    goal: tuple[float, float, float] | None = None,
    overrides: dict[str, object] | None = None,
) -> tuple[str, np.ndarray, np.ndarray]:
    """The racecar mission with MPPI: status, ground-truth track, the first plan followed."""
    doc = yaml.safe_load(MISSION.read_text())
    doc["params"] = str(PARAMS)
    doc["map"] = str((MISSION.parent / doc["map"]).resolve())
    world = yaml.safe_load(WORLD.read_text())
    robot = world["robot"]
    if "description" in robot:  # the car's xacro, relative to the world file
        robot["description"] = str((WORLD.parent / robot["description"]).resolve())
    if start is not None:
        world["robot"]["pose"] = list(start)
    (tmp_path / "world.yaml").write_text(yaml.safe_dump(world, sort_keys=False))
    doc["world"] = str(tmp_path / "world.yaml")
    if goal is not None:
        doc["task"] = {"navigate_to_pose": list(goal)}
    doc["outputs"] = ["report", "trajectory"]
    path = tmp_path / "mission.yaml"
    path.write_text(yaml.safe_dump(doc, sort_keys=False))
    plans: list[np.ndarray] = []

    def first_plan(nav) -> None:  # reads only: the run is the same without it
        handle = nav.stack.controller_server.action.current
        if not plans and handle is not None and handle.goal.path is not None:
            plans.append(np.asarray(handle.goal.path.poses, dtype=float).reshape(-1, 3).copy())

    report = run_mission(Mission.load(path, overrides=overrides), tmp_path / "out", first_plan)
    assert report.collisions == 0, report.contacts
    track = np.genfromtxt(tmp_path / "out" / "trajectory.csv", delimiter=",", names=True)
    assert plans, "the controller was never given a plan"
    return report.status, track, plans[0]


def tightest_radius(x: np.ndarray, y: np.ndarray, yaw: np.ndarray, window: float = 0.05) -> float:
    """The smallest arc length per radian turned over any stretch of at least `window`
    metres of travel (forwards and backwards both count as travel)."""
    yaw = np.unwrap(yaw)
    s = np.r_[0.0, np.cumsum(np.hypot(np.diff(x), np.diff(y)))]
    end = np.searchsorted(s, s + window)
    ok = end < len(s)
    i, j = np.flatnonzero(ok), end[ok]
    return float(np.min((s[j] - s[i]) / np.maximum(np.abs(yaw[j] - yaw[i]), 1e-12)))


def distance_to_polyline(points: np.ndarray, poly: np.ndarray) -> np.ndarray:
    """Each point's distance to the polyline through `poly`'s (x, y)."""
    a, b = poly[:-1, :2], poly[1:, :2]
    ab = b - a
    t = ((points[:, None] - a[None]) * ab[None]).sum(-1) / np.maximum((ab * ab).sum(-1), 1e-12)
    foot = a[None] + np.clip(t, 0.0, 1.0)[..., None] * ab[None]
    return np.hypot(*(points[:, None] - foot).transpose(2, 0, 1)).min(axis=1)


def legs(track: np.ndarray) -> int:
    """How many times the car set off in a new direction (forwards or backwards)."""
    v = track["cmd_v"]
    moving = np.sign(v[np.abs(v) > 0.02])
    return int(1 + np.count_nonzero(np.diff(moving)))


def commands_within_turning_limit(track: np.ndarray) -> bool:
    return bool(np.all(np.abs(track["cmd_w"]) <= np.abs(track["cmd_v"]) / MIN_TURNING_R + 1e-6))


def test_mppi_follows_a_forward_curve_of_1_2_m_radius(tmp_path):
    # Hybrid-A* at 1.2 m plans one left arc from the street's right side; measured: the
    # car stays within 2.5 cm of it (clipping every sample to the turning limit, as btnav
    # did, drifted 0.42 m off it and failed, commanding |wz| <= 0.09 where 0.25 was needed)
    status, track, plan = run(
        tmp_path,
        start=(1.5, 0.9, 0.0),
        goal=(3.3, 2.0, 1.3),
        overrides={"planner_server.GridBased.minimum_turning_radius": 1.2},
    )
    assert status == "succeeded"
    seg = np.hypot(*np.diff(plan[:, :2], axis=0).T)
    plan_r = tightest_radius(plan[:, 0], plan[:, 1], plan[:, 2])
    # a curve about as tight as asked for (1.2 m measured), that the car can drive
    assert R_MIN < plan_r < 1.3 and np.unwrap(plan[:, 2])[-1] > 1.2
    assert seg.sum() > 2.0  # the curve, not a stub: the test means what it says
    gt = np.stack([track["gt_x"], track["gt_y"]], axis=-1)
    assert distance_to_polyline(gt, plan).max() < 0.06
    assert tightest_radius(track["gt_x"], track["gt_y"], track["gt_yaw"]) >= R_MIN - 0.02
    assert commands_within_turning_limit(track)
    x, y = track["gt_x"][-1], track["gt_y"][-1]
    assert math.hypot(x - 3.3, y - 2.0) <= XY_TOL + 0.01


@pytest.mark.parametrize(
    "start", [None, (3.02, 1.52, 0.0), (3.0, 1.5, -0.04)], ids=["bundled", "offset", "skewed"]
)
def test_mppi_turns_the_racecar_round_by_a_three_point_turn(tmp_path, start):
    status, track, _ = run(tmp_path, start)
    assert status == "succeeded"
    x, y, yaw = track["gt_x"][-1], track["gt_y"][-1], track["gt_yaw"][-1]
    assert math.hypot(x - 3.0, y - 1.5) <= XY_TOL + 0.01
    assert abs(math.remainder(yaw - math.pi, math.tau)) <= YAW_TOL + 0.01
    assert legs(track) >= 3, "facing back down a 2.2 m street takes a three-point turn at least"
    assert tightest_radius(track["gt_x"], track["gt_y"], track["gt_yaw"]) >= R_MIN - 0.02
    assert commands_within_turning_limit(track)


def test_the_radius_measure_sees_a_turn_tighter_than_the_car():
    """The curvature measure can fail a run: an arc of 0.4 m is measured as 0.4 m."""
    t = np.linspace(0.0, 1.0, 50)
    r = tightest_radius(0.4 * np.cos(t), 0.4 * np.sin(t), t + math.pi / 2)
    assert r == pytest.approx(0.4, rel=0.02)
    poly = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]])
    d = distance_to_polyline(np.array([[0.5, 0.1], [1.2, 0.5], [2.0, 2.0]]), poly)
    assert d == pytest.approx([0.1, 0.2, math.hypot(1.0, 1.0)])
