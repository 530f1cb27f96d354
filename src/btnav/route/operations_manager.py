"""nav2_route's OperationsManager: runs the route operations at the tracker's moments.

On a status change (a node passed), the operations the passed node, the entered edge
(ON_ENTER) and the exited edge (ON_EXIT) name run first, then every ON_STATUS_CHANGE
operation; every ON_QUERY operation runs on each cycle. A graph operation whose type no
loaded operation has fails tracking (OPERATION_FAILED), as in Nav2.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from ..core.geometry import Pose2D
from .exceptions import OperationFailed
from .graph import DirectionalEdge, Node, Operation, OperationTrigger, ReroutingState, Route
from .route_operation import OperationResult, RouteOperation, RouteOperationType


@dataclass
class OperationsResult:
    operations_triggered: list[str] = field(default_factory=list)
    reroute: bool = False
    blocked_ids: list[int] = field(default_factory=list)

    def add(self, name: str, result: OperationResult) -> None:
        self.reroute = self.reroute or result.reroute
        self.blocked_ids.extend(result.blocked_ids)
        self.operations_triggered.append(name)


@dataclass
class TrackingState:
    """Where the robot is on the route (Nav2's RouteTrackingState)."""

    last_node: Node | None = None
    next_node: Node | None = None
    current_edge: DirectionalEdge | None = None
    route_edges_idx: int = -1
    within_radius: bool = False


class OperationsManager:
    def __init__(self, operations: dict[str, RouteOperation]) -> None:
        self.graph_operations = {
            n: op for n, op in operations.items() if op.process_type == RouteOperationType.ON_GRAPH
        }
        self.change_operations = [
            op
            for op in operations.values()
            if op.process_type == RouteOperationType.ON_STATUS_CHANGE
        ]
        self.query_operations = [
            op for op in operations.values() if op.process_type == RouteOperationType.ON_QUERY
        ]

    def process(
        self,
        status_change: bool,
        state: TrackingState,
        route: Route,
        pose: Pose2D,
        rerouting: ReroutingState,
    ) -> OperationsResult:
        result = OperationsResult()
        node, entered = state.last_node, state.current_edge
        exited = route.edges[state.route_edges_idx - 1] if state.route_edges_idx > 0 else None
        if state.route_edges_idx == 0 and rerouting.curr_edge is not None:
            exited = rerouting.curr_edge  # leaving the partial edge a reroute kept
        if status_change:
            for op in self._graph_operations(node, entered, exited):
                plugin = self.graph_operations.get(op.type)
                if plugin is None:
                    raise OperationFailed(
                        f"Operation {op.type} does not exist in route operations loaded!"
                    )
                result.add(
                    plugin.name, plugin.perform(node, entered, exited, route, pose, op.metadata)
                )
            for plugin in self.change_operations:
                result.add(plugin.name, plugin.perform(node, entered, exited, route, pose))
        for plugin in self.query_operations:
            result.add(plugin.name, plugin.perform(node, entered, exited, route, pose))
        return result

    @staticmethod
    def _graph_operations(
        node: Node | None, entered: DirectionalEdge | None, exited: DirectionalEdge | None
    ) -> list[Operation]:
        ops: list[Operation] = []
        for owner, trigger in (
            (node, OperationTrigger.NODE),
            (entered, OperationTrigger.ON_ENTER),
            (exited, OperationTrigger.ON_EXIT),
        ):
            if owner is not None:
                ops.extend(op for op in owner.operations if op.trigger == trigger)
        return ops
