"""Missions that map as they go: `localization: slam` and `localization: cartographer`.

Nav2 drives them with Regulated Pure Pursuit (params/nav2_params_rpp.yaml: Nav2's params
with RPP's documented section) rather than MPPI: the mapping, not the controller, is what
these tests judge, and MPPI was ~60% of their CPU (44 -> 17 s). With RPP they pass on
seeds 0-2 with wide margins (the mapping runs: 0.4-2.8 cm RMS against 10 cm, every
occupied cell near a wall, >= 99.3% of the free cells free against 98%).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import yaml

from btnav.core.errors import BtnavError
from btnav.mission import Mission, run_mission
from btnav.sim.rasterize import rasterize
from btnav.sim.world_spec import load_world_spec
from btnav.testing.slam_metrics import map_quality

REPO = Path(__file__).resolve().parents[2]
WORLD = REPO / "worlds" / "corridor_loop.yaml"
PARAMS = REPO / "params" / "nav2_params_rpp.yaml"  # see the module's docstring


def mission(tmp_path: Path, **fields) -> Path:
    doc = {
        "mission": "map_lower_corridor",
        "world": str(WORLD),
        "params": str(PARAMS),
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


# -- the pose graph: saved by one mission, loaded by the next ------------------------------


def slam_params(folder: Path, **keys) -> Path:
    """PARAMS with slam_toolbox's own section (mapper_params_online_async), `keys` set."""
    doc = yaml.safe_load(PARAMS.read_text())
    slam = yaml.safe_load((REPO / "params" / "mapper_params_online_async.yaml").read_text())
    slam["slam_toolbox"]["ros__parameters"].update(keys)
    path = folder / "params.yaml"
    path.write_text(yaml.safe_dump({**doc, **slam}, sort_keys=False))
    return path


@pytest.fixture(scope="module")
def mapped(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A mission that maps the lower corridor to x = 7 m and saves its map and pose graph."""
    first = tmp_path_factory.mktemp("first")
    task = {"follow_waypoints": [[7.0, 1.2, 0.0]]}
    spec = mission(first, localization="slam", task=task, outputs=["map", "pose_graph"])
    assert run_mission(Mission.load(spec), first).status == "succeeded"
    assert (first / "pose_graph.npz").is_file()
    return first


def test_a_mission_s_pose_graph_is_what_mode_localization_localises_on(mapped, tmp_path):
    # slam_toolbox's map_file_name: the file's name without its extension
    params = slam_params(tmp_path, mode="localization", map_file_name=str(mapped / "pose_graph"))
    task = {"navigate_to_pose": [4.0, 1.2, 0.0]}
    spec = mission(tmp_path, localization="slam", params=str(params), task=task)
    report = run_mission(Mission.load(spec), tmp_path)
    assert report.status == "succeeded" and report.collisions == 0
    assert report.localization_error["rms_xy"] <= 0.05, report.localization_error
    # the map it drove on is the first mission's, not one of its own: driving to x = 4 m
    # with an 8 m lidar, it would have seen no further than x = 12.1 m
    from btnav.maps import load_map

    made, used = load_map(mapped / "map.yaml"), load_map(tmp_path / "map.yaml")
    assert used.size_m[0] >= made.size_m[0] > 13.0


@pytest.mark.slow
def test_a_mapping_mission_goes_on_from_a_saved_pose_graph(mapped, tmp_path):
    params = slam_params(tmp_path, mode="mapping", map_file_name=str(mapped / "pose_graph"))
    # x = 12.5 m is on the saved map, beyond what the lidar sees from the start (9.3 m)
    task = {"navigate_to_pose": [12.5, 1.2, 0.0]}
    spec = mission(
        tmp_path, localization="slam", params=str(params), task=task, outputs=["pose_graph"]
    )
    report = run_mission(Mission.load(spec), tmp_path)
    assert report.status == "succeeded" and report.collisions == 0, report.error_msg
    assert report.localization_error["rms_xy"] <= 0.10, report.localization_error
    with np.load(mapped / "pose_graph.npz") as a, np.load(tmp_path / "pose_graph.npz") as b:
        old, grown = a["stamps"], b["stamps"]
        assert len(grown) > len(old) + 10
        assert (grown[: len(old)] == old).all()  # the saved nodes, then the new ones
        assert b["graph_poses"][len(old) :, 0].max() > 11.0  # mapped on past x = 7 m
        new_to_old = (b["graph_edge_i"] < len(old)) != (b["graph_edge_j"] < len(old))
        assert new_to_old.any()  # linked to the saved graph, not a second one beside it


@pytest.mark.parametrize("localization", ["ground_truth", "cartographer"])
def test_a_pose_graph_from_a_localiser_without_one_names_the_output(tmp_path, localization):
    fields = {"localization": localization, "outputs": ["report", "pose_graph"]}
    if localization == "ground_truth":
        fields["map"] = str(REPO / "maps" / "small_office.yaml")
    path = mission(tmp_path, **fields)
    line = next(n for n, t in enumerate(path.read_text().splitlines(), 1) if "pose_graph" in t)
    with pytest.raises(BtnavError, match="needs localization: slam") as info:
        Mission.load(path)
    err = info.value
    assert err.file == str(path) and err.line == line and err.key == "outputs[1]"
