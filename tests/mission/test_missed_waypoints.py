"""A missed waypoint says why: its pose, Nav2's error code (number and name) and message,
the tree node that failed last and the sim time, in report.json (issue 34)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

from btnav.mission.mission import Mission
from btnav.mission.report import error_code_name, missed_line
from btnav.mission.runner import run_mission

from .missions import read_report, write_mission

#: Reached, beyond the map (the planner refuses the goal), inside the map's obstacle.
WAYPOINTS = [[1.6, 1.0, 0.0], [20.0, 3.0, 0.0], [6.5, 1.2, 0.0]]


@pytest.fixture(scope="module")
def run(tmp_path_factory: pytest.TempPathFactory) -> tuple[dict[str, Any], list[dict[str, Any]]]:
    """The tour's report.json and its bt_log.jsonl records (run once for the module)."""
    folder = tmp_path_factory.mktemp("missed")
    path = write_mission(
        folder,
        "three_stops",
        task={"follow_waypoints": WAYPOINTS},
        time_limit=120,
        outputs=["report", "bt_log"],
    )
    with pytest.warns(UserWarning):  # the mission warns of both goals as it loads
        mission = Mission.load(path)
    run_mission(mission, folder / "out")
    log = (folder / "out" / "bt_log.jsonl").read_text().splitlines()
    return read_report(folder / "out"), [json.loads(line) for line in log]


def statuses(run: tuple[dict[str, Any], list[dict[str, Any]]]) -> list[dict[str, Any]]:
    return run[0]["missed_waypoint_statuses"]


def test_missed_waypoints_stay_the_indices_scripts_read(run):
    report, _ = run
    assert report["status"] == "succeeded" and report["missed_waypoints"] == [1, 2]
    assert [s["waypoint_index"] for s in statuses(run)] == [1, 2]


def test_each_names_its_goal_pose(run):
    assert [s["waypoint_pose"] for s in statuses(run)] == WAYPOINTS[1:]


def test_each_has_nav2s_error_code_number_and_name(run):
    assert [(s["error_code"], s["error_code_name"]) for s in statuses(run)] == [
        (204, "GOAL_OUTSIDE_MAP"),  # ComputePathToPose's codes: the planner refused the goal
        (208, "NO_VALID_PATH"),
    ]
    assert all(s["waypoint_status"] == "FAILED" for s in statuses(run))  # WaypointStatus's


def test_each_has_the_message(run):
    beyond, inside = statuses(run)
    assert "(20.000, 3.000)" in beyond["error_msg"] and "outside" in beyond["error_msg"]
    assert inside["error_msg"].startswith("Failed to create plan")


def test_each_has_the_sim_time_it_was_given_up(run):
    report, _ = run
    beyond, inside = statuses(run)
    assert 0.0 < beyond["sim_time"] < inside["sim_time"] <= report["sim_time"]
    assert inside["sim_time"] == pytest.approx(report["sim_time"], abs=0.2)  # the last goal


def test_each_names_the_tree_node_that_failed_last(run):
    _, log = run
    for status in statuses(run):
        node = status["failed_node"]
        assert node["type"] == "ComputePathToPose"
        # The bt_log has that node's FAILURE, and no action node failed later for this goal.
        failures = [
            r
            for r in log
            if r["current_status"] == "FAILURE"
            and r["timestamp"] <= status["sim_time"] + 1e-9
            and r["type"] in {"ComputePathToPose", "FollowPath", "Spin", "BackUp", "Wait"}
        ]
        assert (failures[-1]["node_name"], failures[-1]["type"]) == (node["name"], node["type"])


def test_the_printed_line_carries_every_field(run):
    beyond = statuses(run)[0]
    line = missed_line(beyond)
    assert line.startswith("missed waypoint 1 (20, 3, 0): error 204 GOAL_OUTSIDE_MAP ")
    assert f'"{beyond["error_msg"]}"' in line
    assert line.endswith(f"; ComputePathToPose failed last, at {beyond['sim_time']:.1f} s sim")


def test_a_tour_without_misses_lists_none(tmp_path: Path):
    path = write_mission(tmp_path, task={"follow_waypoints": WAYPOINTS[:1]}, outputs=["report"])
    report = run_mission(Mission.load(path), tmp_path / "out")
    assert report.missed_waypoints == [] and report.missed_waypoint_statuses == []
    assert read_report(tmp_path / "out")["missed_waypoint_statuses"] == []


def test_code_names_come_from_each_actions_own_hundreds():
    assert [error_code_name(c) for c in (0, 2, 105, 204, 603, 9001, 12345)] == [
        "NONE",
        "SEND_GOAL_FAILURE",
        "FAILED_TO_MAKE_PROGRESS",
        "GOAL_OUTSIDE_MAP",
        "STOP_ON_MISSED_WAYPOINT",
        "FAILED_TO_LOAD_BEHAVIOR_TREE",
        "12345",
    ]
