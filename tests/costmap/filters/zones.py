"""Small scenes for filter tests: a room, a mask with one zone, costmaps with filters."""

from __future__ import annotations

import numpy as np

from btnav.core.geometry import Pose2D
from btnav.costmap import CostmapROS, InflationLayer, StaticLayer
from btnav.costmap.filters import CostmapFilter, CostmapFilterInfo
from btnav.maps.occupancy_grid import OccupancyGrid
from btnav.params.costmap import CostmapParams

RES = 0.05
SIZE = 200  # cells: a 10 m x 10 m room
#: The zone: x 4..6 m, y 4..6 m.
ZONE = (slice(80, 120), slice(80, 120))


def room() -> OccupancyGrid:
    data = np.zeros((SIZE, SIZE), np.int8)
    data[[0, -1], :] = 100
    data[:, [0, -1]] = 100
    return OccupancyGrid(data, RES, Pose2D(0.0, 0.0, 0.0))


def zone_mask(value: int, rest: int = 0, frame_id: str = "map") -> OccupancyGrid:
    """A mask the size of the room: `value` in the zone, `rest` elsewhere."""
    data = np.full((SIZE, SIZE), rest, np.int8)
    data[ZONE] = value
    return OccupancyGrid(data, RES, Pose2D(0.0, 0.0, 0.0), frame_id)


def costmap_with(
    costmap_filter: CostmapFilter,
    info: CostmapFilterInfo,
    mask: OccupancyGrid,
    *,
    rolling: bool = False,
    frame: str = "map",
) -> CostmapROS:
    """A costmap (static + inflation, or a rolling 3 m window) with `costmap_filter` fed."""
    if rolling:
        params = CostmapParams(
            global_frame=frame, rolling_window=True, width=3, height=3, resolution=RES
        )
        layers = [InflationLayer("inflation_layer")]
    else:
        params = CostmapParams(global_frame=frame, resolution=RES, robot_radius=0.22)
        # footprint clearing makes every update touch the robot's cells, as an obstacle
        # layer's scans do: a costmap with nothing to update runs no filter, as in Nav2
        static = StaticLayer("static_layer", StaticLayer.Params(footprint_clearing_enabled=True))
        layers = [static, InflationLayer("inflation_layer")]
    ros = CostmapROS(
        "costmap", params, layers, map=None if rolling else room(), filters=[costmap_filter]
    )
    assert costmap_filter.set_filter_info(info)
    costmap_filter.set_mask(mask)
    return ros
