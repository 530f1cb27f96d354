"""dwb_critics::PathDist: how far (cells, Manhattan) the trajectory ends from the local plan."""

from __future__ import annotations

from ....plugins import register
from .map_grid import MapGridCritic, plan_cells_on_costmap


@register("critic", "dwb_critics::PathDist", aliases=["dwb_critics::PathDistCritic"])
class PathDistCritic(MapGridCritic):
    def prepare(self, pose, velocity, goal, plan, costmap) -> bool:
        return self.set_seeds(plan_cells_on_costmap(plan, costmap), costmap)
