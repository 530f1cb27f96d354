"""`btnav_example::KeepoutZonesLayer`: polygons from the params file, written into the costmap.

Nav2 keeps a robot out of places with a costmap filter and a mask image; this layer
does it with polygons in the params file, which is how a student marks "not through
the kitchen" without drawing a mask. `keepout_zones` become lethal, so planners go
round them and the inflation layer (listed after this one) inflates them like walls;
`slow_zones` get `slow_zone_cost`, which a planner with a cost weight avoids when the
detour is cheap. Zones are in the costmap's `global_frame` (`map` for Nav2's global
costmap).

The layer contract, as the built-in layers keep it:

- the zones live in the layer's own grid (`CostmapLayer.grid`, NO_INFORMATION
  outside them: this layer has no opinion there) and are drawn again whenever the grid
  is remade (`match_size`), the params change (`on_params_changed`) or the costmap is
  cleared entirely (`reset`: zones are not sensed data, they come back);
- `update_bounds` grows the window over the zones only when they were redrawn (every
  update on a rolling window, which moves under them);
- `update_costs` takes the higher cost of master and layer in the window (Nav2's
  `updateWithMax`), so a zone never lowers what the static layer says.
"""

from __future__ import annotations

import numpy as np
from btnav.core.geometry import Pose2D
from btnav.costmap.cost_values import LETHAL_OBSTACLE, MAX_NON_OBSTACLE, NO_INFORMATION
from btnav.costmap.costmap_2d import Costmap2D
from btnav.costmap.footprint import polygon_cells
from btnav.costmap.layer import Bounds, CostmapLayer, Window
from btnav.params import Points
from btnav.plugins import register
from pydantic import Field


@register("costmap_layer", "btnav_example::KeepoutZonesLayer")
class KeepoutZonesLayer(CostmapLayer):
    """Keepout (lethal) and slow (costly) polygons, given in the params file."""

    class Params(CostmapLayer.Params):
        keepout_zones: list[Points] = Field(
            default_factory=list, description='polygons the robot must not enter: "[[x, y], ...]"'
        )
        slow_zones: list[Points] = Field(
            default_factory=list, description="polygons a planner should avoid when it can"
        )
        slow_zone_cost: int = Field(150, ge=1, le=MAX_NON_OBSTACLE)

    params: Params

    def __init__(self, name: str, params: Params | None = None) -> None:
        super().__init__(name, params)
        self.redrawn = True

    def default_value(self) -> int:
        return NO_INFORMATION  # outside the zones the layer says nothing

    # -- when the zones are drawn ------------------------------------------------------------

    def match_size(self) -> None:
        super().match_size()
        self.draw_zones()

    def on_params_changed(self) -> None:
        self.draw_zones()

    def reset(self) -> None:
        self.draw_zones()
        self.current = True

    def is_clearable(self) -> bool:
        return False  # clearing around the robot must not open a keepout zone

    def clear_area(self, window: Window, invert: bool) -> None:
        return

    def draw_zones(self) -> None:
        """Rasterise the zones into the layer's grid (slow ones first: keepout wins an overlap)."""
        grid = self.grid
        grid.reset_map()
        for zone in self.params.slow_zones:
            if zone:
                ys, xs = polygon_cells(grid, zone)
                grid.costs[ys, xs] = self.params.slow_zone_cost
        for zone in self.params.keepout_zones:
            if zone:
                ys, xs = polygon_cells(grid, zone)
                grid.costs[ys, xs] = LETHAL_OBSTACLE
        self.redrawn = True

    # -- the two passes ----------------------------------------------------------------------

    def update_bounds(self, robot: Pose2D, bounds: Bounds) -> None:
        if self.layered is None:
            return
        if self.layered.rolling_window:
            self.match_origin()  # the window moved: draw the zones where they now fall
            self.draw_zones()
        if self.redrawn:
            for zone in (*self.params.keepout_zones, *self.params.slow_zones):
                bounds.touch_points(np.asarray(zone, dtype=float).reshape(-1, 2))
            self.redrawn = False

    def update_costs(self, master: Costmap2D, window: Window) -> None:
        if self.enabled and not window.empty:
            self.update_with_max(master, window)
