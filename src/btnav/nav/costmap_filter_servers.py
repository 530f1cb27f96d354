"""The zone servers Nav2's launch brings up beside the costmaps, and their wiring to the filters.

nav2_bringup's keepout_zone_launch.py and speed_zone_launch.py start two nodes per
zone: a map_server serving the mask (`FilterMaskServer`, from a `*_filter_mask_server`
section) and a costmap_filter_info_server (`CostmapFilterInfoServer`, from a
`*_costmap_filter_info_server` section). Topics connect them in ROS; here
`bring_up_costmap_filters` connects them by the same names: each costmap filter gets the
info whose `filter_info_topic` it names, then the mask whose `topic_name` that info's
`mask_topic` names; a speed filter's limit goes to the controller_server whose
`speed_limit_topic` is the filter's. An enabled filter left without either is a located
error (Nav2 would only log "filter mask was not received" and let the robot drive
through the zone). The costmaps are updated once more at the end, so a plan at t = 0
already sees the zones.
"""

from __future__ import annotations

from dataclasses import replace
from os import PathLike
from typing import TYPE_CHECKING, Any

from ..core.errors import ParamsError
from ..costmap.costmap_ros import CostmapROS
from ..costmap.filters.costmap_filter import CostmapFilter
from ..costmap.filters.filter_info import FILTER_TYPES, CostmapFilterInfo
from ..costmap.filters.speed_filter import SpeedFilter, SpeedLimit
from ..maps.map_io import load_map
from ..maps.occupancy_grid import OccupancyGrid
from ..params.costmap_filters import CostmapFilterInfoServerParams, FilterMaskServerParams
from ..params.paramsfile import ParamsFile, ServerParams
from .map_server import MapServer

if TYPE_CHECKING:
    from .stack import NavStack


def _topic(name: str) -> str:
    """A topic as btnav matches it: btnav has no namespaces, so `/x` and `x` are one."""
    return name.strip().lstrip("/")


class FilterMaskServer(MapServer):
    """A map_server instance serving a filter mask on `topic_name`, in `frame_id`."""

    def __init__(
        self,
        name: str,
        params: FilterMaskServerParams,
        *,
        base_dir: str | PathLike[str] | None = None,
    ) -> None:
        super().__init__(params, base_dir=base_dir)
        self.name = name
        self.params: FilterMaskServerParams
        if self.map is not None:
            self.map = replace(self.map, frame_id=params.frame_id)

    @property
    def topic_name(self) -> str:
        return _topic(self.params.topic_name)

    def load_map(self, map_or_path: OccupancyGrid | str | PathLike[str]) -> OccupancyGrid:
        """Nav2's LoadMap service on this server: a new mask for its filters."""
        grid = map_or_path if isinstance(map_or_path, OccupancyGrid) else load_map(map_or_path)
        return super().load_map(replace(grid, frame_id=self.params.frame_id))

    def set_parameters(self, params: ServerParams) -> None:
        """Nav2's map_server reads its params when configured only: they are kept, not used."""
        self.params = params.model


class CostmapFilterInfoServer:
    """costmap_filter_info_server: the CostmapFilterInfo it latches on `filter_info_topic`."""

    def __init__(self, name: str, params: CostmapFilterInfoServerParams) -> None:
        self.name = name
        self.params = params
        self.info = CostmapFilterInfo(
            params.type, params.mask_topic, params.base, params.multiplier
        )

    @property
    def filter_info_topic(self) -> str:
        return _topic(self.params.filter_info_topic)

    def set_parameters(self, params: ServerParams) -> None:
        """Nav2's info server reads its params when configured only: they are kept, not used."""
        self.params = params.model


def bring_up_costmap_filters(stack: NavStack) -> None:
    """Start the file's zone servers and connect both costmaps' filters to them."""
    pf = stack.params
    masks: list[FilterMaskServer] = []
    infos: list[CostmapFilterInfoServer] = []
    for name, server in pf.servers.items():
        if isinstance(server.model, FilterMaskServerParams):
            mask_server = FilterMaskServer(name, server.model, base_dir=pf.path.parent)
            masks.append(stack.add_server(name, mask_server))
        elif isinstance(server.model, CostmapFilterInfoServerParams):
            infos.append(stack.add_server(name, CostmapFilterInfoServer(name, server.model)))
    for costmap_server in (stack.global_costmap, stack.local_costmap):
        ros = costmap_server.costmap_ros
        for costmap_filter in ros.filters:
            _connect(pf, ros, costmap_filter, infos, masks)
            if isinstance(costmap_filter, SpeedFilter):
                _connect_speed_limit(costmap_filter, stack)
        if ros.filters:
            ros.update(frame_tree=stack.runtime.frames, now=stack.runtime.now, force=True)


def _connect(
    pf: ParamsFile,
    ros: CostmapROS,
    costmap_filter: CostmapFilter,
    infos: list[CostmapFilterInfoServer],
    masks: list[FilterMaskServer],
) -> None:
    """Give `costmap_filter` its info and mask; an enabled filter that cannot have them is
    an error naming its section."""
    wanted = _topic(costmap_filter.params.filter_info_topic)
    info_server = next((s for s in infos if s.filter_info_topic == wanted), None)
    if info_server is None:
        _unless_disabled(
            pf,
            ros,
            costmap_filter,
            f"no costmap_filter_info_server publishes its filter_info_topic '{wanted}' "
            f"(the file has {_listed([s.filter_info_topic for s in infos])})",
        )
        return
    info = info_server.info
    if not costmap_filter.set_filter_info(info):
        wants = " or ".join(f"{t} ({FILTER_TYPES[t]})" for t in costmap_filter.info_types)
        _unless_disabled(
            pf,
            ros,
            costmap_filter,
            f"{info_server.name} sends type {info.type} ({FILTER_TYPES.get(info.type, '?')}) "
            f"but a {type(costmap_filter).__name__} reads type {wants}",
        )
        return
    mask_topic = _topic(info.filter_mask_topic)
    mask_server = next((s for s in masks if s.topic_name == mask_topic), None)
    if mask_server is None:
        _unless_disabled(
            pf,
            ros,
            costmap_filter,
            f"{info_server.name}'s mask_topic '{mask_topic}' is no mask server's topic_name "
            f"(the file has {_listed([s.topic_name for s in masks])})",
        )
        return
    if mask_server.map is None:
        _unless_disabled(
            pf,
            ros,
            costmap_filter,
            f"{mask_server.name} serves no mask: set its yaml_filename (a mission gives it "
            "as keepout_mask: or speed_mask:, as Nav2's launch arguments do)",
        )
    mask_server.subscribe(costmap_filter.set_mask)


def _connect_speed_limit(speed_filter: SpeedFilter, stack: NavStack) -> None:
    """The filter's limits to the controller_server listening on its speed_limit_topic."""
    controller = stack.controller_server
    listening = _topic(controller.params.model.speed_limit_topic)
    if _topic(speed_filter.params.speed_limit_topic) != listening:
        return  # as in ROS: a topic nobody subscribes to; a user may still subscribe

    def deliver(message: SpeedLimit) -> None:
        controller.set_speed_limit(message.speed_limit, message.percentage)

    speed_filter.subscribe(deliver)


def _unless_disabled(pf: ParamsFile, ros: CostmapROS, costmap_filter: Any, problem: str) -> None:
    if not costmap_filter.enabled:
        return  # a disabled filter needs nothing (Nav2's launch starts no zone servers then)
    server = pf.server(ros.name)
    section = server.plugins.get(costmap_filter.name)
    raise ParamsError(
        f"{costmap_filter.name} is enabled but {problem}",
        file=str(pf.path),
        line=section.line if section is not None else server.line,
        key=section.key if section is not None else server.key,
    )


def _listed(names: list[str]) -> str:
    return ", ".join(f"'{n}'" for n in names) if names else "none"
