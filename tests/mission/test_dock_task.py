"""A mission's `task: {dock: ...}`: nav2_simple_commander's dockRobotByID / dockRobotByPose."""

from __future__ import annotations

from pathlib import Path

import pytest

from btnav.mission import Mission, MissionError

REPO = Path(__file__).resolve().parents[2]


def mission_file(tmp_path: Path, task: str, params: str = "nav2_params_dock.yaml") -> Path:
    path = tmp_path / "m.yaml"
    path.write_text(
        f"world: {REPO / 'worlds' / 'office_dock.yaml'}\n"
        f"params: {REPO / 'params' / params}\n"
        f"map: {REPO / 'maps' / 'small_office.yaml'}\n"
        f"task:\n  dock: {task}\n"
    )
    return path


def test_the_bundled_dock_mission_loads_with_its_dock_id():
    mission = Mission.load(REPO / "missions" / "office_dock.yaml")
    assert mission.task == "dock" and mission.spec.task.dock.dock_id == "home_dock"
    assert mission.spec.task.poses == []


def test_a_dock_task_gives_an_id_or_a_pose_not_both(tmp_path):
    with pytest.raises(MissionError, match=r"dock_id .* or dock_pose") as info:
        Mission.load(mission_file(tmp_path, "{dock_id: home_dock, dock_pose: [1, 2, 0]}"))
    assert info.value.line == 5
    by_pose = Mission.load(mission_file(tmp_path, "{dock_pose: [11.6, 1.0], dock_type: x}"))
    assert by_pose.spec.task.dock.dock_pose == (11.6, 1.0, 0.0)


def test_a_misspelt_dock_key_names_the_right_one(tmp_path):
    with pytest.raises(MissionError) as info:
        Mission.load(mission_file(tmp_path, "{dock_di: home_dock}"))
    assert info.value.suggestion == "dock_id"


def test_a_dock_task_needs_a_docking_server(tmp_path):
    params = tmp_path / "no_docking.yaml"
    text = (REPO / "params" / "nav2_params.yaml").read_text()
    params.write_text(
        text[: text.index("docking_server:")] + text[text.index("loopback_simulator:") :]
    )
    with pytest.raises(MissionError, match="needs the docking_server") as info:
        Mission.load(mission_file(tmp_path, "{dock_id: home_dock}", params=str(params)))
    assert info.value.key == "task.dock"
