"""Route operations (plugin kind `route_operation`): what the route tracker does as the
robot moves along a route (nav2_route::RouteOperation).

An operation runs at one of three moments (`process_type`): ON_GRAPH, when a node or
edge of the route names it in its `operations` (its `type` is the operation's name in
the params file: `operations: [open_door]`, `open_door: {plugin: ...}`); ON_STATUS_CHANGE,
whenever a node is passed; ON_QUERY, on every tracker cycle. `perform` may ask for a
reroute and name edges (or nodes) to avoid then.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import IntEnum
from typing import Any

from ..core.geometry import Pose2D
from ..params.schema import ParamsModel
from ..plugins import Plugin
from .context import RouteContext
from .graph import DirectionalEdge, Node, Route


class RouteOperationType(IntEnum):
    ON_GRAPH = 0
    ON_STATUS_CHANGE = 1
    ON_QUERY = 2


@dataclass
class OperationResult:
    reroute: bool = False
    blocked_ids: list[int] = field(default_factory=list)


class RouteOperation(Plugin):
    class Params(ParamsModel):
        pass

    process_type = RouteOperationType.ON_GRAPH
    context: RouteContext | None = None

    def configure(self, context: Any) -> None:
        self.context = context

    def perform(
        self,
        node: Node | None,
        edge_entered: DirectionalEdge | None,
        edge_exited: DirectionalEdge | None,
        route: Route,
        pose: Pose2D,
        metadata: dict[str, Any] | None = None,
    ) -> OperationResult:
        raise NotImplementedError

    def services(self) -> dict[str, Any]:
        """The operation's services by name under its own (ReroutingService's reroute)."""
        return {}
