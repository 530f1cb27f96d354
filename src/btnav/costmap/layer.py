"""The costmap layer plugin base (nav2_costmap_2d::Layer and CostmapLayer, in Python spelling).

A layered costmap updates in Nav2's two passes. `update_bounds` lets every enabled
layer grow the window (in world metres) that changed since the last update; the
master grid is reset in that window; then `update_costs` lets every enabled layer,
in list order, write its costs into the window with one of Nav2's combination
methods (`update_with_overwrite`, `update_with_max`, ...). All passes are whole-array
numpy operations on the window.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray
from pydantic import Field

from ..core.frames import FrameTree
from ..core.geometry import Pose2D
from ..core.messages import LaserScan
from ..maps.occupancy_grid import OccupancyGrid
from ..params.schema import ParamsModel
from ..plugins import Plugin
from .cost_values import FREE_SPACE, NO_INFORMATION
from .costmap_2d import Costmap2D

if TYPE_CHECKING:
    from .layered_costmap import LayeredCostmap


@dataclass
class Bounds:
    """A world-frame window (Nav2 passes min_x, min_y, max_x, max_y by reference)."""

    min_x: float = float("inf")
    min_y: float = float("inf")
    max_x: float = float("-inf")
    max_y: float = float("-inf")

    def touch(self, x: float, y: float) -> None:
        self.min_x = min(self.min_x, x)
        self.min_y = min(self.min_y, y)
        self.max_x = max(self.max_x, x)
        self.max_y = max(self.max_y, y)

    def touch_points(self, xy: NDArray[np.float64]) -> None:
        if len(xy):
            # column by column (a reduction along the short axis costs several times more)
            x, y = xy[:, 0], xy[:, 1]
            self.touch(float(x.min()), float(y.min()))
            self.touch(float(x.max()), float(y.max()))

    def merge(self, other: Bounds) -> None:
        if not other.empty:
            self.touch(other.min_x, other.min_y)
            self.touch(other.max_x, other.max_y)

    def expanded(self, margin: float) -> Bounds:
        return Bounds(
            self.min_x - margin, self.min_y - margin, self.max_x + margin, self.max_y + margin
        )

    @property
    def empty(self) -> bool:
        return not (self.min_x <= self.max_x and self.min_y <= self.max_y)

    def cover(self, costmap: Costmap2D) -> None:
        """Grow to the whole of `costmap`."""
        sx, sy = costmap.size_in_meters
        self.touch(costmap.origin_x, costmap.origin_y)
        self.touch(costmap.origin_x + sx, costmap.origin_y + sy)


@dataclass(frozen=True)
class Window:
    """Cells [x0, xn) x [y0, yn) of the master grid being updated."""

    x0: int
    y0: int
    xn: int
    yn: int

    @property
    def slices(self) -> tuple[slice, slice]:
        return slice(self.y0, self.yn), slice(self.x0, self.xn)

    @property
    def empty(self) -> bool:
        return self.xn <= self.x0 or self.yn <= self.y0


class Layer(Plugin):
    """Base of every `costmap_layer` plugin.

    Subclasses override `update_bounds` and `update_costs` (and `reset`,
    `match_size`, `on_footprint_changed`, `on_params_changed`, `set_map`,
    `receive_scan`, `is_current` as they need).
    `params` is the validated section of the layer in the params file.
    """

    class Params(ParamsModel):
        enabled: bool = True

    def __init__(self, name: str, params: Params | None = None) -> None:
        super().__init__(name, params)
        self.layered: LayeredCostmap | None = None
        self.current = True

    # -- life cycle ---------------------------------------------------------------

    def initialize(self, layered: LayeredCostmap) -> None:
        self.layered = layered
        self.on_initialize()

    def on_initialize(self) -> None:
        """Called once the layer belongs to a layered costmap."""

    @property
    def enabled(self) -> bool:
        return bool(getattr(self.params, "enabled", True))

    @property
    def master(self) -> Costmap2D:
        assert self.layered is not None, f"layer '{self.name}' is not in a costmap"
        return self.layered.costmap

    def set_params(self, params: ParamsModel) -> None:
        """New params while running (Nav2's dynamic parameters); the next update uses them."""
        if not isinstance(params, type(self).Params):
            raise TypeError(
                f"layer '{self.name}' takes {type(self).Params.__qualname__}, "
                f"got {type(params).__qualname__}"
            )
        self.params = params
        self.on_params_changed()

    def on_params_changed(self) -> None:
        """React to `set_params` (e.g. the inflation layer recomputes everything)."""

    # -- the two passes -------------------------------------------------------------

    def update_bounds(self, robot: Pose2D, bounds: Bounds) -> None:
        """Grow `bounds` (world metres) to cover what this layer changed."""

    def update_costs(self, master: Costmap2D, window: Window) -> None:
        """Write this layer's costs into `master` inside `window`."""

    # -- the rest of Nav2's Layer interface --------------------------------------------

    def reset(self) -> None:
        """Forget what was sensed (clear_entirely calls it on every layer)."""

    def is_clearable(self) -> bool:
        """Whether clear_around_robot / clear_except_region clear this layer."""
        return False

    def match_size(self) -> None:
        """The master grid changed size, resolution or origin."""

    def on_footprint_changed(self) -> None:
        """The robot footprint (and so the inscribed radius) changed."""

    def clear_area(self, window: Window, invert: bool) -> None:
        """Reset cells inside (or, with `invert`, outside) `window` of this layer's grid."""

    # -- inputs: every layer is offered them; most ignore them ------------------------

    def set_map(self, grid: OccupancyGrid) -> None:
        """A new map from map_server or SLAM (Nav2's static layer subscribes to `map`)."""

    def receive_scan(
        self,
        scan: LaserScan,
        frame_tree: FrameTree,
        source: str | None = None,
        global_frame: str | None = None,
    ) -> None:
        """A new scan (Nav2's layers subscribe to their observation sources' topics)."""

    def is_current(self, now: float) -> bool:
        """Whether this layer's inputs are recent enough (Nav2's `isCurrent`: `current_`)."""
        return self.current


class CostmapLayer(Layer):
    """A layer with its own grid of the master's geometry (Nav2's CostmapLayer)."""

    def __init__(self, name: str, params: Layer.Params | None = None) -> None:
        super().__init__(name, params)
        self.grid = Costmap2D.empty(1, 1, 1.0)

    def default_value(self) -> int:
        assert self.layered is not None
        return NO_INFORMATION if self.layered.track_unknown_space else FREE_SPACE

    def match_size(self) -> None:
        m = self.master
        self.grid = Costmap2D.empty(
            m.size_x,
            m.size_y,
            m.resolution,
            m.origin_x,
            m.origin_y,
            m.frame_id,
            self.default_value(),
        )

    def match_origin(self) -> None:
        """Follow the master's rolling window, keeping what is still on it."""
        m = self.master
        if self.grid.costs.shape != m.costs.shape or self.grid.resolution != m.resolution:
            self.match_size()
            return
        self.grid.update_origin(m.origin_x, m.origin_y)

    def reset(self) -> None:
        self.grid.default_value = self.default_value()
        self.grid.reset_map()
        self.current = True

    def is_clearable(self) -> bool:
        return True

    def clear_area(self, window: Window, invert: bool) -> None:
        if not invert:
            self.grid.costs[window.slices] = self.grid.default_value
            return
        keep = self.grid.costs[window.slices].copy()
        self.grid.reset_map()
        self.grid.costs[window.slices] = keep

    # -- Nav2's combination methods, on the window ----------------------------------------

    def update_with_true_overwrite(self, master: Costmap2D, window: Window) -> None:
        """Every cell, unknown included."""
        master.costs[window.slices] = self.grid.costs[window.slices]

    def update_with_overwrite(self, master: Costmap2D, window: Window) -> None:
        """Every cell this layer knows (not NO_INFORMATION)."""
        src = self.grid.costs[window.slices]
        dst = master.costs[window.slices]
        np.copyto(dst, src, where=src != NO_INFORMATION)

    def update_with_max(self, master: Costmap2D, window: Window) -> None:
        """The higher of the two, where this layer knows; unknown in the master is overwritten."""
        src = self.grid.costs[window.slices]
        dst = master.costs[window.slices]
        np.copyto(dst, src, where=(src != NO_INFORMATION) & ((dst == NO_INFORMATION) | (dst < src)))

    def update_with_max_without_unknown_overwrite(self, master: Costmap2D, window: Window) -> None:
        """The higher of the two, but the master's NO_INFORMATION cells stay unknown."""
        src = self.grid.costs[window.slices]
        dst = master.costs[window.slices]
        np.copyto(dst, src, where=(src != NO_INFORMATION) & (dst != NO_INFORMATION) & (dst < src))

    def combine(self, master: Costmap2D, window: Window, method: int) -> None:
        """Nav2's `combination_method`: 0 overwrite, 1 max, 2 max without unknown overwrite."""
        if method == 0:
            self.update_with_overwrite(master, window)
        elif method == 1:
            self.update_with_max(master, window)
        else:
            self.update_with_max_without_unknown_overwrite(master, window)


def combination_method_field(default: int = 1) -> int:
    """Nav2's `combination_method` key: 0 overwrite, 1 max, 2 max without unknown overwrite."""
    return Field(  # type: ignore[no-any-return]
        default, ge=0, le=2, description="0 overwrite, 1 max, 2 max without unknown overwrite"
    )
