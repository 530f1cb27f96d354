"""KeepoutZonesLayer: zones in the master grid, inflated, kept through clears, changed live."""

from __future__ import annotations

import numpy as np
import pytest
from btnav.core.errors import ParamsError
from btnav.core.geometry import Pose2D
from btnav.costmap import CostmapROS, InflationLayer
from btnav.costmap.cost_values import (
    FREE_SPACE,
    INSCRIBED_INFLATED_OBSTACLE,
    LETHAL_OBSTACLE,
    NO_INFORMATION,
)
from btnav.params import load_params
from btnav.params.costmap import CostmapParams

from btnav_example.keepout_zones_layer import KeepoutZonesLayer

from .conftest import EXAMPLE_PARAMS

KEEPOUT = "[[1.0, 1.0], [2.0, 1.0], [2.0, 2.0], [1.0, 2.0]]"
SLOW = "[[3.0, 3.0], [4.0, 3.0], [4.0, 4.0]]"


def costmap(**layer_params) -> CostmapROS:
    """A 5 x 5 m free global costmap with the zones layer and an inflation layer after it."""
    params = CostmapParams(width=5, height=5, resolution=0.1, robot_radius=0.2)
    zones = KeepoutZonesLayer("keepout_layer", KeepoutZonesLayer.Params(**layer_params))
    inflation = InflationLayer("inflation_layer", InflationLayer.Params(inflation_radius=0.5))
    cm = CostmapROS("global_costmap", params, [zones, inflation])
    cm.update(Pose2D(0.5, 0.5, 0.0), force=True)
    return cm


def at(cm: CostmapROS, x: float, y: float) -> int:
    return int(cm.costmap.cost_at_point(x, y))


def test_keepout_zones_are_lethal_and_inflated_slow_zones_costly():
    cm = costmap(keepout_zones=[KEEPOUT], slow_zones=[SLOW], slow_zone_cost=120)
    assert at(cm, 1.5, 1.5) == LETHAL_OBSTACLE
    assert at(cm, 2.15, 1.5) == INSCRIBED_INFLATED_OBSTACLE  # within the robot's radius
    assert FREE_SPACE < at(cm, 2.35, 1.5) < INSCRIBED_INFLATED_OBSTACLE
    assert at(cm, 3.8, 3.2) == 120  # inside the triangle
    assert at(cm, 3.2, 3.8) == FREE_SPACE  # outside it
    assert at(cm, 4.5, 0.5) == FREE_SPACE


def test_the_layer_has_no_say_outside_its_zones():
    """NO_INFORMATION outside the zones: an unknown master cell stays unknown there."""
    params = CostmapParams(width=5, height=5, resolution=0.1, track_unknown_space=True)
    zones = KeepoutZonesLayer("keepout_layer", KeepoutZonesLayer.Params(keepout_zones=[KEEPOUT]))
    cm = CostmapROS("global_costmap", params, [zones])
    cm.update(Pose2D(), force=True)
    assert at(cm, 1.5, 1.5) == LETHAL_OBSTACLE
    assert at(cm, 3.5, 3.5) == NO_INFORMATION


def test_clearing_the_costmap_never_opens_a_zone():
    cm = costmap(keepout_zones=[KEEPOUT])
    cm.clear_around_pose(Pose2D(1.5, 1.5, 0.0), reset_distance=2.0)
    assert at(cm, 1.5, 1.5) == LETHAL_OBSTACLE
    cm.clear_entirely()
    assert at(cm, 1.5, 1.5) == LETHAL_OBSTACLE


def test_zones_change_while_running_as_nav2s_dynamic_parameters():
    cm = costmap(keepout_zones=[KEEPOUT])
    cm.set_parameters({"keepout_layer.keepout_zones": ["[[3, 3], [4, 3], [4, 4], [3, 4]]"]})
    assert at(cm, 3.5, 3.5) == LETHAL_OBSTACLE
    assert at(cm, 1.5, 1.5) == FREE_SPACE
    cm.set_parameters({"keepout_layer.enabled": False})
    assert at(cm, 3.5, 3.5) == FREE_SPACE


def test_on_a_rolling_window_the_zone_stays_where_it_is_in_the_world():
    params = CostmapParams(
        width=3, height=3, resolution=0.1, rolling_window=True, global_frame="odom"
    )
    zones = KeepoutZonesLayer("keepout_layer", KeepoutZonesLayer.Params(keepout_zones=[KEEPOUT]))
    cm = CostmapROS("local_costmap", params, [zones])
    for x in (-0.5, 0.7, 1.4, 3.5):
        cm.update(Pose2D(x, 1.5, 0.0), force=True)
        costs = cm.costmap.cost_at(np.array([[1.5, 1.5], [1.05, 1.95], [2.3, 1.5]]))
        inside_window = abs(1.5 - x) < 1.5  # the 3 m window is centred on the robot
        assert costs[0] == (LETHAL_OBSTACLE if inside_window else NO_INFORMATION)
        assert costs[2] != LETHAL_OBSTACLE


def test_the_example_params_put_the_zones_in_the_office(office_costmap):
    assert at(office_costmap, 7.05, 2.25) == LETHAL_OBSTACLE  # between the table and pillar
    assert at(office_costmap, 2.1, 1.9) == 150  # the slow zone by the cabinet
    names = [layer.name for layer in office_costmap.layers]
    assert names.index("keepout_layer") < names.index("inflation_layer")


def test_a_polygon_needs_three_points(tmp_path):
    text = EXAMPLE_PARAMS.read_text().replace(
        '"[[1.6, 1.4], [2.6, 1.4], [2.6, 2.4], [1.6, 2.4]]"', '"[[1.6, 1.4], [2.6, 1.4]]"'
    )
    (tmp_path / "params.yaml").write_text(text)
    with pytest.raises(ParamsError, match="at least 3 points") as info:
        load_params(tmp_path / "params.yaml")
    assert "keepout_layer.slow_zones" in str(info.value)
