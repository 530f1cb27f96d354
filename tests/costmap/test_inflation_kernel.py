"""The compiled inflation pass writes the numpy path's costs (scipy's distance transform)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from btnav.costmap import LETHAL_OBSTACLE, CostmapROS, InflationLayer
from btnav.costmap.cost_values import INSCRIBED_INFLATED_OBSTACLE
from btnav.costmap.costmap_2d import Costmap2D
from btnav.costmap.layer import Window
from btnav.costmap.static_layer import interpret_values
from btnav.maps import load_map
from btnav.params.costmap import CostmapParams


def scene(rng: np.random.Generator, ny: int, nx: int) -> np.ndarray:
    """Walls, dots and unknown patches over free and already-costed cells."""
    costs = rng.choice(np.array([0, 0, 0, 0, 0, 30, 120, 253], np.uint8), size=(ny, nx))
    costs[rng.random((ny, nx)) < rng.uniform(0.0, 0.05)] = LETHAL_OBSTACLE
    for _ in range(rng.integers(0, 4)):
        y, x = rng.integers(0, ny), rng.integers(0, nx)
        costs[y, max(x - 20, 0) : x + 20] = LETHAL_OBSTACLE  # a wall
    y, x = rng.integers(0, ny), rng.integers(0, nx)
    costs[y : y + rng.integers(1, 15), x : x + rng.integers(1, 15)] = 255  # unknown
    return costs


@pytest.mark.parametrize("seed", range(30))
def test_kernel_and_numpy_inflate_the_same(seed: int) -> None:
    rng = np.random.default_rng(seed)
    ny, nx = int(rng.integers(1, 120)), int(rng.integers(1, 120))
    res = float(rng.choice([0.05, 0.1, 0.025]))
    params = CostmapParams(width=1, height=1, resolution=res, robot_radius=rng.uniform(0.05, 0.4))
    layer = InflationLayer(
        "inflation_layer",
        InflationLayer.Params(
            inflation_radius=float(rng.choice([0.0, 0.2, 0.55, 0.7, 1.0])),
            cost_scaling_factor=float(rng.uniform(0.5, 10.0)),
            inflate_unknown=bool(rng.integers(0, 2)),
            inflate_around_unknown=bool(rng.integers(0, 2)),
        ),
    )
    CostmapROS("c", params, [layer])  # the layer's radii and resolution (not its size)
    costs = scene(rng, ny, nx)
    x0, y0 = int(rng.integers(0, nx)), int(rng.integers(0, ny))
    window = Window(x0, y0, int(rng.integers(x0 + 1, nx + 1)), int(rng.integers(y0 + 1, ny + 1)))
    out = {}
    for method in ("numpy", "kernel"):
        layer.method = method
        master = Costmap2D(costs.copy(), res)
        layer.update_costs(master, window)
        out[method] = master.costs
    assert np.array_equal(out["numpy"], out["kernel"])


def test_a_wall_is_inflated_by_the_kernel_as_nav2_does() -> None:
    """What a user sees: 254 on the wall, 253 within the inscribed radius, a decay to 0 at
    the inflation radius, on both sides of the wall."""
    params = CostmapParams(width=4, height=4, resolution=0.05, robot_radius=0.22)
    layer = InflationLayer("i", InflationLayer.Params(inflation_radius=0.7))
    cm = CostmapROS("c", params, [layer])
    costs = cm.costmap.costs
    costs[:, 40] = LETHAL_OBSTACLE
    layer.update_costs(cm.costmap, Window(0, 0, 80, 80))
    row = costs[40].astype(int)
    assert row[40] == 254 and (row[36:45] == [253] * 4 + [254] + [253] * 4).all()
    assert (np.diff(row[44:55]) <= 0).all() and row[53] > 0 and row[55] == 0
    assert (row[26:40] == row[41:55][::-1]).all()


def nav2_costmap(nav2_dir: Path, name: str) -> Costmap2D:
    """A map Nav2 ships, as a global costmap's static layer reads it (unknown kept)."""
    grid = load_map(nav2_dir / "maps" / f"{name}.yaml")
    return Costmap2D(interpret_values(grid.data), grid.resolution, grid.origin.x, grid.origin.y)


@pytest.mark.parametrize("name", ["tb3_sandbox", "depot", "warehouse"])
def test_kernel_and_numpy_inflate_nav2s_maps_the_same(nav2_dir: Path, name: str) -> None:
    """Nav2's own maps with its default inflation and variants: the whole map (as a first
    update does) and random windows (as later updates do), on grids already inflated."""
    base = nav2_costmap(nav2_dir, name)
    rng = np.random.default_rng(len(name))
    ny, nx = base.costs.shape
    variants = [
        dict(inflation_radius=0.55, cost_scaling_factor=3.0),
        dict(inflation_radius=0.7, cost_scaling_factor=10.0, inflate_around_unknown=True),
        dict(inflation_radius=0.35, cost_scaling_factor=1.0, inflate_unknown=True),
    ]
    for i, keys in enumerate(variants):
        params = CostmapParams(width=1, height=1, resolution=base.resolution, robot_radius=0.22)
        layer = InflationLayer("inflation_layer", InflationLayer.Params(**keys))
        CostmapROS("c", params, [layer])
        windows = [Window(0, 0, nx, ny)] if i == 0 or name != "warehouse" else []
        for _ in range(4):
            x0, y0 = int(rng.integers(0, nx - 10)), int(rng.integers(0, ny - 10))
            windows.append(Window(x0, y0, min(x0 + 150, nx), min(y0 + 120, ny)))
        grids = {m: base.copy() for m in ("numpy", "kernel")}
        for window in windows:
            for method, grid in grids.items():
                layer.method = method
                layer.update_costs(grid, window)
            assert np.array_equal(grids["numpy"].costs, grids["kernel"].costs)
        assert (grids["kernel"].costs == INSCRIBED_INFLATED_OBSTACLE).any()
