"""The command line as a user meets it: exit codes and one-line errors, no tracebacks."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from btnav.cli import main
from btnav.maps import load_map

REPO = Path(__file__).resolve().parents[1]
OFFICE = REPO / "worlds" / "small_office.yaml"
TOUR = REPO / "missions" / "office_tour.yaml"


def run_cli(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "btnav.cli", *args], capture_output=True, text=True, cwd=REPO
    )


def test_params_check_accepts_nav2s_own_file(nav2_params_file, capsys):
    assert main(["params", "check", str(nav2_params_file)]) == 0
    out = capsys.readouterr().out
    assert "controller_server" in out and "not implemented" in out


def test_a_misspelt_param_is_one_line_and_exit_2(nav2_params_file, tmp_path):
    text = nav2_params_file.read_text()
    bad = tmp_path / "my_params.yaml"
    bad.write_text(text.replace("controller_frequency: 20.0", "controller_frequncy: 20.0"))
    line = text.splitlines().index("    controller_frequency: 20.0") + 1
    proc = run_cli("params", "check", str(bad))
    assert proc.returncode == 2
    err = proc.stderr.strip()
    assert "Traceback" not in proc.stderr and len(err.splitlines()) == 1
    assert f"my_params.yaml:{line}:" in err
    assert "controller_frequncy" in err and "did you mean 'controller_frequency'" in err


def test_missing_file_is_a_user_error():
    proc = run_cli("params", "check", "no/such/params.yaml")
    assert proc.returncode == 2 and "no/such/params.yaml" in proc.stderr
    assert "Traceback" not in proc.stderr


def test_usage_errors_exit_2():
    assert run_cli("params").returncode == 2
    assert run_cli("bogus-command").returncode == 2


def test_map_from_world_writes_a_map_server_map(tmp_path):
    out = tmp_path / "new_folder" / "office.yaml"
    assert main(["map", "from-world", str(OFFICE), "-o", str(out), "--resolution", "0.1"]) == 0
    grid = load_map(out)
    assert grid.resolution == pytest.approx(0.1)
    assert (grid.data == 100).any() and (grid.data == 0).any()


def test_world_show_draws_a_png(tmp_path):
    pytest.importorskip("matplotlib")
    out = tmp_path / "new_folder" / "office.png"
    assert main(["world", "show", str(OFFICE), "-o", str(out)]) == 0
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and out.stat().st_size > 10_000


def test_world_frames_prints_rep105_and_the_sensors(capsys):
    assert main(["world", "frames", str(OFFICE)]) == 0
    out = capsys.readouterr().out
    for frame in ("map", "odom", "base_footprint", "base_link", "laser"):
        assert frame in out


def test_tree_import_and_show_through_the_command(nav2_dir, tmp_path):
    xml = nav2_dir / "behavior_trees" / "navigate_to_pose_w_replanning_and_recovery.xml"
    out = tmp_path / "nav.yaml"
    proc = run_cli("tree", "import", str(xml), "-o", str(out))
    assert proc.returncode == 0, proc.stderr
    assert "RecoveryNode" in out.read_text()
    proc = run_cli("tree", "show", "navigate_to_pose_w_replanning_and_recovery")
    assert proc.returncode == 0 and "ComputePathToPose" in proc.stdout
    proc = run_cli("tree", "show", "navigate_to_pose_w_replanning_and_recovry")
    assert proc.returncode == 2 and "did you mean" in proc.stderr and "Traceback" not in proc.stderr


def test_a_mistake_in_a_mission_is_one_line_and_exit_2(tmp_path):
    mission = tmp_path / "m.yaml"
    mission.write_text(
        f"world: {OFFICE}\nmap: {REPO / 'maps' / 'small_office.yaml'}\n"
        "task:\n  navigate_to_pose: [3, 2]\noutputs: [report, trajectry]\n"
    )
    result = run_cli("run", str(mission), "--out", str(tmp_path / "out"))
    assert result.returncode == 2 and result.stdout == ""
    assert result.stderr.strip().count("\n") == 0 and "Traceback" not in result.stderr
    assert (
        f"{mission}:5: outputs[1]:" in result.stderr
        and "did you mean 'trajectory'" in result.stderr
    )
    assert not (tmp_path / "out").exists()  # nothing ran
    bad_set = run_cli(
        "run", "missions/office_tour.yaml", "--set", "controller_server.controller_frequncy=5"
    )
    assert bad_set.returncode == 2 and "did you mean 'controller_frequency'" in bad_set.stderr


def test_frames_prints_the_tree_and_checks_every_frame_the_params_name(capsys):
    assert main(["frames", str(TOUR)]) == 0
    out = capsys.readouterr().out
    assert out.startswith("map\n") and "laser" in out
    assert "local_costmap.local_costmap.global_frame = odom (line 244): ok" in out
    assert "docking_server.base_frame = base_link (line 547): not checked" in out
    code = main(["frames", str(TOUR), "--set", "amcl.base_frame_id=base_foot"])
    captured = capsys.readouterr()
    assert code == 2 and "amcl.base_frame_id = base_foot (line 8): MISSING" in captured.out
    assert "nav2_params.yaml:8: amcl.base_frame_id:" in captured.err
    assert "did you mean 'base_footprint'" in captured.err
