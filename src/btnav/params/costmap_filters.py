"""Keys of the two servers a costmap filter reads: the mask server and the filter info server.

A keepout or speed zone is two nodes beside the costmaps (nav2_bringup's
keepout_zone_launch.py, speed_zone_launch.py): a map_server instance serving the mask
(`*_filter_mask_server`: `yaml_filename`, `topic_name`, `frame_id`) and a
costmap_filter_info_server (`*_costmap_filter_info_server`) telling the filter which
mask topic to read, what kind of filter it is (`type`) and how mask values become
filter values (`base + multiplier * value`). A filter finds its info server by
`filter_info_topic`; the info server's `mask_topic` is the mask server's `topic_name`.
btnav runs them under the names Nav2's launch files and tutorials give them.
"""

from __future__ import annotations

from pydantic import Field

from .map_io import MapServerParams
from .node import NodeParams

#: Nav2's node names for the zone servers: the tutorials' and nav2_bringup's launch files'.
ZONE_PREFIXES: tuple[str, ...] = ("", "keepout_", "speed_", "binary_")
FILTER_MASK_SERVERS: tuple[str, ...] = tuple(f"{p}filter_mask_server" for p in ZONE_PREFIXES)
FILTER_INFO_SERVERS: tuple[str, ...] = tuple(
    f"{p}costmap_filter_info_server" for p in ZONE_PREFIXES
)


class FilterMaskServerParams(MapServerParams):
    """A map_server serving a filter mask: an info server's `mask_topic` names its `topic_name`."""

    topic_name: str = Field("map", min_length=1)


class CostmapFilterInfoServerParams(NodeParams):
    """costmap_filter_info_server: the CostmapFilterInfo it latches on `filter_info_topic`."""

    type: int = Field(
        0,
        ge=0,
        le=4,
        description="0 keepout, 1 speed limit in %, 2 speed limit in m/s, 3 binary, "
        "4 zone parameters",
    )
    filter_info_topic: str = Field("costmap_filter_info", min_length=1)
    mask_topic: str = Field("filter_mask", min_length=1)
    base: float = 0.0
    multiplier: float = 1.0
