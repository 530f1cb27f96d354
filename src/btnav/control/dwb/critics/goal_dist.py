"""dwb_critics::GoalDist: how far (cells, Manhattan) the trajectory ends from the last plan pose on the costmap."""

from __future__ import annotations

from ....plugins import register
from .map_grid import MapGridCritic, plan_cells_on_costmap


@register("critic", "dwb_critics::GoalDist", aliases=["dwb_critics::GoalDistCritic"])
class GoalDistCritic(MapGridCritic):
    def prepare(self, pose, velocity, goal, plan, costmap) -> bool:
        cells = plan_cells_on_costmap(plan, costmap)
        return self.set_seeds(cells[-1:], costmap)
