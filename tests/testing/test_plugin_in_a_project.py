"""The plugin as a user meets it: a project of their own, nothing but btnav installed.

Each test writes a test file into a fresh folder (no conftest, no ini file) and runs
pytest on it in a subprocess, so only the `pytest11` entry point brings the fixtures.
"""

from __future__ import annotations

import importlib.util
import re
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]

#: A user's test file using every fixture and helper, on short drives of the office tour.
USER_TESTS = """
from btnav.testing import (
    assert_no_collisions, assert_node_status, assert_reached, assert_within, respond,
    run_mission, tick_until,
)

DESK = {"navigate_to_pose": [3.0, 2.0, 1.57]}


def test_run_mission_reaches_the_desk():
    report = run_mission("office_tour", task=DESK, localization="ground_truth", time_limit=30)
    assert_reached(report)
    assert_no_collisions(report)
    assert_within(report, (3.0, 2.0), tol=0.3)
    assert_node_status(report, "ComputePathToPose", "SUCCESS")


def test_a_mission_with_overrides(btnav_mission):
    mission = btnav_mission(
        "office_tour", seed=4,
        **{"local_costmap.local_costmap.inflation_layer.inflation_radius": 0.4},
    )
    local = mission.params.raw["local_costmap"]["local_costmap"]["ros__parameters"]
    assert mission.seed == 4 and local["inflation_layer"]["inflation_radius"] == 0.4


def test_the_navigator_drives_on_sim_time(btnav_navigator):
    nav = btnav_navigator("office_tour", localization="ground_truth")
    nav.go_to_pose((2.0, 1.0, 0.0))
    result = tick_until(nav, timeout=30.0)
    assert result.status == "SUCCESS" and result.ticks > 0, result
    assert_within(nav, (2.0, 1.0), tol=0.3)
    assert_no_collisions(nav)


def test_a_recovery_after_a_failed_follow(btnav_tree):
    tree = btnav_tree(
        "navigate_to_pose_w_replanning_and_recovery",
        goal=(6.0, 3.0, 0.0),
        servers={"FollowPath": [respond("FAILURE", ticks=5), "SUCCESS"]},
        nodes={"ValidatePath": "SUCCESS"},
    )
    status, ticks = tick_until(tree, timeout=5.0)
    assert status == "SUCCESS" and ticks < 50
    assert_node_status(tree, "ClearLocalCostmap-Context", "SUCCESS")


def test_a_tree_on_the_real_servers(btnav_navigator, btnav_tree):
    nav = btnav_navigator("office_tour", localization="ground_truth")
    tree = btnav_tree(
        "Sequence: {children: [{ComputePathToPose: {goal: '{goal}', path: '{path}'}}]}",
        navigator=nav, goal=(6.0, 3.0, 0.0),
    )
    assert tick_until(tree).status == "SUCCESS"
    assert tree.blackboard["path"].length() > 5.0


def test_a_world(btnav_world):
    assert len(btnav_world(__WORLD__).solids) == 15
"""

#: One failing and one passing run, for --btnav-out.
KEPT_TESTS = """
from btnav.testing import assert_reached, run_mission, tick_until

def test_too_short_to_arrive():
    assert_reached(run_mission("office_tour", task={"navigate_to_pose": [3.0, 2.0, 1.57]},
                               localization="ground_truth", time_limit=2))

def test_a_failure_that_made_no_run():
    assert 1 == 2

def test_a_passing_tree(btnav_tree):
    tree = btnav_tree("Sequence: {children: [{Spin: {spin_dist: 1.0}}]}")
    assert tick_until(tree).status == "SUCCESS"
"""


@pytest.mark.slow
def test_a_users_test_file_passes_with_only_the_installed_fixtures(pytester):
    pytester.makepyfile(
        test_user=USER_TESTS.replace("__WORLD__", repr(str(REPO / "worlds" / "small_office.yaml")))
    )
    result = pytester.runpytest_subprocess("-p", "no:cacheprovider")
    result.assert_outcomes(passed=6)


@pytest.mark.slow
def test_btnav_out_keeps_a_failed_tests_run_folder_and_prints_its_path(pytester):
    pytester.makepyfile(test_kept=KEPT_TESTS)
    out = pytester.path / "runs"
    result = pytester.runpytest_subprocess("-p", "no:cacheprovider", f"--btnav-out={out}")
    result.assert_outcomes(passed=1, failed=2)
    kept = out / "test_kept.py_test_too_short_to_arrive"
    files = {p.name for p in kept.iterdir()}
    assert files >= {"bt_log.jsonl", "report.json", "trajectory.csv"}
    if importlib.util.find_spec("matplotlib") is not None:
        assert "run.png" in files
    assert [p.name for p in out.iterdir()] == [kept.name]  # the passing test left nothing
    text = result.stdout.str()
    assert "time_limit of 2 s reached" in text
    assert re.search(r"-+ btnav -+\s+run folder kept .*\n" + re.escape(str(kept)), text), text
    assert text.count(" btnav ---") == 1  # nothing about the test that made no run


def readme_test_file() -> str | None:
    """The test file in README.md's "Testing a tree with pytest" section, if it is there."""
    text = (REPO / "README.md").read_text()
    section = re.search(r"\n## Testing a tree with pytest\n(.*?)(?=\n## |\Z)", text, re.S)
    if section is None:
        return None
    block = re.search(r"```python\n(.*?)```", section.group(1), re.S)
    return block.group(1) if block else None


@pytest.mark.slow
def test_the_readme_test_file_passes_as_printed(pytester):
    code = readme_test_file()
    if code is None:
        pytest.skip("README.md has no 'Testing a tree with pytest' section yet")
    pytester.makepyfile(test_readme_example=code)
    result = pytester.runpytest_subprocess("-p", "no:cacheprovider")
    outcomes = result.parseoutcomes()
    assert outcomes.get("passed", 0) >= 1 and set(outcomes) <= {"passed", "seconds"}, outcomes
