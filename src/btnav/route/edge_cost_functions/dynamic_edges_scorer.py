"""DynamicEdgesScorer: costs and closures set at run time by another program (a fleet
manager) through its `adjust_edges` service; a closed edge is refused, an adjusted one
costs what was set, any other nothing."""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from typing import Any

from ...params.schema import ParamsModel
from ...plugins import register
from ..edge_scorer import EdgeCostFunction
from ..graph import DirectionalEdge, EdgeType, RouteRequest


@register("edge_cost_function", "nav2_route::DynamicEdgesScorer")
class DynamicEdgesScorer(EdgeCostFunction):
    class Params(ParamsModel):
        """Nav2's has no keys of its own (not even a weight)."""

    def __init__(self, name: str, params: Any = None) -> None:
        super().__init__(name, params)
        self.closed_edges: set[int] = set()
        self.dynamic_penalties: dict[int, float] = {}

    def adjust_edges(
        self,
        closed_edges: Iterable[int] = (),
        opened_edges: Iterable[int] = (),
        adjust_edges: Mapping[int, float] | None = None,
    ) -> bool:
        """nav2_msgs/DynamicEdges: close edges, reopen edges, set edges' costs."""
        self.closed_edges.update(int(e) for e in closed_edges)
        self.closed_edges.difference_update(int(e) for e in opened_edges)
        for edgeid, cost in (adjust_edges or {}).items():
            self.dynamic_penalties[int(edgeid)] = float(cost)
        return True

    def services(self) -> dict[str, Any]:
        return {"adjust_edges": self.adjust_edges}

    def score(
        self, edge: DirectionalEdge, request: RouteRequest, edge_type: EdgeType
    ) -> float | None:
        if edge.edgeid in self.closed_edges:
            return None
        return self.dynamic_penalties.get(edge.edgeid, 0.0)
