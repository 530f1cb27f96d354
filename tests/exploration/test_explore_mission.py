"""Exploring with SLAM (`task: explore`), teleop scripts (`task: drive`), and a mission in
stages (map, then navigate the map with AMCL): what a user runs and looks at."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import yaml

from btnav.core.errors import BtnavError
from btnav.exploration.coverage import coverage
from btnav.maps.map_io import load_map
from btnav.mission import Mission, run_mission
from btnav.mission.stages import run_stages
from btnav.sim.rasterize import rasterize
from btnav.sim.world_spec import load_world_spec

REPO = Path(__file__).resolve().parents[2]
FOUR_ROOMS = REPO / "worlds" / "four_rooms.yaml"
START = (1.0, 1.0)


def write(tmp_path: Path, name: str = "mission.yaml", **fields) -> Path:
    doc = {
        "mission": "explore_four_rooms",
        "world": str(FOUR_ROOMS),
        "params": str(REPO / "params" / "nav2_params.yaml"),
        "localization": "slam",
        "initial_pose": [*START, 0.0],
        "task": "explore",
        "time_limit": 400,
        "outputs": ["report", "trajectory", "bt_log", "map"],
        **fields,
    }
    path = tmp_path / name
    path.write_text(yaml.safe_dump(doc, sort_keys=False))
    return path


def test_the_same_seed_explores_the_same_way_to_the_byte(tmp_path):
    runs = []
    for i in range(2):
        out = tmp_path / f"run{i}"
        run_mission(Mission.load(write(tmp_path, time_limit=15)), out)
        runs.append((out / "trajectory.csv").read_bytes())
    assert runs[0] == runs[1]
    rows = np.loadtxt(tmp_path / "run0" / "trajectory.csv", delimiter=",", skiprows=1)
    assert np.hypot(*(rows[-1, 1:3] - START)) > 0.5  # it went somewhere


def test_a_drive_script_moves_the_robot_within_its_limits_and_maps_as_it_goes(tmp_path):
    script = [[0.4, 0.0, 4.0], [0.0, 1.0, 1.5], [0.3, 0.0, 2.0]]
    path = write(tmp_path, task={"drive": script}, time_limit=30)
    report = run_mission(Mission.load(path), tmp_path / "out")
    assert report.status == "succeeded" and report.collisions == 0
    assert report.sim_time == pytest.approx(7.5, abs=0.15)  # the script's length, then stop
    rows = np.loadtxt(tmp_path / "out" / "trajectory.csv", delimiter=",", skiprows=1)
    t, x, y, yaw = rows[:, 0], rows[:, 1], rows[:, 2], rows[:, 3]
    at4 = np.searchsorted(t, 4.0)
    # 0.4 m/s for 4 s, reached at the base's a_max of 1 m/s^2: 1.6 m less 0.08 m
    assert x[at4] - START[0] == pytest.approx(1.52, abs=0.05)
    assert abs(y[at4] - START[1]) < 0.02
    assert yaw[-1] == pytest.approx(1.5, abs=0.1)  # 1 rad/s for 1.5 s, within alpha_max
    assert report.explored_area > 10.0  # SLAM mapped as it went
    assert (tmp_path / "out" / "map.yaml").is_file()


def test_a_drive_command_with_a_negative_duration_names_its_line(tmp_path):
    path = write(tmp_path, task={"drive": [[0.2, 0.0, 1.0], [0.2, 0.0, -1.0]]})
    with pytest.raises(BtnavError) as info:
        Mission.load(path)
    assert info.value.key.startswith("task.drive") and info.value.line is not None


# -- a mission in stages -----------------------------------------------------------------


def staged(tmp_path: Path, stages: list[dict], **fields) -> Path:
    doc = {
        "mission": "four_rooms_loop",
        "world": str(FOUR_ROOMS),
        "params": str(REPO / "params" / "nav2_params.yaml"),
        "initial_pose": [*START, 0.0],
        **fields,
        "stages": stages,
    }
    path = tmp_path / "loop.yaml"
    path.write_text(yaml.safe_dump(doc, sort_keys=False))
    return path


MAP_STAGE = {
    "name": "map",
    "localization": "slam",
    "task": "explore",
    "time_limit": 400,
    "outputs": ["report"],
}
TOUR = [[3.5, 2.0, 0.0], [7.5, 3.0, 1.57], [7.0, 7.5, 3.14], [2.0, 7.0, -1.57]]
TOUR_STAGE = {
    "name": "tour",
    "localization": "amcl",
    "map": "map",
    "task": {"follow_waypoints": TOUR},
    "time_limit": 300,
}


@pytest.fixture(scope="module")
def closed_loop(tmp_path_factory):
    """The staged mission's run, shared: its map stage is the explore mission `write` gives
    (the same world, start, params, seed and time limit), so the explore test below judges
    that stage rather than exploring the four rooms a second time (~50 s of CPU)."""
    tmp = tmp_path_factory.mktemp("loop")
    explore = dict(MAP_STAGE, outputs=["report", "trajectory", "bt_log", "map"])
    report = run_stages(staged(tmp, [explore, TOUR_STAGE]), tmp / "out")
    return tmp / "out", report


@pytest.mark.slow
def test_exploring_four_rooms_maps_them_and_ends_by_itself(closed_loop):
    out, staged_report = closed_loop
    name, report = staged_report.stages[0]  # `task: explore` with SLAM, run by run_mission
    assert name == "map"
    out = out / "map"
    assert report.status == "succeeded", report.summary()  # no frontier left, not the time limit
    assert report.collisions == 0, report.contacts
    truth = rasterize(load_world_spec(FOUR_ROOMS), 0.05)
    mapped = coverage(load_map(out / "map.yaml"), truth, START)
    assert mapped.fraction >= 0.90, mapped
    assert report.explored_area == pytest.approx(mapped.mapped_m2, rel=0.1)
    # the tree visited frontiers with Nav2's planner and controller
    log = [json.loads(line) for line in (out / "bt_log.jsonl").open()]
    succeeded = {e["type"] for e in log if e["current_status"] == "SUCCESS"}
    assert {"ComputeFrontiers", "ComputePathToPose", "IsExplorationComplete"} <= succeeded


@pytest.mark.slow
def test_the_closed_loop_maps_then_tours_the_map_with_amcl(closed_loop):
    out, report = closed_loop
    assert [name for name, _ in report.stages] == ["map", "tour"]
    (_, mapping), (_, tour) = report.stages
    assert mapping.succeeded and tour.succeeded and not tour.missed_waypoints, tour.summary()
    assert mapping.collisions == 0 and tour.collisions == 0
    # the map stage saved its map although its outputs did not ask: the tour needed it
    saved = load_map(out / "map" / "map.yaml")
    assert (saved.data == 0).sum() * saved.resolution**2 == pytest.approx(mapping.explored_area)
    top = json.loads((out / "report.json").read_text())
    assert top["status"] == "succeeded" and [s["stage"] for s in top["stages"]] == ["map", "tour"]
    # Nav2's amcl section on the map SLAM made holds the bound issue 34 sets (6.8 cm measured)
    err = tour.localization_error
    assert err["rms_xy"] <= 0.08 and err["max_xy"] < 0.30, err


@pytest.mark.slow
@pytest.mark.xfail(
    strict=True,
    reason="AMCL on the SLAM-made map: 6.8 cm RMS on seeds 0-2 (5.3-5.6 cm on the map "
    "drawn from the world); btnav's AMCL is nav2_amcl's algorithm, and with Nav2's amcl "
    "section the filter, not the map, sets the error: one scan fits either map to 2.5-3 cm "
    "RMS, but the cloud stays ~25 cm / 15 deg wide and its mean trails the robot",
)
def test_amcl_on_the_slam_map_is_within_5_cm(closed_loop):
    _, report = closed_loop
    _, tour = report.stages[-1]
    assert tour.localization_error["rms_xy"] <= 0.05, tour.localization_error


@pytest.mark.slow
def test_amcl_matched_to_the_odometry_holds_5_cm_on_the_slam_map(closed_loop, tmp_path):
    """The shipped matched params (alphas from the world's odometry noise and
    likelihood_field_prob) tour the map the map stage saved: 2.0-2.5 cm RMS on seeds 0-2."""
    out, _ = closed_loop
    mission = write(
        tmp_path,
        params=str(REPO / "params" / "nav2_params_matched_amcl.yaml"),
        localization="amcl",
        map=str(out / "map" / "map.yaml"),
        task={"follow_waypoints": TOUR},
        time_limit=300,
        outputs=["report"],
    )
    report = run_mission(Mission.load(mission))
    assert report.status == "succeeded" and not report.missed_waypoints, report.summary()
    assert report.collisions == 0
    assert report.localization_error["rms_xy"] <= 0.05, report.localization_error


def test_mistakes_in_stages_are_named_at_their_lines(tmp_path):
    bad_key = dict(MAP_STAGE, locaization="slam")
    with pytest.raises(BtnavError) as info:
        run_stages(staged(tmp_path, [bad_key, TOUR_STAGE]), tmp_path / "out")
    assert info.value.suggestion == "localization" and info.value.line is not None
    assert not (tmp_path / "out").exists()  # nothing ran
    later = dict(TOUR_STAGE, map="tour")
    with pytest.raises(BtnavError, match="as this very stage"):
        run_stages(staged(tmp_path, [MAP_STAGE, later]), tmp_path / "out")
    with pytest.raises(BtnavError, match="its task, not one at the top"):
        run_stages(staged(tmp_path, [MAP_STAGE], task="explore"), tmp_path / "out")
    with pytest.raises(BtnavError, match="runs in stages"):
        Mission.load(staged(tmp_path, [MAP_STAGE, TOUR_STAGE]))


def test_explore_feedback_carries_the_robots_pose_as_nav2s_navigators_do(tmp_path):
    nav = Mission.load(write(tmp_path)).navigator()
    assert nav.explore()
    for _ in range(20):  # 2 s of exploring
        nav.is_task_complete()
    pose = nav.get_feedback().current_pose
    truth = nav.robot_pose
    assert abs(pose.x - truth.x) < 0.1 and abs(pose.y - truth.y) < 0.1, (pose, truth)
    assert nav.get_feedback().navigation_time > 1.0
