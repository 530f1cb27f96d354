"""AdjustSpeedLimit: on entering an edge, the controller's speed limit becomes the edge's
`speed_limit` (percent of the maximum; 100 when the edge has none), as Nav2's publishes
nav2_msgs/SpeedLimit on `speed_limit` for controller_server."""

from __future__ import annotations

from typing import Any

from ...core.geometry import Pose2D
from ...params.schema import ParamsModel, Why, ignored
from ...plugins import register
from ..edge_scorer import metadata_number
from ..graph import DirectionalEdge, Node, Route
from ..route_operation import OperationResult, RouteOperation, RouteOperationType


@register("route_operation", "nav2_route::AdjustSpeedLimit")
class AdjustSpeedLimit(RouteOperation):
    class Params(ParamsModel):
        speed_tag: str = "speed_limit"
        speed_limit_topic: str = ignored("speed_limit", Why.TOPIC)

    process_type = RouteOperationType.ON_STATUS_CHANGE

    def perform(
        self,
        node: Node | None,
        edge_entered: DirectionalEdge | None,
        edge_exited: DirectionalEdge | None,
        route: Route,
        pose: Pose2D,
        metadata: dict[str, Any] | None = None,
    ) -> OperationResult:
        if edge_entered is None:
            return OperationResult()
        limit = metadata_number(edge_entered.metadata, self.params.speed_tag, 100.0)
        #: The last limit sent (speed_limit, percentage), for reports and tests.
        self.last_sent = (limit, True)
        setter = self.context.set_speed_limit if self.context is not None else None
        if setter is not None:
            setter(limit, True)
        return OperationResult()
