"""The command line as a user meets it: exit codes and one-line errors, no tracebacks."""

from __future__ import annotations

import json
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


def test_a_yaml_syntax_error_names_the_broken_line(nav2_params_file, tmp_path):
    text = nav2_params_file.read_text()
    lines = text.splitlines()
    broken = next(n for n, t in enumerate(lines) if t.endswith('["progress_checker"]'))
    lines[broken] = lines[broken].removesuffix("]")  # the list is never closed
    bad = tmp_path / "my_params.yaml"
    bad.write_text("\n".join(lines) + "\n")
    error = one_error_line(run_cli("params", "check", str(bad)))
    assert error.startswith(
        f"btnav: error: {bad}:{broken + 1}: invalid YAML: the '[' opened on this line is "
        f"not closed (expected ',' or ']', but got "
    )


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
    result = run_cli("run", str(mission), "-o", str(tmp_path / "out"))  # -o as btnav slam spells it
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
    assert "docking_server.base_frame = base_link (line 547): ok" in out
    assert "loopback_simulator.base_frame_id = base_footprint (line 594): not checked" in out
    code = main(["frames", str(TOUR), "--set", "amcl.base_frame_id=base_foot"])
    captured = capsys.readouterr()
    assert code == 2
    # The value is not on line 8 of the file: the --set that gave it is blamed.
    assert (
        "amcl.base_frame_id = base_foot (--set amcl.base_frame_id=base_foot): MISSING"
        in captured.out
    )
    assert captured.err.startswith(
        "btnav: error: --set amcl.base_frame_id=base_foot: amcl.base_frame_id: frame 'base_foot'"
    )
    assert "did you mean 'base_footprint'" in captured.err and "nav2_params" not in captured.err


# -- every problem is one line that says so ----------------------------------------------


def one_error_line(proc: subprocess.CompletedProcess[str]) -> str:
    """The command's only stderr line, checked to be an error, with exit 2 and no traceback."""
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in proc.stderr, proc.stderr
    assert lines[0].startswith("btnav: error: "), lines[0]
    return lines[0]


def test_every_command_prints_its_error_as_one_btnav_error_line(nav2_params_file, tmp_path):
    bad_params = tmp_path / "my_params.yaml"
    bad_params.write_text(
        nav2_params_file.read_text().replace("controller_frequency:", "controller_frequncy:")
    )
    mission = tmp_path / "m.yaml"
    mission.write_text(f"world: {OFFICE}\ntask:\n  navigate_to_pose: [3, 2]\nseeed: 1\n")
    errors = [
        one_error_line(run_cli("params", "check", str(bad_params))),
        one_error_line(run_cli("params", "check", "no/such/params.yaml")),
        one_error_line(run_cli("tree", "show", "navigate_w_replanning_tme")),
        one_error_line(run_cli("tree", "import", str(tmp_path / "missing.xml"))),
        one_error_line(run_cli("run", str(mission), "--out", str(tmp_path / "out"))),
        one_error_line(run_cli("run", str(TOUR), "--set", "controller_server")),
        one_error_line(run_cli("frames", str(mission))),
        one_error_line(run_cli("world", "frames", str(tmp_path / "no_world.yaml"))),
        one_error_line(run_cli("map", "from-world", str(OFFICE))),  # -o is required
        one_error_line(run_cli("run")),  # the mission is required
    ]
    assert "my_params.yaml:" in errors[0] and "did you mean 'controller_frequency'" in errors[0]
    assert "did you mean 'navigate_w_replanning_time'" in errors[2]
    assert f"{mission}:4: seeed:" in errors[4] and "did you mean 'seed'" in errors[4]
    assert errors[5] == (
        "btnav: error: --set controller_server: expected KEY=VALUE, got 'controller_server'"
    )
    assert errors[9] == (
        "btnav: error: the following arguments are required: mission (see 'btnav run --help')"
    )


def test_an_unwritable_out_folder_is_a_user_error_not_a_traceback(tmp_path, capsys):
    blocker = tmp_path / "a_file"
    blocker.write_text("not a folder")
    assert main(["run", str(TOUR), "--out", str(blocker / "out")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("btnav: error: ") and str(blocker) in err and err.count("\n") == 1


# -- a value given by --set is blamed on the --set ---------------------------------------


def test_a_wrong_set_value_names_the_set_option_not_a_file_line(capsys):
    cases = {
        "controller_server.controller_frequency=-3": (
            "btnav: error: --set controller_server.controller_frequency=-3: "
            "controller_server.controller_frequency: Input should be greater than 0"
        ),
        "local_costmap.global_frame=odm": (
            "btnav: error: --set local_costmap.global_frame=odm: "
            "local_costmap.local_costmap.global_frame: frame 'odm' is not in the robot's "
            "frame tree"
        ),
        "mission.time_limt=3": (
            "btnav: error: --set mission.time_limt=3: time_limt: unknown key 'time_limt' "
            "(did you mean 'time_limit'?)"
        ),
        "mission.initial_pose=[6.5, 1.2]": (
            "btnav: error: --set mission.initial_pose=[6.5, 1.2]: initial_pose: the initial "
            "pose [6.5, 1.2, 0] is inside an obstacle of the map ("
        ),
        "bt_navigator.default_nav_to_pose_bt_xml=navigate_w_replanning_tme": (
            "btnav: error: --set bt_navigator.default_nav_to_pose_bt_xml="
            "navigate_w_replanning_tme: bt_navigator.default_nav_to_pose_bt_xml: no tree file"
        ),
    }
    for option, expected in cases.items():
        assert main(["run", str(TOUR), "--set", option]) == 2, option
        err = capsys.readouterr().err
        assert err.startswith(expected), (option, err)
        assert err.count("\n") == 1 and "nav2_params.yaml:" not in err and ".yaml:" not in err
    assert main(["run", str(TOUR), "--seed", "-1"]) == 2
    assert capsys.readouterr().err.startswith("btnav: error: --seed -1: seed: ")


# -- btnav tree show and btnav run say the same about a tree ------------------------------


def test_tree_show_exits_2_with_the_message_run_gives_for_an_unknown_node(tmp_path):
    tree = tmp_path / "my_tree.yaml"
    tree.write_text(
        (REPO / "trees" / "navigate_w_replanning_time.yaml")
        .read_text()
        .replace("ComputePathToPose:", "ComputePathToPse:")
    )
    mission = tmp_path / "m.yaml"
    mission.write_text(
        f"world: {OFFICE}\nmap: {REPO / 'maps' / 'small_office.yaml'}\ntree: {tree}\n"
        "task:\n  navigate_to_pose: [3, 2]\n"
    )
    shown = run_cli("tree", "show", str(tree))
    ran = run_cli("run", str(mission), "--out", str(tmp_path / "out"))
    message = one_error_line(shown)
    assert message == one_error_line(ran)
    assert f"{tree}:" in message and "unknown node type 'ComputePathToPse'" in message
    assert "did you mean 'ComputePathToPose'" in message
    assert "ComputePathToPse*" in shown.stdout  # the tree as written, the bad node marked


# -- follow_waypoints with a missed waypoint, and a goal the map says is blocked -----------


def test_missed_waypoints_exit_1_and_a_goal_off_the_map_is_warned_first(tmp_path, capsys):
    mission = tmp_path / "m.yaml"
    mission.write_text(
        f"mission: two_stops\nworld: {OFFICE}\nmap: {REPO / 'maps' / 'small_office.yaml'}\n"
        "task:\n  follow_waypoints:\n    - [1.6, 1.0, 0.0]\n    - [20, 3]\n"
        "    - [6.5, 1.2, 0.0]\n"
        "time_limit: 120\noutputs: [report]\n"
    )
    out = tmp_path / "out"
    assert main(["run", str(mission), "--out", str(out)]) == 1
    captured = capsys.readouterr()
    assert captured.err.splitlines() == [
        f"btnav: warning: {mission}:7: task.follow_waypoints[1]: task pose [20, 3, 0] is "
        f"outside the map ({REPO / 'maps' / 'small_office.yaml'} covers x -0.2 to 12.2, "
        "y -0.2 to 8.2); Nav2 will try it and fail",
        f"btnav: warning: {mission}:8: task.follow_waypoints[2]: task pose [6.5, 1.2, 0] is "
        f"inside an obstacle of the map ({REPO / 'maps' / 'small_office.yaml'}); "
        "Nav2 will try it and fail",
    ]
    summary = captured.out.splitlines()[0]
    assert summary.startswith("two_stops: succeeded with 2 of 3 waypoints missed: ")
    assert "1/3 waypoints (missed [1, 2])" in summary
    report = json.loads((out / "report.json").read_text())
    assert report["status"] == "succeeded" and report["missed_waypoints"] == [1, 2]


def test_run_prints_a_line_per_missed_waypoint_under_the_result(tmp_path, capsys):
    mission = tmp_path / "m.yaml"
    mission.write_text(
        f"mission: one_miss\nworld: {OFFICE}\nmap: {REPO / 'maps' / 'small_office.yaml'}\n"
        "task:\n  follow_waypoints:\n    - [1.6, 1.0, 0.0]\n    - [20, 3]\n"
        "time_limit: 60\noutputs: [report]\n"
    )
    out = tmp_path / "out"
    assert main(["run", str(mission), "--out", str(out)]) == 1
    lines = capsys.readouterr().out.splitlines()
    (missed,) = json.loads((out / "report.json").read_text())["missed_waypoint_statuses"]
    assert lines[0].startswith("one_miss: succeeded with 1 of 2 waypoints missed: ")
    assert lines[1] == (
        "  missed waypoint 1 (20, 3, 0): error 204 GOAL_OUTSIDE_MAP "
        '"Goal coordinates of (20.000, 3.000) was outside bounds"; ComputePathToPose '
        f"failed last, at {missed['sim_time']:.1f} s sim"
    )
    assert lines[2] == f"outputs in {out}/: report.json" and len(lines) == 3


def test_run_with_strict_params_stops_at_a_key_nav2_skips(tmp_path, nav2_params_file, capsys):
    from .params.tutorial import DOCUMENTED_CRITICS, SKIPPED, line_of, with_tutorial_sections

    params = with_tutorial_sections(
        nav2_params_file, tmp_path / "tutorial.yaml", critics=DOCUMENTED_CRITICS
    )
    mission = tmp_path / "m.yaml"
    mission.write_text(
        f"world: {OFFICE}\nmap: {REPO / 'maps' / 'small_office.yaml'}\nparams: {params}\n"
        "strict_params: true\ntask:\n  navigate_to_pose: [3, 2]\n"
    )
    assert main(["run", str(mission), "--out", str(tmp_path / "out")]) == 2
    captured = capsys.readouterr()
    key = SKIPPED[0][0]
    assert captured.out == ""
    assert captured.err.splitlines() == [
        f"btnav: error: {params}:{line_of(params, key)}: {key}: Nav2 Humble's name, replaced "
        "in Iron by a list, no longer read since Jazzy; Nav2 ignores it too (current "
        f"equivalent: progress_checker_plugins) (strict_params: true in {mission} makes a key "
        "Nav2 skips an error; 12 more keys Nav2 skips)"
    ]


def test_params_check_strict_makes_a_skipped_key_an_error(tmp_path, nav2_params_file, capsys):
    from .params.tutorial import DOCUMENTED_CRITICS, with_tutorial_sections

    params = with_tutorial_sections(
        nav2_params_file, tmp_path / "tutorial.yaml", critics=DOCUMENTED_CRITICS
    )
    assert main(["params", "check", str(params)]) == 0
    capsys.readouterr()
    assert main(["params", "check", "--strict", str(params)]) == 2
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and err[0].startswith(f"btnav: error: {params}:")


def test_a_behavior_plugin_named_otherwise_than_the_tree_calls_it_says_the_fix(
    tmp_path, nav2_params_file, capsys
):
    text = nav2_params_file.read_text().replace(
        '["spin", "backup", "drive_on_heading", "assisted_teleop", "wait"]',
        '["Spin", "backup", "drive_on_heading", "assisted_teleop", "wait"]',
    )
    text = text.replace("    spin:\n      plugin:", "    Spin:\n      plugin:")
    assert '["Spin",' in text and "    Spin:" in text
    params = tmp_path / "params.yaml"
    params.write_text(text)
    mission = tmp_path / "m.yaml"
    mission.write_text(
        f"world: {OFFICE}\nmap: {REPO / 'maps' / 'small_office.yaml'}\nparams: {params}\n"
        "task:\n  navigate_to_pose: [3, 2]\n"
    )
    assert main(["run", str(mission), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1
    assert "calls the action server 'spin', but the Spin server is named 'Spin'" in err[0]
    assert "rename the plugin 'spin', or set the node's server_name=\"Spin\"" in err[0]


# -- btnav run on a terminal, and elsewhere ------------------------------------------------


def test_run_prints_only_its_result_when_stdout_is_not_a_terminal(tmp_path, capsys):
    mission = tmp_path / "m.yaml"
    mission.write_text(
        f"mission: short\nworld: {OFFICE}\nmap: {REPO / 'maps' / 'small_office.yaml'}\n"
        "task:\n  navigate_to_pose: [1.6, 1.0, 0.0]\noutputs: [report]\n"
    )
    assert main(["run", str(mission), "--out", str(tmp_path / "out")]) == 0
    captured = capsys.readouterr()
    lines = captured.out.split("\n")
    assert len(lines) == 3 and lines[2] == "" and "\r" not in captured.out
    assert lines[0].startswith("short: succeeded: ")
    assert lines[1] == f"outputs in {tmp_path / 'out'}/: report.json"
    assert captured.err == ""


# -- world warnings reach the user once --------------------------------------------------


def test_a_mover_crossing_a_wall_is_one_warning_line(tmp_path):
    world = tmp_path / "office.yaml"
    world.write_text(
        OFFICE.read_text().replace("path: [[9.0, 5.6]]", "path: [[9.0, 5.6], [9.0, 3.0]]")
    )
    proc = run_cli("world", "frames", str(world))
    assert proc.returncode == 0
    assert proc.stderr.splitlines() == [
        f"btnav: warning: {world}:31: obstacles[8].circle.moves: the route of this moving "
        "circle goes through walls[5] (line 16) on its way from (9, 5.6) to (9, 3); "
        "moving obstacles pass through whatever is in their way"
    ]
    assert run_cli("world", "frames", str(OFFICE)).stderr == ""
