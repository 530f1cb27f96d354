"""The static layer turns map_server's map into costs, as Nav2's StaticLayer does."""

from __future__ import annotations

import numpy as np

from btnav.core.geometry import Pose2D
from btnav.costmap import (
    FREE_SPACE,
    INSCRIBED_INFLATED_OBSTACLE,
    LETHAL_OBSTACLE,
    NO_INFORMATION,
    CostmapROS,
    InflationLayer,
    StaticLayer,
    interpret_values,
)
from btnav.maps.occupancy_grid import OccupancyGrid
from btnav.params.costmap import CostmapParams


def room(resolution: float = 0.05, size: int = 80) -> OccupancyGrid:
    """A 4 m x 4 m map with a one-cell wall at x = 2.0 m and an unknown corner."""
    data = np.zeros((size, size), np.int8)
    data[:, size // 2] = 100
    data[:10, :10] = -1
    return OccupancyGrid(data, resolution, Pose2D(-1.0, -1.0, 0.0))


def global_costmap(grid: OccupancyGrid, **params) -> CostmapROS:
    p = CostmapParams(resolution=params.pop("resolution", 0.05), robot_radius=0.2, **params)
    layers = [
        StaticLayer("static_layer"),
        InflationLayer("inflation_layer", InflationLayer.Params(inflation_radius=0.5)),
    ]
    cm = CostmapROS("global_costmap", p, layers, map=grid)
    cm.update(Pose2D(0.0, 0.0, 0.0))
    return cm


def test_a_wall_is_lethal_and_inflated() -> None:
    cm = global_costmap(room(), track_unknown_space=True)
    m = cm.costmap
    assert (m.size_x, m.size_y, m.origin_x, m.origin_y) == (80, 80, -1.0, -1.0)
    wall_x = 1.0 + 0.025  # the wall cell's centre
    for y in (0.0, 1.0, 2.0):
        assert m.cost_at([[wall_x, y]])[0] == LETHAL_OBSTACLE
        assert m.cost_at([[wall_x - 0.1, y]])[0] == INSCRIBED_INFLATED_OBSTACLE
        assert 0 < m.cost_at([[wall_x - 0.35, y]])[0] < INSCRIBED_INFLATED_OBSTACLE
        assert m.cost_at([[wall_x - 0.8, y]])[0] == FREE_SPACE
    assert m.cost_at([[-0.9, -0.9]])[0] == NO_INFORMATION


def test_unknown_is_free_without_track_unknown_space() -> None:
    cm = global_costmap(room(), track_unknown_space=False)
    assert cm.costmap.cost_at([[-0.9, -0.9]])[0] == FREE_SPACE


def test_interpretation_follows_nav2() -> None:
    data = np.array([[-1, 0, 50, 64, 65, 100]], np.int8)
    trinary = interpret_values(data, lethal_cost_threshold=65)
    assert trinary.tolist() == [[255, 0, 0, 0, 254, 254]]
    scaled = interpret_values(data, lethal_cost_threshold=100, trinary_costmap=False)
    assert scaled.tolist() == [[255, 0, 127, 162, 165, 254]]
    untracked = interpret_values(data, track_unknown_space=False)
    assert untracked[0, 0] == FREE_SPACE


def test_a_finer_map_is_resampled_without_losing_thin_walls() -> None:
    fine = room(resolution=0.025, size=160)  # the same room at twice the resolution
    cm = global_costmap(fine, resolution=0.05, track_unknown_space=True)
    m = cm.costmap
    assert (m.size_x, m.size_y, m.resolution) == (80, 80, 0.05)
    # The 2.5 cm wall at x = 1.0 m still fills a whole costmap column.
    col = m.costs[:, m.world_to_map([[1.01, 0.0]])[0][0, 0]]
    assert (col == LETHAL_OBSTACLE).all()


def test_a_rolling_window_samples_the_map_under_it() -> None:
    p = CostmapParams(rolling_window=True, width=2, height=2, resolution=0.05)
    cm = CostmapROS("local_costmap", p, [StaticLayer("static_layer")], map=room())
    cm.update(Pose2D(1.0, 0.0, 0.0))
    assert cm.costmap.cost_at([[1.02, 0.0]])[0] == LETHAL_OBSTACLE
    cm.update(Pose2D(-0.5, 0.0, 0.0))
    assert cm.costmap.origin_x == -1.5
    assert not (cm.costmap.costs == LETHAL_OBSTACLE).any()  # the wall is out of the window
