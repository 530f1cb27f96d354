"""Missions that map as they go: `localization: slam` and `localization: cartographer`."""

from __future__ import annotations

from pathlib import Path

import pytest
import yaml

from btnav.core.errors import BtnavError
from btnav.mission import Mission, run_mission
from btnav.sim.rasterize import rasterize
from btnav.sim.world_spec import load_world_spec
from btnav.slam.metrics import map_quality

REPO = Path(__file__).resolve().parents[2]
WORLD = REPO / "worlds" / "corridor_loop.yaml"


def mission(tmp_path: Path, **fields) -> Path:
    doc = {
        "mission": "map_lower_corridor",
        "world": str(WORLD),
        "params": str(REPO / "params" / "nav2_params.yaml"),
        "initial_pose": [1.2, 1.2, 0.0],
        "task": {"follow_waypoints": [[6.0, 1.2, 0.0], [11.0, 1.2, 0.0]]},
        "time_limit": 120,
        "outputs": ["report", "map"],
        **fields,
    }
    path = tmp_path / "mission.yaml"
    path.write_text(yaml.safe_dump(doc, sort_keys=False))
    return path


@pytest.mark.parametrize("localization", ["slam", "cartographer"])
def test_mapping_while_nav2_drives_reaches_every_goal_and_saves_the_map(tmp_path, localization):
    report = run_mission(Mission.load(mission(tmp_path, localization=localization)), tmp_path)
    assert report.status == "succeeded" and report.missed_waypoints == []
    assert report.collisions == 0
    assert report.localization_error["rms_xy"] <= 0.10
    from btnav.maps import load_map

    grid = load_map(tmp_path / "map.yaml")
    q = map_quality(grid, rasterize(load_world_spec(WORLD), 0.01), tolerance=0.10)
    assert q.occupied_near_surface >= 0.95 and q.free_is_free >= 0.98, q


def test_a_misspelt_cartographer_key_names_the_lua_line(tmp_path):
    lua = tmp_path / "robot.lua"
    text = (REPO / "params" / "cartographer_2d.lua").read_text()
    lua.write_text(
        text.replace("TRAJECTORY_BUILDER_2D.max_range", "TRAJECTORY_BUILDER_2D.max_rnage")
    )
    with pytest.raises(BtnavError) as info:
        Mission.load(mission(tmp_path, localization="cartographer", cartographer_config=str(lua)))
    err = info.value
    assert err.file == str(lua) and err.line is not None and err.suggestion == "max_range"


def test_cartographer_config_without_cartographer_is_a_mistake(tmp_path):
    with pytest.raises(BtnavError) as info:
        Mission.load(mission(tmp_path, localization="slam", cartographer_config="robot.lua"))
    assert info.value.key == "cartographer_config"
