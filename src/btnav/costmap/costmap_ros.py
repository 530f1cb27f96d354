"""Nav2's Costmap2DROS: the costmap server a Nav2 user configures.

`CostmapROS` (alias `Costmap2DROS`) is built from a `global_costmap`/`local_costmap`
params section, updated at `update_frequency` from the robot pose, scans and the frame
tree, with the clear-costmap services and dynamic parameters. It treats every layer
alike, through `Layer`'s hooks (a new map, a new scan, `is_current`, `reset`): a
user's layer gets what a built-in one gets. The sections its `filters` list names are
costmap filters (`costmap.filters`), run after the layers.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from typing import Any

import numpy as np
import pydantic
from numpy.typing import NDArray

from ..core.errors import ParamsError
from ..core.frames import FrameTree
from ..core.geometry import Pose2D
from ..core.messages import LaserScan
from ..maps.occupancy_grid import OccupancyGrid
from ..params.costmap import CostmapParams
from ..params.paramsfile import ParamsFile, ServerParams
from ..params.schema import field_named_list, validate_section
from .costmap_2d import Costmap2D
from .filters.costmap_filter import CostmapFilter
from .inflation_layer import InflationLayer, inflation_cost
from .layer import Layer, Window
from .layered_costmap import LayeredCostmap, robot_footprint


def _as_section(model: pydantic.BaseModel) -> dict[str, Any]:
    """A model back as the params section it came from (named sub-sections un-gathered)."""
    out: dict[str, Any] = {}
    for name, info in type(model).model_fields.items():
        value = getattr(model, name)
        if field_named_list(info) is not None:
            for sub_name, sub in (value or {}).items():
                out[sub_name] = _as_section(sub) if isinstance(sub, pydantic.BaseModel) else sub
            continue
        out[info.alias or name] = (
            _as_section(value) if isinstance(value, pydantic.BaseModel) else value
        )
    return out


def _set_dotted(section: dict[str, Any], parts: Sequence[str], value: Any) -> None:
    node = section
    for part in parts[:-1]:
        node = node.setdefault(part, {})
        if not isinstance(node, dict):
            raise ParamsError(f"'{part}' is a value, not a section", key=".".join(parts))
    node[parts[-1]] = value


class CostmapROS:
    """A costmap server: Nav2's Costmap2DROS (`global_costmap`, `local_costmap`).

    Build it from a params file (`CostmapROS.from_params(params, "local_costmap")`)
    or from a `CostmapParams` model and layer instances. `costmap` is the master
    `Costmap2D` planners and controllers read.
    """

    def __init__(
        self,
        name: str = "costmap",
        params: CostmapParams | None = None,
        layers: Iterable[Layer] = (),
        *,
        map: OccupancyGrid | None = None,
        params_file: ParamsFile | None = None,
        filters: Iterable[CostmapFilter] = (),
    ) -> None:
        self.name = name
        self.params = params if params is not None else CostmapParams()
        self.params_file = params_file
        self.layered = LayeredCostmap(self.params)
        self.layered.set_footprint(robot_footprint(self.params))
        for layer in layers:
            self.layered.add_layer(layer)
        for costmap_filter in filters:
            self.layered.add_filter(costmap_filter)
        self.last_robot_pose: Pose2D | None = None
        self.last_update: float | None = None
        self.map: OccupancyGrid | None = None
        if map is not None:
            self.set_map(map)

    @classmethod
    def from_params(
        cls,
        params: ParamsFile,
        name: str = "global_costmap",
        *,
        map: OccupancyGrid | None = None,
    ) -> CostmapROS:
        """The costmap `name` of a loaded params file, its layers in `plugins` order and
        its filters in `filters` order."""
        server = params.server(name)
        return cls(
            name,
            server.model,
            _layers_of(server),
            map=map,
            params_file=params,
            filters=_filters_of(server),
        )

    # -- what users read --------------------------------------------------------------------

    @property
    def costmap(self) -> Costmap2D:
        return self.layered.costmap

    @property
    def global_frame(self) -> str:
        return self.params.global_frame

    @property
    def robot_base_frame(self) -> str:
        return self.params.robot_base_frame

    @property
    def layers(self) -> list[Layer]:
        return self.layered.layers

    def layer(self, name: str) -> Layer:
        return self.layered.layer(name)

    @property
    def filters(self) -> list[CostmapFilter]:
        return self.layered.filters

    def filter(self, name: str) -> CostmapFilter:
        return self.layered.filter(name)

    @property
    def footprint(self) -> NDArray[np.float64]:
        """The padded footprint in the robot frame."""
        return self.layered.footprint

    def oriented_footprint(self, pose: Pose2D) -> NDArray[np.float64]:
        return pose.transform_points(self.layered.footprint)

    @property
    def inscribed_radius(self) -> float:
        return self.layered.inscribed_radius

    @property
    def circumscribed_radius(self) -> float:
        return self.layered.circumscribed_radius

    @property
    def use_radius(self) -> bool:
        """Whether the footprint is the circle of `robot_radius` (no `footprint` given)."""
        return len(self.params.footprint) == 0

    def inflation_layer(self, name: str = "") -> InflationLayer | None:
        """Nav2's InflationLayerInterface::getInflationLayer: the layer called `name`, or
        with no name the first inflation layer; None if there is none."""
        for layer in self.layers:
            if isinstance(layer, InflationLayer) and (not name or layer.name == name):
                return layer
        return None

    def circumscribed_cost(self, inflation_layer_name: str = "") -> float:
        """The inflation cost at the circumscribed radius (Nav2's findCircumscribedCost): a
        cell cheaper than this cannot put any part of the footprint on an obstacle, so
        only dearer ones need the footprint checked. -1 without an inflation layer."""
        layer = self.inflation_layer(inflation_layer_name)
        if layer is None:
            return -1.0
        return float(
            inflation_cost(
                self.circumscribed_radius, self.inscribed_radius, layer.params.cost_scaling_factor
            )
        )

    @property
    def update_period(self) -> float:
        return 1.0 / self.params.update_frequency

    def get_robot_pose(self, frame_tree: FrameTree) -> Pose2D:
        return frame_tree.lookup(self.global_frame, self.robot_base_frame)

    def is_current(self, now: float) -> bool:
        return all(
            layer.is_current(now) for layer in [*self.layers, *self.filters] if layer.enabled
        )

    # -- inputs ---------------------------------------------------------------------------

    def set_map(self, grid: OccupancyGrid) -> None:
        """map_server's map (or SLAM's), offered to every layer (the static layer takes it)."""
        self.map = grid
        for layer in self.layers:
            layer.set_map(grid)

    def receive_scan(self, scan: LaserScan, frame_tree: FrameTree) -> None:
        """A scan, offered to every layer (obstacle and voxel layers buffer it until update)."""
        self.layered.frame_tree = frame_tree
        for layer in self.layers:
            layer.receive_scan(scan, frame_tree, global_frame=self.global_frame)

    def update(
        self,
        robot_pose: Pose2D | None = None,
        scans: Iterable[LaserScan] = (),
        frame_tree: FrameTree | None = None,
        now: float | None = None,
        *,
        force: bool = False,
    ) -> bool:
        """Take the scans; update the costmap if `update_frequency` says it is due (or `force`).

        `robot_pose` is the robot in the global frame; without it the frame tree gives it.
        Returns whether the costmap was updated.
        """
        if isinstance(scans, LaserScan):
            scans = [scans]
        for scan in scans:
            if frame_tree is None:
                raise ValueError("scans need the frame tree to be placed in the costmap")
            self.receive_scan(scan, frame_tree)
        if frame_tree is not None:
            self.layered.frame_tree = frame_tree
        if (
            not force
            and now is not None
            and self.last_update is not None
            and now < self.last_update + self.update_period - 1e-9
        ):
            return False
        if robot_pose is None:
            if frame_tree is None:
                raise ValueError("give the robot pose or the frame tree to find it")
            robot_pose = self.get_robot_pose(frame_tree)
        self.layered.update_map(robot_pose)
        self.last_robot_pose = robot_pose
        if now is not None:
            self.last_update = now
        return True

    def refresh(self) -> None:
        """Recompute the whole master grid from the layers (after a clear or a param change)."""
        pose = self.last_robot_pose
        if pose is None:
            if not self.layered.rolling_window:
                self.layered.update_map(Pose2D(), full=True)
            return
        self.layered.update_map(pose, full=True)

    # -- services (nav2_costmap_2d ClearCostmapService) -----------------------------------

    def clear_entirely(self) -> None:
        """Reset the master and every layer; the static map comes back, sensed obstacles do not."""
        self.layered.reset_layers()
        self.refresh()

    def clear_around_robot(self, reset_distance: float = 1.0) -> None:
        """Clear clearable layers inside the square of side `reset_distance` centred on the robot."""
        self._clear_region(self.last_robot_pose, reset_distance, invert=False)

    def clear_except_region(self, reset_distance: float = 1.0) -> None:
        """Clear clearable layers outside the square of side `reset_distance` round the robot."""
        self._clear_region(self.last_robot_pose, reset_distance, invert=True)

    def clear_around_pose(self, pose: Pose2D, reset_distance: float = 1.0) -> None:
        """Nav2's ClearCostmapAroundPose: as clear_around_robot, round any pose."""
        self._clear_region(pose, reset_distance, invert=False)

    def _clear_region(self, pose: Pose2D | None, reset_distance: float, invert: bool) -> None:
        if pose is None:
            pose = Pose2D()
        m = self.costmap
        half = reset_distance / 2.0
        sx, sy = m.world_to_map_enforce_bounds(pose.x - half, pose.y - half)
        ex, ey = m.world_to_map_enforce_bounds(pose.x + half, pose.y + half)
        # Nav2 clears the cells strictly between the two corner cells.
        window = Window(sx + 1, sy + 1, max(ex, sx + 1), max(ey, sy + 1))
        for layer in self.layers:
            if layer.is_clearable():
                layer.clear_area(window, invert)
        self.refresh()

    # -- dynamic parameters -------------------------------------------------------------------

    def set_parameters(self, changes: Mapping[str, Any] | ServerParams) -> None:
        """Change params while running, as Nav2's dynamic parameters.

        `changes` is `{"inflation_layer.inflation_radius": 0.5, "robot_radius": 0.3}`
        (validated like the file; nothing changes if one value is wrong) or the
        `ServerParams` that `btnav.params.validate_update` returned.
        """
        if isinstance(changes, ServerParams):
            self._apply(changes.model, {n: p.params for n, p in changes.plugins.items()})
            return
        if self.params_file is not None:
            from ..params.updates import validate_update

            server = validate_update(self.params_file, self.name, changes)
            self._apply(server.model, {n: p.params for n, p in server.plugins.items()})
            return
        own: dict[str, Any] = _as_section(self.params)
        plugins = [*self.layers, *self.filters]
        sections = {layer.name: _as_section(layer.params) for layer in plugins}
        for key, value in changes.items():
            parts = key.split(".")
            if parts[0] in sections and len(parts) > 1:
                _set_dotted(sections[parts[0]], parts[1:], value)
            else:
                _set_dotted(own, parts, value)
        model = validate_section(CostmapParams, own, key_prefix=[self.name])
        layer_params = {
            layer.name: validate_section(
                type(layer).Params, sections[layer.name], key_prefix=[self.name, layer.name]
            )
            for layer in plugins
        }
        self._apply(model, layer_params)

    def _apply(self, model: CostmapParams, layer_params: Mapping[str, Any]) -> None:
        old = self.params
        self.params = model
        self.layered.params = model
        geometry = ("width", "height", "resolution", "origin_x", "origin_y")
        if any(getattr(old, k) != getattr(model, k) for k in geometry):
            p = model
            self.layered.resize_map(
                max(1, int(p.width / p.resolution)),
                max(1, int(p.height / p.resolution)),
                p.resolution,
                p.origin_x,
                p.origin_y,
            )
            if self.map is not None and not self.layered.rolling_window:
                self.set_map(self.map)
        self.layered.set_footprint(robot_footprint(model))
        for layer in [*self.layers, *self.filters]:
            new = layer_params.get(layer.name)
            if new is not None and new != layer.params:
                layer.set_params(new)
        self.refresh()


#: Nav2's C++ name for the costmap server.
Costmap2DROS = CostmapROS


def _layers_of(server: ServerParams) -> list[Layer]:
    """Layer instances for a costmap's `plugins` (filters and unimplemented layers are skipped)."""
    out: list[Layer] = []
    for section in server.plugins.values():
        if section.list_key != "plugins" or section.cls is None:
            continue
        out.append(section.cls(section.name, section.params))
    return out


def _filters_of(server: ServerParams) -> list[CostmapFilter]:
    """Filter instances for a costmap's `filters`, in list order."""
    return [
        section.cls(section.name, section.params)
        for section in server.plugins.values()
        if section.list_key == "filters" and section.cls is not None
    ]
