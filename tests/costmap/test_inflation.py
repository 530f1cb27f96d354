"""The inflation layer gives Nav2's costs at known distances from an obstacle."""

from __future__ import annotations

import math

import numpy as np

from btnav.core.geometry import Pose2D
from btnav.costmap import (
    INSCRIBED_INFLATED_OBSTACLE,
    LETHAL_OBSTACLE,
    NO_INFORMATION,
    CostmapLayer,
    CostmapROS,
    InflationLayer,
    inflation_cost,
)
from btnav.params.costmap import CostmapParams


class Dots(CostmapLayer):
    """A test layer: lethal at the cells it is given (and unknown where told)."""

    def __init__(self, cells=(), unknown=()):
        super().__init__("dots")
        self.cells, self.unknown = list(cells), list(unknown)

    def update_bounds(self, robot, bounds):
        bounds.cover(self.master)

    def update_costs(self, master, window):
        for mx, my in self.unknown:
            master.costs[my, mx] = NO_INFORMATION
        for mx, my in self.cells:
            master.costs[my, mx] = LETHAL_OBSTACLE


def nav2_cost(d: float, inscribed: float, scaling: float, radius: float, res: float) -> int:
    """Nav2's computeCost, written out for the test (d in metres between cell centres)."""
    if d / res > math.ceil(radius / res - 1e-9):
        return 0
    if d == 0:
        return 254
    if d <= inscribed:
        return 253
    return int(252 * math.exp(-scaling * (d - inscribed)))


def costmap_with(radius=0.7, scaling=3.0, robot_radius=0.22, **inflation):
    params = CostmapParams(width=4, height=4, resolution=0.05, robot_radius=robot_radius)
    layer = InflationLayer(
        "inflation_layer",
        InflationLayer.Params(inflation_radius=radius, cost_scaling_factor=scaling, **inflation),
    )
    dots = Dots([(40, 40)])
    cm = CostmapROS("c", params, [dots, layer])
    cm.update(Pose2D(2.0, 2.0, 0.0))
    return cm, dots


def test_formula_by_hand() -> None:
    # 252 * exp(-3 * (0.5 - 0.2)) = 102.45 -> 102, as Nav2's unsigned char cast.
    assert inflation_cost(0.5, 0.2, 3.0) == 102
    assert inflation_cost(0.0, 0.2, 3.0) == LETHAL_OBSTACLE
    assert inflation_cost(0.2, 0.2, 3.0) == INSCRIBED_INFLATED_OBSTACLE
    assert inflation_cost(0.9, 0.2, 3.0, inflation_radius=0.7) == 0


def test_costs_match_nav2_at_known_distances() -> None:
    cm, _ = costmap_with()
    costs = cm.costmap.costs
    inscribed = cm.inscribed_radius
    for dx in range(0, 18):
        for dy in (0, 3, 7):
            d = math.hypot(dx, dy) * 0.05
            want = nav2_cost(d, inscribed, 3.0, 0.7, 0.05)
            assert costs[40 + dy, 40 + dx] == want, (dx, dy)
            assert costs[40 - dy, 40 - dx] == want, (dx, dy)


def test_inscribed_radius_is_nav2s_padded_16_gon() -> None:
    cm, _ = costmap_with(robot_radius=0.22)
    # robot_radius 0.22 + footprint_padding 0.01 -> a 16-gon of radius 0.23.
    assert math.isclose(cm.circumscribed_radius, 0.23 + 0.01 * (math.sqrt(2) - 1), abs_tol=0.01)
    assert math.isclose(cm.inscribed_radius, 0.23 * math.cos(math.pi / 16), rel_tol=0.01)
    row = cm.costmap.costs[40, 40:]
    assert row[4] == 253  # 0.20 m: inside
    assert row[5] < 253  # 0.25 m: outside the inscribed radius


def test_nothing_beyond_the_inflation_radius() -> None:
    cm, _ = costmap_with(radius=0.3, scaling=1.0)
    row = cm.costmap.costs[40, 40:]
    assert row[6] > 0  # 0.30 m
    assert (row[7:] == 0).all()


def test_unknown_cells_stay_unknown_unless_inscribed() -> None:
    params = CostmapParams(width=2, height=2, resolution=0.05, robot_radius=0.1)
    unknown = [(20 + k, 20) for k in range(1, 10)]
    for inflate_unknown, expect in ((False, [253, 253, 255, 255]), (True, [253, 253, 0, 0])):
        layer = InflationLayer(
            "i", InflationLayer.Params(inflation_radius=0.5, inflate_unknown=inflate_unknown)
        )
        cm = CostmapROS("c", params, [Dots([(20, 20)], unknown), layer])
        cm.update(Pose2D(1.0, 1.0, 0.0))
        got = cm.costmap.costs[20, 21:25].tolist()
        if inflate_unknown:
            assert got[:2] == expect[:2] and all(0 < c < 253 for c in got[2:])
        else:
            assert got == expect


def test_inflate_around_unknown_seeds_from_unknown() -> None:
    params = CostmapParams(width=2, height=2, resolution=0.05, robot_radius=0.1)
    layer = InflationLayer("i", InflationLayer.Params(inflate_around_unknown=True))
    cm = CostmapROS("c", params, [Dots([], [(20, 20)]), layer])
    cm.update(Pose2D(1.0, 1.0, 0.0))
    assert cm.costmap.costs[20, 21] == 253
    # As Nav2: the unknown seed itself takes the "obstacle" cost.
    assert cm.costmap.costs[20, 20] == LETHAL_OBSTACLE


def test_changing_inflation_radius_changes_the_costmap() -> None:
    cm, _ = costmap_with(radius=0.3, scaling=1.0)
    before = int(np.count_nonzero(cm.costmap.costs))
    cm.set_parameters({"inflation_layer.inflation_radius": 0.6})
    after = int(np.count_nonzero(cm.costmap.costs))
    assert cm.layer("inflation_layer").params.inflation_radius == 0.6
    assert after > 3 * before
    assert cm.costmap.costs[40, 40 + 10] > 0  # 0.5 m now inflated


def test_removed_obstacle_loses_its_inflation() -> None:
    cm, dots = costmap_with()
    dots.cells = []
    cm.update(Pose2D(2.0, 2.0, 0.0))
    assert not cm.costmap.costs.any()
