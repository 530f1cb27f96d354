"""Nav2's command chain in a mission: what the base is told keeps the velocity
smoother's limits (nav2_params.yaml: max_accel [3.0, 0, 3.5], max_velocity [0.5, 0, 2.0])."""

from __future__ import annotations

import numpy as np
import yaml

from btnav.mission import Mission, run_mission
from btnav.params import load_params

from .missions import PARAMS, write_mission


def test_the_base_never_gets_a_command_beyond_the_smoothers_limits(tmp_path):
    path = write_mission(tmp_path, "short", task={"navigate_to_pose": [3.0, 2.0, 1.57]})
    report = run_mission(Mission.load(path), tmp_path / "run")
    assert report.status == "succeeded" and report.collisions == 0
    rows = np.loadtxt(tmp_path / "run" / "trajectory.csv", delimiter=",", skiprows=1)
    t, v, w = rows[:, 0], rows[:, 10], rows[:, 11]
    m = load_params(PARAMS).server("velocity_smoother").model
    assert v.max() <= m.max_velocity[0] and v.min() >= m.min_velocity[0]
    assert np.abs(w).max() <= m.max_velocity[2]
    dt = np.diff(t)
    accel_v, accel_w = np.diff(v) / dt, np.diff(w) / dt
    assert accel_v.max() <= m.max_accel[0] + 1e-9 and accel_v.min() >= m.max_decel[0] - 1e-9
    assert np.abs(accel_w).max() <= m.max_accel[2] + 1e-9
    assert v.max() > 0.45  # it did drive at speed


def _steepest_change(tmp_path, name: str, doc: dict) -> tuple[float, float]:
    """The largest |dv/dt| and |dw/dt| the base was told in the short run with `doc`."""
    params = tmp_path / f"{name}_params.yaml"
    params.write_text(yaml.safe_dump(doc, sort_keys=False))
    path = write_mission(
        tmp_path, name, params=str(params), task={"navigate_to_pose": [3.0, 2.0, 1.57]}
    )
    report = run_mission(Mission.load(path), tmp_path / name)
    assert report.status == "succeeded" and report.collisions == 0
    rows = np.loadtxt(tmp_path / name / "trajectory.csv", delimiter=",", skiprows=1)
    dt = np.diff(rows[:, 0])
    return (
        float(np.abs(np.diff(rows[:, 10]) / dt).max()),
        float(np.abs(np.diff(rows[:, 11]) / dt).max()),
    )


def test_the_smoother_is_what_keeps_the_limits(tmp_path):
    doc = yaml.safe_load(PARAMS.read_text())
    unsmoothed = {k: v for k, v in doc.items() if k != "velocity_smoother"}
    raw_v, raw_w = _steepest_change(tmp_path, "unsmoothed", unsmoothed)
    assert max(raw_v, raw_w) > 0.5  # the controller alone changes its command faster

    limits = doc["velocity_smoother"]["ros__parameters"]
    limits["max_accel"], limits["max_decel"] = [0.5, 0.0, 0.5], [-0.5, 0.0, -0.5]
    gentle_v, gentle_w = _steepest_change(tmp_path, "gentle", doc)
    assert gentle_v <= 0.5 + 1e-9 and gentle_w <= 0.5 + 1e-9
