"""Global and local costmaps built from Nav2's params: updates, rolling window, services, params."""

from __future__ import annotations

import numpy as np
import pytest

from btnav.core.errors import ParamsError
from btnav.core.geometry import Pose2D
from btnav.costmap import (
    INSCRIBED_INFLATED_OBSTACLE,
    LETHAL_OBSTACLE,
    Costmap2D,
    CostmapROS,
    InflationLayer,
    ObstacleLayer,
    StaticLayer,
    VoxelLayer,
)
from btnav.maps.occupancy_grid import OccupancyGrid
from btnav.params import load_params


@pytest.fixture(scope="module")
def nav2(nav2_params_file):
    return load_params(nav2_params_file)


def office() -> OccupancyGrid:
    """10 m x 10 m, walls round the edge, unknown outside nothing."""
    data = np.zeros((200, 200), np.int8)
    data[[0, -1], :] = 100
    data[:, [0, -1]] = 100
    return OccupancyGrid(data, 0.05, Pose2D(0.0, 0.0, 0.0))


def test_nav2_params_build_both_costmaps_with_btnav_layers(nav2) -> None:
    local = nav2.server("local_costmap")
    assert [p.cls for p in local.plugins.values() if p.list_key == "plugins"] == [
        VoxelLayer,
        InflationLayer,
    ]
    glob = nav2.server("global_costmap")
    assert [p.cls for p in glob.plugins.values() if p.list_key == "plugins"] == [
        StaticLayer,
        ObstacleLayer,
        InflationLayer,
    ]
    voxel = local.plugins["voxel_layer"].params
    assert (voxel.z_voxels, voxel.observation_sources) == (16, ["scan"])
    assert voxel.sources["scan"].raytrace_max_range == 3.0
    assert voxel.sources["scan"].clearing is True
    ignored = {e.key for e in nav2.ignored}
    assert "local_costmap.local_costmap.voxel_layer.publish_voxel_map" in ignored
    assert "local_costmap.local_costmap.voxel_layer.scan.topic" in ignored
    assert not any(".inflation_layer" in k for k in ignored)


def test_a_misspelt_source_key_is_located(nav2_params_file, tmp_path) -> None:
    lines = nav2_params_file.read_text().splitlines(keepends=True)
    line = next(i for i, t in enumerate(lines) if "raytrace_max_range: 3.0" in t) + 1
    lines[line - 1] = lines[line - 1].replace("raytrace_max_range", "raytrace_max_rang")
    path = tmp_path / "params.yaml"
    path.write_text("".join(lines))
    with pytest.raises(ParamsError) as info:
        load_params(path)
    assert info.value.line == line
    assert info.value.key == "local_costmap.local_costmap.voxel_layer.scan.raytrace_max_rang"
    assert info.value.suggestion == "raytrace_max_range"


def test_global_costmap_takes_the_map(nav2, scan_of, tree_at) -> None:
    cm = CostmapROS.from_params(nav2, "global_costmap", map=office())
    assert (cm.costmap.size_x, cm.costmap.size_y, cm.global_frame) == (200, 200, "map")
    cm.update(None, [scan_of(1.01)], tree_at(5.0, 5.0, 0.0), now=0.0)
    c = cm.costmap
    assert c.cost_at([[0.02, 5.0]])[0] == LETHAL_OBSTACLE  # the map's wall
    assert c.cost_at([[0.12, 5.0]])[0] == INSCRIBED_INFLATED_OBSTACLE
    assert c.cost_at([[6.02, 5.0]])[0] == LETHAL_OBSTACLE  # the scan's obstacle
    assert c.cost_at([[5.0, 5.0]])[0] == 0


def test_update_runs_at_update_frequency(nav2, scan_of, tree_at) -> None:
    cm = CostmapROS.from_params(nav2, "global_costmap", map=office())  # 1 Hz
    tree = tree_at(5.0, 5.0, 0.0)
    assert cm.update(None, [], tree, now=0.0)
    assert not cm.update(None, [scan_of(1.01)], tree, now=0.5)
    assert cm.costmap.cost_at([[6.02, 5.0]])[0] != LETHAL_OBSTACLE
    assert cm.update(None, [], tree, now=1.0)  # the buffered scan is used
    assert cm.costmap.cost_at([[6.02, 5.0]])[0] == LETHAL_OBSTACLE


def test_rolling_window_follows_the_robot(nav2, scan_of, tree_at) -> None:
    cm = CostmapROS.from_params(nav2, "local_costmap")
    assert (cm.costmap.size_x, cm.global_frame) == (60, "odom")
    cm.update(None, [scan_of(1.01)], tree_at(2.0, 1.0, 0.0), now=0.0)
    assert (cm.costmap.origin_x, cm.costmap.origin_y) == pytest.approx((0.5, -0.5))
    assert cm.costmap.cost_at([[3.02, 1.0]])[0] == LETHAL_OBSTACLE
    # Drive 1 m forward with nothing in view (inf, not valid): the obstacle keeps its place.
    cm.update(None, [scan_of(None)], tree_at(3.0 - 0.5, 1.0, 0.0), now=1.0)
    assert (cm.costmap.origin_x, cm.costmap.origin_y) == pytest.approx((1.0, -0.5))
    assert cm.costmap.cost_at([[3.02, 1.0]])[0] == LETHAL_OBSTACLE
    cm.update(None, [], tree_at(6.0, 1.0, 0.0), now=2.0)  # far away: off the window
    assert not (cm.costmap.costs == LETHAL_OBSTACLE).any()


def test_clear_entirely_keeps_the_static_map(nav2, scan_of, tree_at) -> None:
    cm = CostmapROS.from_params(nav2, "global_costmap", map=office())
    cm.update(None, [scan_of(1.01)], tree_at(5.0, 5.0, 0.0), now=0.0)
    assert cm.costmap.cost_at([[6.02, 5.0]])[0] == LETHAL_OBSTACLE
    cm.clear_entirely()
    assert cm.costmap.cost_at([[6.02, 5.0]])[0] == 0
    assert cm.costmap.cost_at([[0.02, 5.0]])[0] == LETHAL_OBSTACLE
    cm.update(None, [], tree_at(5.0, 5.0, 0.0), now=5.0)  # stays clear until a new scan
    assert cm.costmap.cost_at([[6.02, 5.0]])[0] == 0


def test_clear_around_robot_and_except_region(nav2, scan_of, tree_at) -> None:
    cm = CostmapROS.from_params(nav2, "global_costmap", map=office())
    tree = tree_at(5.0, 5.0, 0.0)
    near, far = [[5.52, 5.0]], [[3.48, 5.0]]
    cm.update(None, [scan_of(0.51)], tree, now=0.0, force=True)
    cm.update(None, [scan_of(1.51)], tree_at(5.0, 5.0, np.pi), now=0.0, force=True)
    assert cm.costmap.cost_at(near)[0] == cm.costmap.cost_at(far)[0] == LETHAL_OBSTACLE
    cm.clear_around_robot(2.0)  # a 2 m square round the robot
    assert cm.costmap.cost_at(near)[0] != LETHAL_OBSTACLE
    assert cm.costmap.cost_at(far)[0] == LETHAL_OBSTACLE
    cm.update(None, [scan_of(0.51)], tree, now=0.0, force=True)
    cm.clear_except_region(2.0)
    assert cm.costmap.cost_at(near)[0] == LETHAL_OBSTACLE
    assert cm.costmap.cost_at(far)[0] != LETHAL_OBSTACLE
    assert cm.costmap.cost_at([[0.02, 5.0]])[0] == LETHAL_OBSTACLE  # the map stays


def test_changing_inflation_radius_mid_run(nav2_params_file, tree_at) -> None:
    params = load_params(nav2_params_file)  # set_parameters updates the loaded file
    cm = CostmapROS.from_params(params, "global_costmap", map=office())
    cm.update(None, [], tree_at(5.0, 5.0, 0.0), now=0.0)
    probe = [[0.6, 5.0]]  # 0.575 m from the wall's cell centre
    assert cm.costmap.cost_at(probe)[0] > 0  # inflation_radius 0.7
    cm.set_parameters({"inflation_layer.inflation_radius": 0.4})
    assert cm.layer("inflation_layer").params.inflation_radius == 0.4
    assert cm.costmap.cost_at(probe)[0] == 0
    with pytest.raises(ParamsError):
        cm.set_parameters({"inflation_layer.inflation_radius": -1.0})
    assert cm.layer("inflation_layer").params.inflation_radius == 0.4


def test_robot_radius_change_moves_the_inscribed_zone(tree_at) -> None:
    cm = CostmapROS(
        "c", None, [StaticLayer("s"), InflationLayer("i")], map=office()
    )  # no params file: changes are validated by the models
    cm.update(Pose2D(5.0, 5.0, 0.0))
    probe = [[0.27, 5.0]]
    assert cm.costmap.cost_at(probe)[0] < INSCRIBED_INFLATED_OBSTACLE
    cm.set_parameters({"robot_radius": 0.3})
    assert cm.costmap.cost_at(probe)[0] == INSCRIBED_INFLATED_OBSTACLE


def test_costmap2d_update_origin_keeps_cells_in_place() -> None:
    m = Costmap2D.empty(10, 10, 0.5, 0.0, 0.0, default_value=0)
    m.costs[5, 5] = 254  # world (2.75, 2.75)
    m.update_origin(1.2, 0.6)  # moves by whole cells: (1.0, 0.5)
    assert (m.origin_x, m.origin_y) == (1.0, 0.5)
    assert m.cost_at([[2.75, 2.75]])[0] == 254
    assert int(m.costs.sum()) == 254
    m.update_origin(100.0, 0.0)
    assert not m.costs.any()
