"""Outputs beyond the built-in files are `output` plugins; a user's is a peer of `png`."""

from __future__ import annotations

import csv
import json
from pathlib import Path
from typing import Any

import pytest

from btnav.mission import Mission, MissionError, RunOutput, run_mission
from btnav.mission.trajectory import COLUMNS
from btnav.plugins import register, unregister

from .missions import world_with, write_mission

#: A person (a circle) walks into the robot as the run starts, then stands at (1, 1).
WALKER = {
    "circle": {"center": [1.0, 1.6], "radius": 0.2, "moves": {"path": [[1.0, 1.0]], "speed": 1.0}}
}


def contact_mission(folder: Path, **fields: Any) -> Path:
    """The small office plus WALKER (obstacles[9], last in the file), a short drive to (3, 2)."""
    world = world_with(folder, WALKER)
    fields.setdefault("outputs", ["report", "trajectory"])
    return write_mission(
        folder,
        "bumped",
        world=str(world),
        initial_pose=[1.0, 1.0, 0.0],
        task={"navigate_to_pose": [3.0, 2.0, 1.57]},
        time_limit=20,
        **fields,
    )


def walker_line(folder: Path) -> int:
    """The line of WALKER's list item in the world file (the last `- circle:`)."""
    lines = (folder / "world.yaml").read_text().splitlines()
    return max(n for n, line in enumerate(lines, 1) if line.lstrip().startswith("- circle:"))


@pytest.fixture
def speed_log():
    written: list[RunOutput] = []

    @register("output", "speed_log")
    class SpeedLog:
        files = ("speeds.txt",)

        def write(self, run: RunOutput) -> None:
            written.append(run)
            (run.out_dir / self.files[0]).write_text(f"{len(run.track)}\n")

    yield written
    unregister("output", "speed_log")


def test_a_users_output_plugin_gets_the_run(tmp_path, speed_log):
    path = write_mission(
        tmp_path,
        task={"navigate_to_pose": [3.0, 2.0, 1.57]},
        outputs=["speed_log", "report"],
        time_limit=2,
    )
    report = run_mission(Mission.load(path), tmp_path / "out")
    (run,) = speed_log
    assert run.report is report and run.mission.name == "mission"
    rows = round(report.sim_time * 20)  # controller_frequency 20 Hz
    assert run.track.shape == (rows, 7) and rows >= 40
    assert run.track[-1, 0] == pytest.approx(report.sim_time)
    assert (tmp_path / "out" / "speeds.txt").read_text() == f"{rows}\n"
    assert report.outputs == ["speeds.txt", "report.json"]


def test_an_unknown_output_lists_the_registered_ones(tmp_path, speed_log):
    path = write_mission(tmp_path, task={"navigate_to_pose": [3, 2]}, outputs=["sped_log"])
    with pytest.raises(MissionError) as info:
        Mission.load(path)
    assert info.value.suggestion == "speed_log" and "png" in info.value.message
    assert info.value.key == "outputs[0]"


def test_a_contact_is_in_the_report_and_flagged_in_the_trajectory(tmp_path):
    report = run_mission(Mission.load(contact_mission(tmp_path)), tmp_path / "out")
    saved = json.loads((tmp_path / "out" / "report.json").read_text())
    assert saved["collisions"] == 1
    [contact] = saved["contacts"]
    assert contact["hit"] == "obstacle" and contact["index"] == 9 and contact["kind"] == "circle"
    assert contact["line"] == walker_line(tmp_path)
    x, y, _yaw = contact["pose"]
    assert abs(x - 1.0) < 0.1 and abs(y - 1.0) < 0.1  # it came as the robot set off
    assert 0.0 < contact["time"] < 1.0
    assert report.contacts == saved["contacts"]

    with open(tmp_path / "out" / "trajectory.csv") as f:
        rows = list(csv.DictReader(f))
    assert tuple(rows[0]) == COLUMNS and COLUMNS[-1] == "contact"
    assert COLUMNS[:12] == ("t", "gt_x", "gt_y", "gt_yaw", "est_x", "est_y", "est_yaw",
                            "odom_x", "odom_y", "odom_yaw", "cmd_v", "cmd_w")  # fmt: skip
    flagged = [float(r["t"]) for r in rows if r["contact"] == "1"]
    assert {r["contact"] for r in rows} == {"0", "1"}
    # One row, the control cycle (0.05 s at 20 Hz) during which the contact began.
    assert len(flagged) == 1 and flagged[0] - 0.05 < contact["time"] <= flagged[0]
