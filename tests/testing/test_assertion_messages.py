"""Each assertion helper's failure names what a user needs to act, on crafted runs."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from btnav.testing import (
    assert_no_collisions,
    assert_node_status,
    assert_reached,
    assert_within,
)

COLUMNS = "t,gt_x,gt_y,gt_yaw,est_x,est_y,est_yaw,odom_x,odom_y,odom_yaw,cmd_v,cmd_w,contact"


def report(**fields) -> dict:
    base = {
        "mission": "office_tour",
        "seed": 0,
        "status": "succeeded",
        "error_code": None,
        "error_msg": None,
        "sim_time": 66.7,
        "collisions": 0,
        "recoveries": 0,
        "replans": 3,
        "missed_waypoints": [],
        "task": "follow_waypoints",
        "goals": 4,
        "contacts": [],
    }
    return base | fields


def run_folder(tmp_path: Path, rows: list[tuple[float, ...]], **fields) -> Path:
    """A run folder as `btnav run` writes it: report.json and trajectory.csv."""
    (tmp_path / "report.json").write_text(json.dumps(report(**fields)))
    lines = [COLUMNS] + [",".join(map(repr, (*r, *r[1:4], *r[1:4], 0.0, 0.0, 0))) for r in rows]
    (tmp_path / "trajectory.csv").write_text("\n".join(lines) + "\n")
    return tmp_path


def failure(check, *args, **kwargs) -> str:
    with pytest.raises(AssertionError) as info:
        check(*args, **kwargs)
    return str(info.value)


def test_assert_reached_passes_a_success_and_names_a_failures_code_and_where(tmp_path):
    assert_reached(report())
    folder = run_folder(
        tmp_path,
        [(0.0, 1.0, 1.0, 0.0), (21.3, 5.12, 2.9, 0.1)],
        status="failed",
        error_code=105,
        error_msg="Failed to make progress",
        sim_time=21.3,
        task="navigate_to_pose",
    )
    text = failure(assert_reached, folder)
    assert "status failed" in text
    assert "105 (FollowPath FAILED_TO_MAKE_PROGRESS): Failed to make progress" in text
    assert "after 21.3 s of sim time, the robot last at (5.12, 2.90, 0.10)" in text
    assert f"run folder: {folder}" in text


def test_assert_reached_lists_the_missed_waypoints_of_a_succeeded_tour():
    class Result:  # what run_mission returns: a report that knows the task's poses
        task_poses = [(3.0, 2.0, 1.57), (6.0, 3.0, 0.0), (9.0, 1.5, 0.0), (2.5, 6.5, 3.14)]
        out_dir = None

        def to_dict(self):
            return report(missed_waypoints=[1, 3])

    text = failure(assert_reached, Result())
    assert "missed waypoints of 4: 1 (6.00, 3.00, 0.00), 3 (2.50, 6.50, 3.14)" in text


def test_assert_no_collisions_says_when_where_and_what_was_hit():
    assert_no_collisions(report())
    contact = {
        "time": 12.345,
        "pose": [3.1, 2.05, 1.57],
        "hit": "obstacle",
        "index": 4,
        "kind": "circle",
        "line": 27,
    }
    wall = contact | {"time": 14.0, "hit": "wall", "index": 1, "kind": "polyline", "line": 11}
    text = failure(assert_no_collisions, report(collisions=2, contacts=[contact, wall]))
    assert "touched something 2 times" in text
    assert "t=12.35 s, robot at (3.10, 2.05, 1.57): hit obstacles[4] (circle), line 27" in text
    assert "t=14.00 s, robot at (3.10, 2.05, 1.57): hit walls[1], line 11" in text


def log_record(t: float, name: str, kind: str, uid: int, before: str, now: str) -> dict:
    return {
        "timestamp": t,
        "navigator": "navigate_to_pose",
        "node_name": name,
        "type": kind,
        "uid": uid,
        "previous_status": before,
        "current_status": now,
    }


LOG = [
    log_record(0.0, "Root.ComputePathToPose", "ComputePathToPose", 3, "IDLE", "RUNNING"),
    log_record(0.1, "Root.ComputePathToPose", "ComputePathToPose", 3, "RUNNING", "FAILURE"),
    log_record(1.0, "Root.ComputePathToPose", "ComputePathToPose", 3, "FAILURE", "RUNNING"),
    log_record(1.1, "Root.ComputePathToPose", "ComputePathToPose", 3, "RUNNING", "FAILURE"),
    log_record(1.1, "Root.FollowPath", "FollowPath", 4, "IDLE", "RUNNING"),
]


def test_assert_node_status_finds_a_node_by_type_or_short_name(tmp_path):
    assert_node_status(LOG, "ComputePathToPose", "FAILURE")
    assert_node_status(LOG, "ComputePathToPose", "FAILURE", times=2, last=False)
    path = tmp_path / "bt_log.jsonl"
    path.write_text("".join(json.dumps(r) + "\n" for r in LOG))
    assert_node_status(path, "FollowPath", "RUNNING", last=True)
    assert_node_status(tmp_path, "Root.FollowPath", "RUNNING")  # a run folder


def test_assert_node_status_lists_the_statuses_the_node_had():
    text = failure(assert_node_status, LOG, "ComputePathToPose", "SUCCESS")
    assert "'ComputePathToPose' was never SUCCESS" in text
    assert "RUNNING x2, FAILURE x2; last FAILURE at t=1.10 s" in text
    assert "first RUNNING at t=0.00 s, first FAILURE at t=0.10 s" in text
    text = failure(assert_node_status, LOG, "ComputePathToPose", "FAILURE", times=1)
    assert "was not FAILURE exactly 1 time" in text


def test_assert_node_status_suggests_the_node_meant():
    text = failure(assert_node_status, LOG, "ComputePathToPos", "SUCCESS")
    assert "did you mean 'ComputePathToPose'?" in text
    assert "it has: ComputePathToPose, FollowPath" in text


def test_assert_within_gives_the_closest_approach_and_when(tmp_path):
    rows = [(0.1 * i, 1.0 + 0.1 * i, 1.0, 0.0) for i in range(30)]  # x from 1.0 to 3.9
    folder = run_folder(tmp_path, rows)
    assert_within(folder, (3.0, 1.1), tol=0.15)
    text = failure(assert_within, folder, (3.0, 2.0), tol=0.25)
    assert "never came within 0.25 m of (3.00, 2.00): closest approach 1.00 m at t=2.00 s" in text
    assert "at (3.00, 1.00, 0.00)" in text and "trajectory.csv" in text


def test_assert_within_checks_the_heading_and_takes_arrays():
    xy_yaw = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.1], [2.0, 0.0, 0.2]])
    assert_within(xy_yaw, (2.0, 0.05, 0.25), tol=0.1, yaw_tol=0.1)
    text = failure(assert_within, xy_yaw, (2.0, 0.0, 1.57), tol=0.1, yaw_tol=0.2)
    assert "never within 0.2 rad of yaw 1.57: best heading 0.20 (off by 1.37 rad) at row 2" in text
    text = failure(assert_within, xy_yaw[:, :2], (5.0, 0.0), tol=0.5)
    assert "closest approach 3.00 m at row 2" in text


def test_a_misspelt_status_is_named_with_the_right_one():
    from btnav import BtnavError

    with pytest.raises(BtnavError, match="SUCCESS"):
        assert_node_status(LOG, "FollowPath", "SUCESS")
