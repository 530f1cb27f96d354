"""Nav2's costmap filters: keepout, speed and binary zones read from a filter mask.

A costmap's `filters: [...]` list names them; they run after its layers
(`LayeredCostmap.update_map`). Their masks and filter info come from the servers
Nav2's launch brings up beside the costmaps (`nav.costmap_filter_servers`).
"""

from .binary_filter import BinaryFilter
from .costmap_filter import CostmapFilter
from .filter_info import (
    BINARY_FILTER,
    KEEPOUT_FILTER,
    NO_SPEED_LIMIT,
    SPEED_FILTER_ABSOLUTE,
    SPEED_FILTER_PERCENT,
    CostmapFilterInfo,
    mask_cost,
)
from .keepout_filter import KeepoutFilter
from .speed_filter import SpeedFilter, SpeedLimit

__all__ = [
    "BINARY_FILTER",
    "KEEPOUT_FILTER",
    "NO_SPEED_LIMIT",
    "SPEED_FILTER_ABSOLUTE",
    "SPEED_FILTER_PERCENT",
    "BinaryFilter",
    "CostmapFilter",
    "CostmapFilterInfo",
    "KeepoutFilter",
    "SpeedFilter",
    "SpeedLimit",
    "mask_cost",
]
