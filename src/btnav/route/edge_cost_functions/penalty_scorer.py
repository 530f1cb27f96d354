"""PenaltyScorer: the edge's static `penalty` from the graph file (may be negative)."""

from __future__ import annotations

from ...plugins import register
from ..edge_scorer import EdgeCostFunction, metadata_number
from ..graph import DirectionalEdge, EdgeType, RouteRequest


@register("edge_cost_function", "nav2_route::PenaltyScorer")
class PenaltyScorer(EdgeCostFunction):
    class Params(EdgeCostFunction.Params):
        penalty_tag: str = "penalty"

    def score(
        self, edge: DirectionalEdge, request: RouteRequest, edge_type: EdgeType
    ) -> float | None:
        return self.params.weight * metadata_number(edge.metadata, self.params.penalty_tag, 0.0)
