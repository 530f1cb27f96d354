"""What a costmap filter is told about its mask (nav2_msgs/CostmapFilterInfo), and the
arithmetic that turns mask values into costs and filter values (Nav2's filter_values.hpp).

A mask is an OccupancyGrid (-1 unknown, 0..100). A keepout filter reads a mask value
as a cost, 0..100 scaled linearly onto FREE_SPACE..LETHAL_OBSTACLE; a speed or binary
filter reads it as a number in its own space, `base + multiplier * value`, with `base`
and `multiplier` from the filter info server (float32 in the message, as Nav2 sends them).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..cost_values import FREE_SPACE, LETHAL_OBSTACLE, NO_INFORMATION

#: CostmapFilterInfo.type values (costmap_filter_info_server's `type`).
KEEPOUT_FILTER = 0
SPEED_FILTER_PERCENT = 1
SPEED_FILTER_ABSOLUTE = 2
BINARY_FILTER = 3
ZONE_PARAMETER_FILTER = 4

FILTER_TYPES: dict[int, str] = {
    KEEPOUT_FILTER: "keepout",
    SPEED_FILTER_PERCENT: "speed limit in % of the maximum speed",
    SPEED_FILTER_ABSOLUTE: "speed limit in m/s",
    BINARY_FILTER: "binary",
    ZONE_PARAMETER_FILTER: "zone parameters",
}

BASE_DEFAULT = 0.0
MULTIPLIER_DEFAULT = 1.0
#: Speed mask values with a meaning of their own: unknown keeps the last limit, 0 lifts it.
SPEED_MASK_UNKNOWN = -1
SPEED_MASK_NO_LIMIT = 0
#: The speed limit that means "no limit" (nav2_msgs/SpeedLimit's convention).
NO_SPEED_LIMIT = 0.0

#: OccupancyGrid values (nav2_util's occ_grid_values).
OCC_GRID_UNKNOWN = -1
OCC_GRID_FREE = 0
OCC_GRID_OCCUPIED = 100


@dataclass(frozen=True)
class CostmapFilterInfo:
    """nav2_msgs/CostmapFilterInfo: the latched message a costmap_filter_info_server sends."""

    type: int = KEEPOUT_FILTER
    filter_mask_topic: str = "filter_mask"
    base: float = BASE_DEFAULT
    multiplier: float = MULTIPLIER_DEFAULT

    def __post_init__(self) -> None:
        # The message carries float32: a filter computes with what arrives, not what was written.
        object.__setattr__(self, "base", float(np.float32(self.base)))
        object.__setattr__(self, "multiplier", float(np.float32(self.multiplier)))

    def filter_value(self, data: ArrayLike) -> NDArray[np.float64]:
        """Mask values in the filter's space: `base + multiplier * value` (unknown included:
        each filter decides what an unknown cell means before it asks)."""
        return np.asarray(data, dtype=np.float64) * self.multiplier + self.base


def mask_cost(data: ArrayLike) -> NDArray[np.uint8]:
    """Mask values -> costs, as Nav2's CostmapFilter::getMaskCost: unknown is NO_INFORMATION,
    0..100 maps linearly onto 0..254 rounded half away from zero (std::round)."""
    d = np.asarray(data, dtype=np.int16)
    scaled = d * float(LETHAL_OBSTACLE - FREE_SPACE) / float(OCC_GRID_OCCUPIED - OCC_GRID_FREE)
    rounded = np.sign(scaled) * np.floor(np.abs(scaled) + 0.5)
    out = rounded.astype(np.int64) & 0xFF  # an unsigned char, as Nav2 stores it
    return np.where(d == OCC_GRID_UNKNOWN, NO_INFORMATION, out).astype(np.uint8)
