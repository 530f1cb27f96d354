"""The compiled raytrace frees the very cells trace_flat lists (the numpy path)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from btnav.core.frames import FrameTree
from btnav.core.geometry import Pose2D
from btnav.core.messages import LaserScan
from btnav.costmap import LETHAL_OBSTACLE, CostmapROS, ObstacleLayer, VoxelLayer
from btnav.costmap.costmap_2d import Costmap2D
from btnav.costmap.obstacle_layer import free_along, trace_flat
from btnav.costmap.static_layer import interpret_values
from btnav.maps import load_map
from btnav.params.costmap import CostmapParams


def random_costs(rng: np.random.Generator, ny: int, nx: int) -> np.ndarray:
    """Costs with plenty of LETHAL, unknown and inflated cells for keep_lethal to meet."""
    return rng.choice(np.array([0, 0, 0, 100, 253, 254, 254, 255], np.uint8), size=(ny, nx))


def rays(rng: np.random.Generator, grid: Costmap2D, n: int) -> tuple[np.ndarray, ...]:
    """An origin on the map, and rays from near it to ends on and off the map (some of
    zero length, some starting beyond their end, some along cell edges)."""
    ny, nx = grid.costs.shape
    res = grid.resolution
    lo = np.array([grid.origin_x, grid.origin_y])
    size = np.array([nx * res, ny * res])
    origin = lo + rng.uniform(0.0, 1.0, 2) * size
    if rng.random() < 0.3:
        origin = lo + np.floor((origin - lo) / res) * res  # on a cell corner
    ends = lo + rng.uniform(-0.5, 1.5, (n, 2)) * size
    ends[: n // 8] = origin  # zero length
    axis = rng.integers(0, 2, n // 4 - n // 8)  # along a row or a column
    ends[n // 8 : n // 4, 0] = np.where(axis == 0, origin[0], ends[n // 8 : n // 4, 0])
    ends[n // 8 : n // 4, 1] = np.where(axis == 1, origin[1], ends[n // 8 : n // 4, 1])
    t = rng.choice([0.0, 0.0, 0.3, 1.2], n)[:, None]  # 1.2: the start beyond the end
    starts = origin + t * (ends - origin)
    return origin, starts, ends


@pytest.mark.parametrize("seed", range(40))
def test_free_along_frees_the_cells_trace_flat_lists(seed: int) -> None:
    rng = np.random.default_rng(seed)
    ny, nx = int(rng.integers(1, 90)), int(rng.integers(1, 90))
    res = float(rng.choice([0.05, 0.1, 0.025, 0.3]))
    grid = Costmap2D(random_costs(rng, ny, nx), res, *rng.uniform(-5.0, 5.0, 2))
    origin, starts, ends = rays(rng, grid, int(rng.integers(0, 400)))
    keep_lethal = bool(rng.integers(0, 2))
    numpy_grid, kernel_grid = grid.copy(), grid.copy()
    a = free_along(numpy_grid, origin, starts, ends, keep_lethal, method="numpy")
    b = free_along(kernel_grid, origin, starts, ends, keep_lethal, method="kernel")
    assert a == b == (len(trace_flat(grid, origin, starts, ends)) > 0)
    assert np.array_equal(numpy_grid.costs, kernel_grid.costs)
    if keep_lethal:
        assert np.array_equal(kernel_grid.costs == LETHAL_OBSTACLE, grid.costs == LETHAL_OBSTACLE)


def test_free_along_frees_a_long_ray_end_to_end() -> None:
    """The kernel changes what a user sees nowhere: a beam across the map frees its row."""
    grid = Costmap2D(np.full((10, 200), 255, np.uint8), 0.05)
    origin = np.array([0.01, 0.26])
    assert free_along(grid, origin, origin[None], np.array([[50.0, 0.26]]), method="kernel")
    assert (grid.costs[5] == 0).all() and (grid.costs[[4, 6]] == 255).all()


def office_like_scan(rng: np.random.Generator, beams: int = 360) -> LaserScan:
    """A lidar's scan in a cluttered room: returns 0.2-5 m, some no-returns and NaNs."""
    inc = 2 * np.pi / beams
    ranges = rng.uniform(0.2, 5.0, beams).astype(np.float32)
    ranges[rng.random(beams) < 0.1] = np.inf
    ranges[rng.random(beams) < 0.02] = np.nan
    return LaserScan(0.0, "laser", -np.pi, np.pi - inc, inc, 0.12, 8.0, ranges)


@pytest.mark.parametrize("layer_cls", [ObstacleLayer, VoxelLayer])
@pytest.mark.parametrize("rolling", [False, True])
def test_obstacle_layers_make_the_same_costmaps_either_way(layer_cls, rolling: bool) -> None:
    """A drive of 30 updates through a rolling or fixed costmap with Nav2's ranges."""
    rng = np.random.default_rng(7)
    params = CostmapParams(
        width=3 if rolling else 8, height=3 if rolling else 6, origin_x=-4.0, origin_y=-3.0,
        resolution=0.05, track_unknown_space=True, robot_radius=0.22, rolling_window=rolling,
    )  # fmt: skip
    source = {"clearing": True, "marking": True, "inf_is_valid": True, "raytrace_min_range": 0.1}
    layer_params = layer_cls.Params.model_validate({"observation_sources": "scan", "scan": source})
    costmaps = {}
    for method in ("numpy", "kernel"):
        layer = layer_cls("obstacle_layer", layer_params)
        layer.method = method
        costmaps[method] = CostmapROS("c", params, [layer])
    for step in range(30):
        tree = FrameTree.rep105()
        pose = Pose2D(-3.0 + 0.2 * step, rng.uniform(-1.0, 1.0), rng.uniform(-np.pi, np.pi))
        tree.set_transform("odom", "base_footprint", pose, 0.0)
        tree.set_static("base_link", "laser", Pose2D(0.1, 0.0, 0.0))
        scan = office_like_scan(rng)
        for cm in costmaps.values():
            cm.update(None, [scan], tree, now=float(step), force=True)
        assert np.array_equal(costmaps["numpy"].costmap.costs, costmaps["kernel"].costmap.costs)
        assert costmaps["numpy"].costmap.origin_x == costmaps["kernel"].costmap.origin_x


@pytest.mark.parametrize("name", ["tb3_sandbox", "depot", "warehouse"])
def test_free_along_clears_nav2s_maps_as_trace_flat_does(nav2_dir: Path, name: str) -> None:
    """Scans of 360 beams (Nav2's 3 m raytrace range, and longer than the map) from free
    cells of Nav2's own maps, the near part freeing all, the far part keeping LETHAL."""
    grid = load_map(nav2_dir / "maps" / f"{name}.yaml")
    base = Costmap2D(interpret_values(grid.data), grid.resolution, grid.origin.x, grid.origin.y)
    rng = np.random.default_rng(len(name))
    ys, xs = np.nonzero(base.costs == 0)
    angles = np.linspace(-np.pi, np.pi, 360, endpoint=False)
    grids = {m: base.copy() for m in ("numpy", "kernel")}
    for i in rng.integers(len(xs), size=12):
        origin = np.array(base.map_to_world((xs[i], ys[i]))) + rng.uniform(-0.02, 0.02, 2)
        near = rng.uniform(0.1, 3.0, angles.size)
        far = near + rng.uniform(0.0, 40.0, angles.size)
        heading = np.column_stack([np.cos(angles), np.sin(angles)])
        starts = origin + 0.1 * heading
        for ends, keep_lethal in ((near, False), (far, True)):
            ends = origin + ends[:, None] * heading
            listed = [free_along(g, origin, starts, ends, keep_lethal, m) for m, g in grids.items()]
            assert listed == [True, True]
        assert np.array_equal(grids["numpy"].costs, grids["kernel"].costs)
    assert (grids["kernel"].costs != base.costs).any()
