"""Every script in examples/ runs as the README says, from the repository root, and prints
what a user runs it for (each in a subprocess, its files in a temporary folder)."""

from __future__ import annotations

import csv
import importlib.util
import re
import subprocess
import sys
from pathlib import Path

import pytest

from btnav.maps import FREE, OCCUPIED, load_map

REPO = Path(__file__).resolve().parents[1]
HAS_MATPLOTLIB = importlib.util.find_spec("matplotlib") is not None


def run_example(name: str, *args: str, code: int = 0) -> str:
    """Run `python examples/NAME.py ARGS` in the repository root; its stdout, once the exit
    code is `code` (the output and errors are shown when it is not)."""
    proc = subprocess.run(
        [sys.executable, f"examples/{name}.py", *args], capture_output=True, text=True, cwd=REPO
    )
    assert proc.returncode == code, f"exit {proc.returncode}\n{proc.stdout}\n{proc.stderr}"
    assert "Traceback" not in proc.stderr
    return proc.stdout


def number(pattern: str, text: str) -> list[float]:
    """The numbers a `pattern` with groups finds in `text` (its first match)."""
    match = re.search(pattern, text, re.MULTILINE)
    assert match is not None, f"no line like {pattern!r} in:\n{text}"
    return [float(g) for g in match.groups()]


# -- send_goal.py ---------------------------------------------------------------------------


def test_send_goal_prints_feedback_and_reaches_the_goal():
    out = run_example("send_goal", "--goal", "3.0", "2.0", "1.57", "--every", "1")
    remaining = [float(m) for m in re.findall(r"distance remaining\s+([\d.]+) m", out)]
    assert len(remaining) >= 3 and remaining[-1] < remaining[0]  # feedback, getting closer
    assert re.search(r"ETA\s+[\d.]+ s\s+navigation time\s+[\d.]+ s\s+recoveries 0", out)
    assert "result: SUCCEEDED" in out and out.rstrip().endswith("goal reached")


def test_send_goal_names_nav2s_error_code_and_retries_once():
    out = run_example("send_goal", "--goal", "50", "50", "0", code=1)
    assert out.count("error code 204 (ComputePathToPose GOAL_OUTSIDE_MAP)") == 2
    assert "attempt 2 of 2" in out and "gave up after 2 attempt(s)" in out


def test_send_goal_cancels_at_its_timeout():
    out = run_example("send_goal", "--timeout", "3", "--retries", "0", code=1)
    assert "timeout: 3 s of sim time passed; canceling the goal" in out
    (t,) = number(r"result: CANCELED at t=([\d.]+) s", out)
    assert 3.0 <= t < 4.0


# -- dynamic_inflation.py -------------------------------------------------------------------


@pytest.mark.slow
def test_dynamic_inflation_shows_the_plan_moving_closer_to_the_walls(tmp_path):
    out = run_example("dynamic_inflation", "--out", str(tmp_path))
    assert number(r"inflation_radius \(m\)\s+([\d.]+)\s+([\d.]+)", out) == [0.7, 0.3]
    before, after = number(r"closest approach to a wall \(m\)\s+([\d.]+)\s+([\d.]+)", out)
    assert after < before
    longer, shorter = number(r"plan length \(m\)\s+([\d.]+)\s+([\d.]+)", out)
    assert shorter < longer
    cells_before, cells_after = number(r"inflated cells \(cost > 0\)\s+(\d+)\s+(\d+)", out)
    assert cells_after < cells_before
    # the tree replanned on the new costmap: the followed plan passes closer too
    followed = number(r"closest approach to a wall ([\d.]+) m at t=[\d.]+ s, ([\d.]+) m", out)
    assert followed[1] < followed[0]
    assert "result: succeeded" in out
    assert (tmp_path / "before_after.png").is_file() == HAS_MATPLOTLIB


# -- check_frames.py ------------------------------------------------------------------------


def test_check_frames_demo_shows_a_connected_and_a_broken_tree():
    out = run_example("check_frames")
    good, broken = out.split("\n\n", 1)
    assert "odom -> base_link: ok, through odom -> base_footprint -> base_link" in good
    assert "laser in map: x 1.100, y 1.000" in good and "result: connected" in good
    assert "under 'base_link' there is: laser" in broken  # the chain's wrong laser frame
    assert "(did you mean 'base_footprint'?)" in broken  # the params' misspelt frame
    assert "result: NOT connected; missing: base_scan, base_foot_print" in broken


def test_check_frames_exits_1_when_the_chain_is_broken():
    out = run_example(
        "check_frames", "missions/office_tour.yaml", "--chain", "map", "odom", "lidar", code=1
    )
    assert "odom -> lidar: MISSING: frame 'lidar' is not in the tree" in out


# -- save_map.py ----------------------------------------------------------------------------


def test_save_map_writes_a_map_server_map_and_counts_its_cells(tmp_path):
    out = run_example("save_map", "--seconds", "10", "--out", str(tmp_path))
    grid = load_map(tmp_path / "map.yaml")  # map_server reads what map_saver wrote
    assert (tmp_path / "map.pgm").is_file() and "mode: trinary" in out
    width, height = number(r"size: (\d+) x (\d+) cells", out)
    assert (width, height) == (grid.width, grid.height)
    (free,) = number(r"free cells: (\d+)", out)
    (occupied,) = number(r"occupied cells: (\d+)", out)
    assert free == (grid.data == FREE).sum() > 0
    assert occupied == (grid.data == OCCUPIED).sum() > 0
    assert number(r"resolution: ([\d.]+) m/cell", out) == [grid.resolution]


# -- sweep_inflation.py ---------------------------------------------------------------------


@pytest.mark.slow
def test_sweep_inflation_runs_a_goal_set_and_prints_the_table(tmp_path):
    args = ["--sets", "1", "--radii", "0.55", "--workers", "1", "--out", str(tmp_path)]
    out = run_example("sweep_inflation", *args)
    assert re.search(r"\| all 1\s+\| 0.55\s+\| 1/1 100%", out)
    with (tmp_path / "results.csv").open() as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 1 and rows[0]["status"] == "succeeded"
