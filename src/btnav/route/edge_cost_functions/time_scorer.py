"""TimeScorer: seconds to traverse the edge: the measured `abs_time_taken` if the edge has
one (TimeMarker writes it), else its length over `abs_speed_limit`, else over `max_vel`."""

from __future__ import annotations

from pydantic import Field

from ...plugins import register
from ..edge_scorer import EdgeCostFunction, metadata_number
from ..graph import DirectionalEdge, EdgeType, RouteRequest


@register("edge_cost_function", "nav2_route::TimeScorer")
class TimeScorer(EdgeCostFunction):
    class Params(EdgeCostFunction.Params):
        speed_tag: str = "abs_speed_limit"
        time_tag: str = "abs_time_taken"
        max_vel: float = Field(0.5, gt=0.0)

    def score(
        self, edge: DirectionalEdge, request: RouteRequest, edge_type: EdgeType
    ) -> float | None:
        taken = metadata_number(edge.metadata, self.params.time_tag, 0.0)
        if taken > 0.0:
            return self.params.weight * taken
        speed = metadata_number(edge.metadata, self.params.speed_tag, 0.0)
        if speed <= 0.0:
            speed = self.params.max_vel
        return self.params.weight * edge.length / speed
