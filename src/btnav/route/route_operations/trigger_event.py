"""TriggerEvent: a graph operation that calls a std_srvs/Trigger service when the robot
reaches its node or edge: the operation's own `service_name` metadata if it has one,
else the params' `service_name` (Nav2's RouteOperationClient).

A service is a callable of no arguments found by name in the route server's services
(the stack's and any a program adds: `route_server.services["open_door"] = fn`);
it answers `(success, message)` or a bool. No such service fails tracking.
"""

from __future__ import annotations

from typing import Any

from ...core.geometry import Pose2D
from ...params.schema import ParamsModel
from ...plugins import register
from ..exceptions import OperationFailed
from ..graph import DirectionalEdge, Node, Route
from ..route_operation import OperationResult, RouteOperation, RouteOperationType


@register("route_operation", "nav2_route::TriggerEvent")
class TriggerEvent(RouteOperation):
    class Params(ParamsModel):
        service_name: str = ""

    process_type = RouteOperationType.ON_GRAPH

    def perform(
        self,
        node: Node | None,
        edge_entered: DirectionalEdge | None,
        edge_exited: DirectionalEdge | None,
        route: Route,
        pose: Pose2D,
        metadata: dict[str, Any] | None = None,
    ) -> OperationResult:
        name = str((metadata or {}).get("service_name") or self.params.service_name)
        where = f"at Node {node.nodeid}" if node is not None else "on the route"
        if not name:
            raise OperationFailed(
                f"Route operation service ({self.name}) needs 'service_name' set in the "
                "param file or in the operation's metadata!"
            )
        services = self.context.services if self.context is not None else {}
        service = services.get(name)
        if service is None:
            raise OperationFailed(
                f"Route operation service ({self.name}) failed to call service: {name} {where}"
            )
        service()
        return OperationResult()
