"""What `btnav slam` does with keys it does not act on, and with `mode: localization`.

Every such key is reported once, in `btnav params check`'s words, never dropped silently;
`mode: localization` is refused at its line rather than mapped anyway.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from btnav.cli import main
from btnav.cli.params import check_report
from btnav.slam.karto.mapper import Mapper
from btnav.slam.karto.slam_toolbox import default_slam_params

from .logs.test_log_values import carmen

CARTOGRAPHER_LUA = Path(__file__).resolve().parents[2] / "params" / "cartographer_2d.lua"

UNIMPLEMENTED = """\
slam_toolbox:
  ros__parameters:
    solver_plugin: solver_plugins::SpaSolver
    ceres_loss_function: HuberLoss
    enable_interactive_mode: true
    position_covariance_scale: 5.0
    yaw_covariance_scale: 2.0
    transform_publish_period: 0.1
    use_scan_barycenter: false
"""


def warnings_in(err: str) -> list[str]:
    return [line for line in err.splitlines() if line.startswith("btnav: warning: ")]


def test_slam_toolbox_keys_btnav_does_not_act_on_are_one_warning(tmp_path, capsys):
    params = tmp_path / "slam.yaml"
    params.write_text(UNIMPLEMENTED)
    log, _ = carmen(tmp_path)
    out = tmp_path / "out"
    assert main(["slam", str(log), "--params", str(params), "-o", str(out)]) == 0
    [warning] = warnings_in(capsys.readouterr().err)
    assert warning.startswith(
        f"btnav: warning: {params}: btnav does not implement these slam_toolbox keys and "
        "runs without them: line 3: slam_toolbox.solver_plugin: "
    )
    for line, key in enumerate(UNIMPLEMENTED.splitlines()[2:8], 3):
        assert f"line {line}: slam_toolbox.{key.split(':')[0].strip()}: " in warning
    assert "use_scan_barycenter" not in warning  # it acts (see below)
    assert (out / "map.yaml").is_file()


def test_params_check_lists_the_same_keys(tmp_path):
    params = tmp_path / "slam.yaml"
    params.write_text(UNIMPLEMENTED)
    report = check_report(params)
    assert "ignored (6):" in report
    for key in ("position_covariance_scale", "yaw_covariance_scale", "transform_publish_period"):
        assert f"slam_toolbox.{key}: " in report
    assert "use_scan_barycenter" not in report


def test_slam_without_params_or_with_acted_on_keys_warns_nothing(tmp_path, capsys):
    params = tmp_path / "slam.yaml"
    params.write_text("slam_toolbox:\n  ros__parameters:\n    minimum_travel_distance: 0.2\n")
    log, _ = carmen(tmp_path)
    for extra in ([], ["--params", str(params)]):
        assert main(["slam", str(log), *extra, "-o", str(tmp_path / "out")]) == 0
        assert warnings_in(capsys.readouterr().err) == []


def test_cartographer_options_btnav_does_not_act_on_are_one_warning(tmp_path, capsys):
    lua = tmp_path / "robot.lua"
    text = CARTOGRAPHER_LUA.read_text().replace(
        "return options",
        "POSE_GRAPH.optimization_problem.log_solver_summary = true\nreturn options",
    )
    lua.write_text(text)
    log, _ = carmen(tmp_path)
    assert main(["slam", str(log), "--lua", str(lua), "-o", str(tmp_path / "out")]) == 0
    assert warnings_in(capsys.readouterr().err) == [
        f"btnav: warning: {lua}: btnav does not implement these Cartographer options and runs "
        "without them: POSE_GRAPH.optimization_problem.log_solver_summary"
    ]


def test_mode_localization_is_refused_at_its_line_and_nothing_is_written(tmp_path, capsys):
    params = tmp_path / "slam.yaml"
    params.write_text(
        "slam_toolbox:\n  ros__parameters:\n    solver_plugin: solver_plugins::SpaSolver\n"
        "    mode: localization\n    map_file_name: /tmp/my_map\n"
    )
    log, _ = carmen(tmp_path)
    out = tmp_path / "out"
    assert main(["slam", str(log), "--params", str(params), "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1  # the error alone, no warning before it
    assert err.startswith(f"btnav: error: {params}:4: slam_toolbox.mode: btnav slam builds a map")
    assert "localization: slam" in err and "set it to mapping" in err
    assert not out.exists()


@pytest.mark.parametrize("use_barycenter", [True, False])
def test_use_scan_barycenter_chooses_karto_reference_position(use_barycenter):
    """Distances between scans (near chains, loop candidates) are measured between the
    scans' barycenters, or with `use_scan_barycenter: false` between their poses."""
    params = default_slam_params().model_copy(
        update={"use_scan_barycenter": use_barycenter, "use_scan_matching": False}
    )
    mapper = Mapper(params, np.zeros(3))
    wall = np.column_stack([np.full(5, 2.0), np.linspace(-1.0, 1.0, 5)])  # 2 m ahead
    for k, odom in enumerate([(0.0, 0.0, 0.0), (1.0, 0.0, np.pi / 2)]):
        ranges = np.hypot(*wall.T).astype(np.float32)
        assert mapper.process(float(k), odom, wall, ranges, np.arctan2(wall[:, 1], wall[:, 0]))
    expected = np.array([[2.0, 0.0], [1.0, 2.0]]) if use_barycenter else mapper.poses[:, :2]
    np.testing.assert_allclose(mapper.barycenters(), expected, atol=1e-9)
