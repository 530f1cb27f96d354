"""ReroutingService: another program asks for a reroute (its `reroute` service, a
std_srvs/Trigger); the next tracker cycle reroutes from where the robot is."""

from __future__ import annotations

from typing import Any

from ...core.geometry import Pose2D
from ...plugins import register
from ..graph import DirectionalEdge, Node, Route
from ..route_operation import OperationResult, RouteOperation, RouteOperationType


@register("route_operation", "nav2_route::ReroutingService")
class ReroutingService(RouteOperation):
    process_type = RouteOperationType.ON_QUERY

    def __init__(self, name: str, params: Any = None) -> None:
        super().__init__(name, params)
        self.requested = False

    def reroute(self) -> tuple[bool, str]:
        self.requested = True
        return True, ""

    def services(self) -> dict[str, Any]:
        return {"reroute": self.reroute}

    def perform(
        self,
        node: Node | None,
        edge_entered: DirectionalEdge | None,
        edge_exited: DirectionalEdge | None,
        route: Route,
        pose: Pose2D,
        metadata: dict[str, Any] | None = None,
    ) -> OperationResult:
        if self.requested:
            self.requested = False
            return OperationResult(reroute=True)
        return OperationResult()
