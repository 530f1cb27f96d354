"""CostmapScorer: the costmap's cost along the edge (its highest, or its mean), as a
fraction of `max_cost`; an edge through a cell at `max_cost` or above is refused when
`invalid_on_collision`, one with an end off the costmap when `invalid_off_map`.

The cells are LineIterator's between the ends' cells, every `check_resolution`-th.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from pydantic import Field

from ...costmap.cost_values import NO_INFORMATION
from ...plugins import register
from ..context import CostmapView
from ..edge_scorer import EdgeCostFunction
from ..graph import DirectionalEdge, EdgeType, RouteRequest
from ..line_cells import line_cells


def edge_costs(view: CostmapView, x0: float, y0: float, x1: float, y1: float, step: int) -> Any:
    """The costs LineIterator meets from (x0, y0) to (x1, y1), every `step`-th cell, or None
    if an end is off the costmap."""
    cells, inside = view.cells([(x0, y0), (x1, y1)])
    if not inside.all():
        return None
    mx, my = line_cells(int(cells[0, 0]), int(cells[0, 1]), int(cells[1, 0]), int(cells[1, 1]))
    return view.costmap.costs[my[::step], mx[::step]].astype(np.float64)


@register("edge_cost_function", "nav2_route::CostmapScorer")
class CostmapScorer(EdgeCostFunction):
    class Params(EdgeCostFunction.Params):
        use_maximum: bool = True
        invalid_on_collision: bool = True
        invalid_off_map: bool = True
        max_cost: float = Field(253.0, gt=0.0, le=255.0)
        check_resolution: int = Field(2, ge=1)
        costmap_topic: str = "global_costmap/costmap_raw"

    view: CostmapView | None = None

    def prepare(self) -> None:
        context = self.context
        self.view = context.costmap(self.params.costmap_topic) if context is not None else None

    def score(
        self, edge: DirectionalEdge, request: RouteRequest, edge_type: EdgeType
    ) -> float | None:
        p = self.params
        if self.view is None:
            return None  # Nav2: no costmap yet, so no edge is valid
        costs = edge_costs(
            self.view, edge.start.x, edge.start.y, edge.end.x, edge.end.y, p.check_resolution
        )
        if costs is None:
            return None if p.invalid_off_map else 0.0
        if p.invalid_on_collision and p.max_cost != NO_INFORMATION and (costs >= p.max_cost).any():
            return None
        if p.use_maximum:
            known = costs[costs != NO_INFORMATION]
            return p.weight * float(known.max(initial=0.0)) / p.max_cost
        return p.weight * float(costs.sum()) / (len(costs) * p.max_cost)
