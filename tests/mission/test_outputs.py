"""Outputs beyond the built-in files are `output` plugins; a user's is a peer of `png`."""

from __future__ import annotations

import pytest

from btnav.mission import Mission, MissionError, RunOutput, run_mission
from btnav.plugins import register, unregister

from .missions import write_mission


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
