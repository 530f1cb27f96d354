"""Nav2's LayeredCostmap: a master grid made from an ordered list of layers.

`LayeredCostmap` holds the master `Costmap2D`, the layers, the footprint and its
radii, and runs Nav2's update (bounds pass, reset of the window, costs pass). The
costmap server around it is `costmap_ros.CostmapROS`.

Costmap filters (a costmap's `filters: [...]`) run after the layers, as Nav2's do: with
any filter the layers write a primary grid, the window is copied into the master and
the filters write over the copy, so no layer (the inflation layer, say) ever reads
what a filter wrote: a keepout zone is not inflated, and its costs never linger in
the layers' own work.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from ..core.frames import FrameTree
from ..core.geometry import Pose2D
from ..params.costmap import CostmapParams
from .cost_values import FREE_SPACE, NO_INFORMATION
from .costmap_2d import Costmap2D
from .footprint import footprint_from_radius, min_max_distances, pad_footprint
from .layer import Bounds, Layer, Window

if TYPE_CHECKING:
    from .filters.costmap_filter import CostmapFilter


class LayeredCostmap:
    """The master grid and its layers (nav2_costmap_2d::LayeredCostmap)."""

    def __init__(self, params: CostmapParams | None = None) -> None:
        self.params = params if params is not None else CostmapParams()
        p = self.params
        self.global_frame = p.global_frame
        self.rolling_window = p.rolling_window
        self.track_unknown_space = p.track_unknown_space
        self.resolution = p.resolution
        default = NO_INFORMATION if p.track_unknown_space else FREE_SPACE
        sx, sy = max(1, int(p.width / p.resolution)), max(1, int(p.height / p.resolution))
        self.costmap = Costmap2D.empty(
            sx, sy, p.resolution, p.origin_x, p.origin_y, p.global_frame, default
        )
        self.layers: list[Layer] = []
        self.filters: list[CostmapFilter] = []
        #: What the layers write when there are filters (Nav2's primary_costmap_).
        self.primary: Costmap2D | None = None
        self.frame_tree: FrameTree | None = None
        self.footprint: NDArray[np.float64] = np.zeros((0, 2))
        self.inscribed_radius = 0.0
        self.circumscribed_radius = 0.0
        self.last_window: Window | None = None

    # -- building ---------------------------------------------------------------------

    def add_layer(self, layer: Layer) -> None:
        self.layers.append(layer)
        layer.initialize(self)
        layer.match_size()
        layer.on_footprint_changed()

    def add_filter(self, costmap_filter: CostmapFilter) -> None:
        """A costmap filter, run after every layer (Nav2's addFilter)."""
        if self.primary is None:
            self.primary = self.costmap.copy()
        self.filters.append(costmap_filter)
        costmap_filter.initialize(self)
        costmap_filter.match_size()
        costmap_filter.on_footprint_changed()

    def filter(self, name: str) -> CostmapFilter:
        for costmap_filter in self.filters:
            if costmap_filter.name == name:
                return costmap_filter
        raise KeyError(f"no filter '{name}'; filters: {', '.join(f.name for f in self.filters)}")

    def layer(self, name: str) -> Layer:
        for layer in self.layers:
            if layer.name == name:
                return layer
        raise KeyError(f"no layer '{name}'; layers: {', '.join(x.name for x in self.layers)}")

    def resize_map(
        self, size_x: int, size_y: int, resolution: float, origin_x: float, origin_y: float
    ) -> None:
        self.resolution = resolution
        self.costmap.resize_map(size_x, size_y, resolution, origin_x, origin_y)
        if self.primary is not None:
            self.primary.resize_map(size_x, size_y, resolution, origin_x, origin_y)
        for layer in [*self.layers, *self.filters]:
            layer.match_size()

    def set_footprint(self, footprint: NDArray[np.float64]) -> None:
        """The padded footprint; the inscribed and circumscribed radii follow from it."""
        self.footprint = np.asarray(footprint, dtype=float).reshape(-1, 2)
        self.inscribed_radius, self.circumscribed_radius = min_max_distances(self.footprint)
        for layer in [*self.layers, *self.filters]:
            layer.on_footprint_changed()

    # -- the update ---------------------------------------------------------------------

    def update_map(self, robot: Pose2D, *, full: bool = False) -> Window | None:
        """One Nav2 update: bounds pass, reset the window, costs pass (layers, then
        filters). Returns the window."""
        m = self.costmap
        primary = self.primary if self.filters else None
        if self.rolling_window:
            sx, sy = m.size_in_meters
            m.update_origin(robot.x - sx / 2.0, robot.y - sy / 2.0)
            if primary is not None:
                primary.update_origin(robot.x - sx / 2.0, robot.y - sy / 2.0)
        bounds = Bounds()
        for layer in [*self.layers, *self.filters]:
            layer.update_bounds(robot, bounds)
        if full:
            bounds.cover(m)
        if bounds.empty:
            self.last_window = None
            return None
        x0, y0 = m.world_to_map_enforce_bounds(bounds.min_x, bounds.min_y)
        xn, yn = m.world_to_map_enforce_bounds(bounds.max_x, bounds.max_y)
        window = Window(x0, y0, min(xn + 1, m.size_x), min(yn + 1, m.size_y))
        if window.empty:
            return None
        target = m if primary is None else primary
        target.reset_map(window.x0, window.y0, window.xn, window.yn)
        for layer in self.layers:
            if layer.enabled:
                layer.update_costs(target, window)
        if primary is not None:
            m.costs[window.slices] = primary.costs[window.slices]
            for costmap_filter in self.filters:
                costmap_filter.update_costs(m, window)
        self.last_window = window
        return window

    def reset_layers(self) -> None:
        self.costmap.reset_map()
        if self.primary is not None:
            self.primary.reset_map()
        for layer in [*self.layers, *self.filters]:
            layer.reset()


def robot_footprint(params: CostmapParams) -> NDArray[np.float64]:
    """The padded footprint Nav2 builds: `footprint` if given, else a 16-gon of robot_radius."""
    base = np.asarray(params.footprint, dtype=float).reshape(-1, 2)
    if len(base) == 0:
        base = footprint_from_radius(params.robot_radius)
    return pad_footprint(base, params.footprint_padding)
