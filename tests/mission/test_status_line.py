"""`btnav run`'s live status line: what it says, and that it stays off the record."""

from __future__ import annotations

import io
from pathlib import Path

import pytest

from btnav.cli.status_line import StatusLine
from btnav.mission import Mission
from btnav.mission.run_status import format_status
from btnav.mission.runner import run_mission

from .missions import write_mission


class Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_the_line_says_time_speed_action_and_waypoint():
    assert format_status(12.44, 6.6, ["FollowPath"], (2, 4)) == (
        "12.4 s sim | 7x real time | FollowPath | waypoint 2/4"
    )
    assert format_status(0.0, None, [], None) == "0.0 s sim"
    assert format_status(3.0, 5.0, ["ComputePathToPose", "FollowPath"], None) == (
        "3.0 s sim | 5x real time | ComputePathToPose, FollowPath"
    )
    long = format_status(12.4, 7.0, ["FollowPath"], (2, 4), width=20)
    assert long == "12.4 s sim | 7x r..." and len(long) == 20


def test_nothing_is_written_when_stdout_is_not_a_terminal():
    plain = io.StringIO()
    line = StatusLine(plain, task="navigate_to_pose", goals=1)
    assert not line.enabled
    line(object())  # never looks at the navigator
    line.close()
    assert plain.getvalue() == ""


def tour(folder: Path) -> Mission:
    path = write_mission(
        folder,
        task={"follow_waypoints": [[1.6, 1.0, 0.0], [2.2, 1.6, 1.57]]},
        outputs=["trajectory", "bt_log"],
    )
    return Mission.load(path)


@pytest.mark.slow
def test_on_a_terminal_the_line_is_redrawn_in_place_and_the_run_is_unchanged(tmp_path):
    terminal = Terminal()
    ticks = iter(range(10**9))
    status = StatusLine(
        terminal,
        task="follow_waypoints",
        goals=2,
        interval=1.0,
        wall_clock=lambda: float(next(ticks)) * 0.1,  # ten polls a redraw
    )
    with_status = run_mission(tour(tmp_path), tmp_path / "a", progress=status)
    status.close()
    without = run_mission(tour(tmp_path), tmp_path / "b")
    for name in ("trajectory.csv", "bt_log.jsonl"):  # the same run, byte for byte
        assert (tmp_path / "a" / name).read_bytes() == (tmp_path / "b" / name).read_bytes()
    assert with_status.sim_time == without.sim_time and with_status.succeeded

    drawn = terminal.getvalue().split("\r")[1:]
    assert len(drawn) > 10 and "\n" not in terminal.getvalue()
    assert any("FollowPath | waypoint 1/2" in d for d in drawn)
    assert any("FollowPath | waypoint 2/2" in d for d in drawn)
    assert all(" s sim | " in d for d in drawn[:-2])
    assert drawn[-1] == "" and drawn[-2].strip() == ""  # erased for the result line
