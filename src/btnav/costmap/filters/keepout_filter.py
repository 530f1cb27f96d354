"""nav2_costmap_2d::KeepoutFilter: the cells a keepout mask marks become obstacles.

Each master cell of the update window takes the mask's cost under its centre (mask
value 0..100 scaled onto 0..254: a trinary mask's occupied cells are LETHAL) where that
is higher than what the layers wrote, or where the layers know nothing; unknown mask
cells change nothing. The filter runs after inflation, so a zone is not inflated: its
edge is a wall the footprint checks see, as in Nav2.

A robot inside a zone (a map started there, localisation drift) could never plan out
of it. With `override_lethal_cost`, while the robot's own cell is lethal in the mask
the filter writes `lethal_override_cost` instead (252 by default, below
INSCRIBED_INFLATED_OBSTACLE), over every window touched until it has left, so the
planner finds a way out that the zone's cost still steers short.
"""

from __future__ import annotations

import numpy as np
from pydantic import Field

from ...core.geometry import Pose2D
from ...plugins import register
from ..cost_values import (
    FREE_SPACE,
    INSCRIBED_INFLATED_OBSTACLE,
    LETHAL_OBSTACLE,
    MAX_NON_OBSTACLE,
    NO_INFORMATION,
)
from ..costmap_2d import Costmap2D
from ..layer import Bounds, Window
from .costmap_filter import CostmapFilter
from .filter_info import mask_cost


@register("costmap_filter", "nav2_costmap_2d::KeepoutFilter", aliases=("btnav/KeepoutFilter",))
class KeepoutFilter(CostmapFilter):
    """Keepout zones (and, with a scale mask, preferred lanes) written into the master grid."""

    class Params(CostmapFilter.Params):
        override_lethal_cost: bool = False
        lethal_override_cost: int = Field(
            MAX_NON_OBSTACLE,
            description=f"the cost of zone cells while the robot is in one; Nav2 clamps it "
            f"to {FREE_SPACE}..{MAX_NON_OBSTACLE}",
        )

    def __init__(self, name: str, params: Params | None = None) -> None:
        super().__init__(name, params)
        self.params: KeepoutFilter.Params
        self.has_updated_data = False
        self.is_pose_lethal = False
        self.last_pose_lethal = False
        self._lethal_bounds = Bounds()

    @property
    def lethal_override_cost(self) -> int:
        return min(max(self.params.lethal_override_cost, FREE_SPACE), MAX_NON_OBSTACLE)

    def on_mask(self) -> None:
        self.has_updated_data = True

    # -- the two passes ---------------------------------------------------------------------

    def update_bounds(self, robot: Pose2D, bounds: Bounds) -> None:
        if not self.enabled:
            return
        super().update_bounds(robot, bounds)
        if self.filter_mask is None:
            return
        if self.has_updated_data:  # a new mask: repaint all of it
            self._touch_mask_extent(bounds)
            self.has_updated_data = False
            return
        self.is_pose_lethal = False
        if not self.params.override_lethal_cost:
            return
        data = self.mask_data_at(robot)
        if data is not None:
            cost = int(mask_cost(data))
            self.is_pose_lethal = cost in (INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE)
        if self.is_pose_lethal or self.last_pose_lethal:
            # every window touched while inside (and the one on leaving) gets repainted
            self._lethal_bounds.merge(bounds)
            bounds.merge(self._lethal_bounds)
        else:
            self._lethal_bounds = Bounds()

    def _touch_mask_extent(self, bounds: Bounds) -> None:
        """Grow `bounds` by the mask's extent in the costmap frame (all of the costmap when
        the frame tree cannot place the mask yet)."""
        assert self.filter_mask is not None and self.layered is not None
        tf = self.mask_transform()
        if tf is None:
            bounds.cover(self.master)
            return
        mask = self.filter_mask
        w, h = mask.size_m
        corners = mask.origin.transform_points([(0.0, 0.0), (w, 0.0), (0.0, h), (w, h)])
        bounds.touch_points(tf.inverse_transform_points(corners))

    def process(self, master: Costmap2D, window: Window, pose: Pose2D) -> None:
        if self.filter_mask is None or window.empty:
            return
        tf = self.mask_transform()
        if tf is None:
            return
        mask = self.filter_mask
        xs, ys = master.cell_centers(window.x0, window.y0, window.xn, window.yn)
        xs, ys = np.broadcast_arrays(xs, ys)
        rc = mask.world_to_cell(tf.transform_points(np.stack([xs, ys], axis=-1)))
        on_mask = mask.in_bounds(rc)
        cost = np.full(xs.shape, NO_INFORMATION, np.uint8)
        cost[on_mask] = mask_cost(mask.data[rc[..., 0][on_mask], rc[..., 1][on_mask]])
        old = master.costs[window.slices]
        write = (cost != NO_INFORMATION) & ((cost > old) | (old == NO_INFORMATION))
        if self.params.override_lethal_cost and self.is_pose_lethal:
            old[write] = self.lethal_override_cost
        else:
            old[write] = cost[write]
        self.last_pose_lethal = self.is_pose_lethal
