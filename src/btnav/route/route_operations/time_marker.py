"""TimeMarker: the seconds the robot took along each edge it completed, written into the
edge's metadata (`abs_time_taken`), where TimeScorer finds it for the next route."""

from __future__ import annotations

from typing import Any

from ...core.geometry import Pose2D
from ...params.schema import ParamsModel
from ...plugins import register
from ..graph import DirectionalEdge, Node, Route
from ..route_operation import OperationResult, RouteOperation, RouteOperationType


@register("route_operation", "nav2_route::TimeMarker")
class TimeMarker(RouteOperation):
    class Params(ParamsModel):
        time_tag: str = "abs_time_taken"

    process_type = RouteOperationType.ON_STATUS_CHANGE

    def __init__(self, name: str, params: Any = None) -> None:
        super().__init__(name, params)
        self.edge_start_time = 0.0
        self.curr_edge: int | None = None

    def perform(
        self,
        node: Node | None,
        edge_entered: DirectionalEdge | None,
        edge_exited: DirectionalEdge | None,
        route: Route,
        pose: Pose2D,
        metadata: dict[str, Any] | None = None,
    ) -> OperationResult:
        now = self.context.now() if self.context is not None else 0.0
        finished = edge_exited is not None and edge_exited.edgeid == self.curr_edge
        if finished and edge_exited is not None and self.edge_start_time > 1e-3:
            edge_exited.metadata[self.params.time_tag] = now - self.edge_start_time
        self.edge_start_time = now
        self.curr_edge = edge_entered.edgeid if edge_entered is not None else None
        return OperationResult()
