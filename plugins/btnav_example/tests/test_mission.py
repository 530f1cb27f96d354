"""The example's mission: its planner, controller, layer and tree node, on btnav's office."""

from __future__ import annotations

import numpy as np
from btnav.mission import Mission, run_mission

from btnav_example.astar_planner import AStarPlanner

from .conftest import OFFICE_MAP, OFFICE_WORLD, PACKAGE

MISSION = PACKAGE / "missions" / "office_example.yaml"
TREE = PACKAGE / "trees" / "navigate_w_path_budget.yaml"
#: btnav's own office, wherever this package was copied to.
OFFICE = {"mission.world": str(OFFICE_WORLD), "mission.map": str(OFFICE_MAP)}


def test_the_mission_reaches_its_goal_round_the_keepout_zone(tmp_path):
    mission = Mission.load(MISSION, overrides=OFFICE)
    planner = mission.params.server("planner_server").plugin("GridBased")
    assert planner.cls is AStarPlanner
    report = run_mission(mission, tmp_path)
    assert report.status == "succeeded", report.error_msg
    assert report.collisions == 0
    track = np.loadtxt(tmp_path / "trajectory.csv", delimiter=",", skiprows=1, usecols=(1, 2))
    in_zone = (np.abs(track[:, 0] - 7.05) < 0.25) & (np.abs(track[:, 1] - 2.25) < 0.65)
    assert not in_zone.any(), "the robot drove through the keepout zone"
    log = (tmp_path / "bt_log.jsonl").read_text()
    assert "IsPathLongerThan" in log


def test_a_path_over_the_budget_fails_the_goal(tmp_path):
    short_budget = tmp_path / "budget_5m.yaml"
    short_budget.write_text(TREE.read_text().replace("length: 25.0", "length: 5.0"))
    mission = Mission.load(MISSION, overrides={**OFFICE, "mission.tree": str(short_budget)})
    report = run_mission(mission, None)
    assert report.status == "failed"
    assert report.path_length < 0.5  # it gave up where it stood
