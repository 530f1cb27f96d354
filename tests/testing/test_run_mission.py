"""run_mission in a test: `--set`-style overrides, the run folder, and the same report."""

from __future__ import annotations

import dataclasses

import pytest

from btnav import BtnavError
from btnav.mission import Mission, RunReport
from btnav.mission import run_mission as btnav_run
from btnav.testing import RunResult, load_mission, run_mission
from btnav.testing.folders import RunFolders, safe_name

SHORT = {"task": {"navigate_to_pose": [3.0, 2.0, 1.57]}, "localization": "ground_truth"}


def test_recording_changes_nothing_in_the_report():
    """run_mission asks for the tick log and trajectory the mission may not; the run is
    the one `btnav run` makes of the same mission and seed all the same."""
    mine = run_mission("office_tour", time_limit=3, outputs=["report"], **SHORT)
    plain = btnav_run(load_mission("office_tour", time_limit=3, outputs=["report"], **SHORT))
    assert isinstance(mine, RunResult) and isinstance(mine, RunReport)
    assert mine.trajectory_file is not None and mine.bt_log_file is not None
    skip = {"wall_time", "outputs"}
    ours = {k: v for k, v in mine.to_dict().items() if k not in skip}
    theirs = {k: v for k, v in dataclasses.asdict(plain).items() if k not in skip}
    assert ours == theirs and ours["status"] == "canceled"
    assert mine.task_poses == [(3.0, 2.0, 1.57)]


def test_overrides_are_blamed_when_wrong(btnav_mission):
    mission = btnav_mission("office_tour", {"mission.seed": 7}, time_limit=20)
    assert isinstance(mission, Mission) and (mission.seed, mission.spec.time_limit) == (7, 20)
    with pytest.raises(BtnavError, match=r"override mission.tiem_limit=3.*'time_limit'"):
        btnav_mission("office_tour", tiem_limit=3)
    with pytest.raises(TypeError, match="overrides apply when a mission is loaded"):
        run_mission(mission, seed=3)


def test_a_tests_folders_are_deleted_unless_it_failed_with_an_out_dir(tmp_path):
    temporary = RunFolders("tests/test_a.py::test_b", None)
    first, second = temporary.claim(), temporary.claim()
    assert second == first / "run-2" and first.is_dir()
    temporary.failed = True
    temporary.finish()
    assert not first.exists()  # no --btnav-out: never kept

    kept = RunFolders("tests/test_a.py::test_b[x-1]", tmp_path)
    folder = kept.claim()
    assert folder == tmp_path / "tests_test_a.py_test_b_x-1"
    kept.failed = True
    kept.finish()
    assert folder.is_dir() and str(folder) in kept.section()

    passed = RunFolders("tests/test_a.py::test_b[x-1]", tmp_path)
    assert passed.claim() == folder  # what the last session left goes first
    passed.finish()
    assert not folder.exists()


def test_a_long_test_id_makes_a_short_unique_folder_name():
    a, b = (
        safe_name("t.py::test_" + "x" * 300 + "[1]"),
        safe_name("t.py::test_" + "x" * 300 + "[2]"),
    )
    assert a != b and len(a) <= 120
