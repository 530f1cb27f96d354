"""A teleop script through Nav2's AssistedTeleop (`drive: {assisted: true}`): the same
commands that drive the robot into a wall stop it short of the wall."""

from __future__ import annotations

import numpy as np
import pytest

from btnav.core.errors import BtnavError
from btnav.mission import Mission, run_mission

from .missions import write_mission

#: Straight at the x = 4 wall (its face at x = 3.95) from (1, 1): 4 m of commands.
AT_THE_WALL = [[0.4, 0.0, 10.0]]
ROBOT_RADIUS = 0.22


def _drive(tmp_path, name, drive):
    path = write_mission(tmp_path, name, task={"drive": drive}, time_limit=20)
    report = run_mission(Mission.load(path), tmp_path / name)
    rows = np.loadtxt(tmp_path / name / "trajectory.csv", delimiter=",", skiprows=1)
    return report, rows


@pytest.mark.slow
def test_assisted_teleop_stops_the_robot_short_of_the_wall_it_would_hit(tmp_path):
    plain, _ = _drive(tmp_path, "plain", AT_THE_WALL)
    assert plain.collisions > 0  # a person at the keyboard drives into the wall

    assisted, rows = _drive(tmp_path, "assisted", {"commands": AT_THE_WALL, "assisted": True})
    assert assisted.status == "succeeded" and assisted.collisions == 0
    gap = 3.95 - (rows[:, 1].max() + ROBOT_RADIUS)
    assert 0.0 < gap < 0.15, f"stopped {gap:.3f} m from the wall"
    # it slowed as it came near (the projection scales the command), not only at the end
    v = rows[:, 10]
    assert v.max() == pytest.approx(0.4, abs=0.01)
    near = rows[:, 1] > 3.95 - ROBOT_RADIUS - 0.35
    assert 0.0 < v[near].max() < 0.4
    assert abs(rows[-1, 2] - 1.0) < 0.02  # straight on


def test_an_assisted_drive_without_assisted_teleop_in_the_params_is_rejected(tmp_path):
    import yaml

    from .missions import PARAMS

    doc = yaml.safe_load(PARAMS.read_text())
    server = doc["behavior_server"]["ros__parameters"]
    server["behavior_plugins"] = [b for b in server["behavior_plugins"] if b != "assisted_teleop"]
    params = tmp_path / "params.yaml"
    params.write_text(yaml.safe_dump(doc, sort_keys=False))
    path = write_mission(
        tmp_path,
        "no_assist",
        params=str(params),
        task={"drive": {"commands": AT_THE_WALL, "assisted": True}},
    )
    report = run_mission(Mission.load(path), tmp_path / "out")
    assert report.status != "succeeded"
    assert "assisted_teleop" in (report.error_msg or report.message or "")


def test_a_misspelt_assisted_key_names_the_right_one(tmp_path):
    path = write_mission(
        tmp_path, "typo", task={"drive": {"commands": AT_THE_WALL, "asisted": True}}
    )
    with pytest.raises(BtnavError) as info:
        Mission.load(path)
    assert "assisted" in str(info.value)
