"""DistanceScorer: the edge's length, divided by its `speed_limit` fraction when it has one
(a slower edge costs as if it were longer: time at a proportion of full speed)."""

from __future__ import annotations

from ...plugins import register
from ..edge_scorer import EdgeCostFunction, metadata_number
from ..graph import DirectionalEdge, EdgeType, RouteRequest


@register("edge_cost_function", "nav2_route::DistanceScorer")
class DistanceScorer(EdgeCostFunction):
    class Params(EdgeCostFunction.Params):
        speed_tag: str = "speed_limit"

    def score(
        self, edge: DirectionalEdge, request: RouteRequest, edge_type: EdgeType
    ) -> float | None:
        speed = metadata_number(edge.metadata, self.params.speed_tag, 1.0)
        return self.params.weight * edge.length / speed
