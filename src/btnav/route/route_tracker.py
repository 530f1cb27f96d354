"""nav2_route's RouteTracker: follows the robot along a route, node by node, and runs the
route operations; one `step(pose)` per tracker cycle (`tracker_update_rate`).

A node is achieved when the robot, having come within `radius_to_achieve_node` of it
(`boundary_radius_to_achieve_node` for the route's first and last nodes), leaves that
radius again, or crosses the line through the node at right angles to the bisector of
the edges before and after it (the robot has moved into the next edge's side). The
first and last nodes are achieved on entering their radius. Achieving the last node
completes the route; an operation asking for a reroute interrupts it.
"""

from __future__ import annotations

from collections.abc import Callable
from enum import Enum

from ..core import fmath
from ..core.geometry import Pose2D
from .graph import ReroutingState, Route, normalized_dot
from .operations_manager import OperationsManager, OperationsResult, TrackingState


class TrackerResult(Enum):
    COMPLETED = "completed"
    INTERRUPTED = "interrupted"


#: (rerouted, next_node_id, last_node_id, edge_id, operations_triggered)
FeedbackSink = Callable[[bool, int, int, int, list[str]], None]


class RouteTracker:
    def __init__(
        self,
        operations: OperationsManager,
        radius_to_achieve_node: float = 2.0,
        boundary_radius_to_achieve_node: float = 1.0,
        aggregate_blocked_ids: bool = False,
    ) -> None:
        self.operations = operations
        self.radius = radius_to_achieve_node
        self.boundary_radius = boundary_radius_to_achieve_node
        self.aggregate_blocked_ids = aggregate_blocked_ids
        self.route: Route | None = None
        self.state = TrackingState()

    def start(self, route: Route, rerouting: ReroutingState, feedback: FeedbackSink) -> None:
        """Begin tracking `route` (after a reroute along the same edge, keep that edge)."""
        self.route = route
        self.state = TrackingState(next_node=route.start_node)
        self.feedback = feedback
        if rerouting.curr_edge is not None:
            self.state.current_edge = rerouting.curr_edge
            self.state.last_node = rerouting.curr_edge.start
            feedback(
                True,
                route.start_node.nodeid,
                self.state.last_node.nodeid,
                self.state.current_edge.edgeid,
                [],
            )
        else:
            feedback(True, route.start_node.nodeid, 0, 0, [])

    def step(self, pose: Pose2D, rerouting: ReroutingState) -> TrackerResult | None:
        """One tracker cycle at the robot's pose (route frame); None: still on the way."""
        route, state = self.route, self.state
        assert route is not None
        status_change = completed = False
        if self.node_achieved(pose):
            status_change = True
            state.within_radius = False
            state.last_node = state.next_node
            state.route_edges_idx += 1
            if state.route_edges_idx < len(route.edges):
                state.current_edge = route.edges[state.route_edges_idx]
                state.next_node = state.current_edge.end
            else:
                state.current_edge = None
                state.next_node = None
                completed = True
        result: OperationsResult = self.operations.process(
            status_change, state, route, pose, rerouting
        )
        if completed:
            assert state.last_node is not None
            self.feedback(False, 0, state.last_node.nodeid, 0, result.operations_triggered)
            return TrackerResult.COMPLETED
        if (status_change or result.operations_triggered) and state.current_edge is not None:
            assert state.next_node is not None and state.last_node is not None
            self.feedback(
                False,
                state.next_node.nodeid,
                state.last_node.nodeid,
                state.current_edge.edgeid,
                result.operations_triggered,
            )
        if result.reroute:
            if self.aggregate_blocked_ids:
                rerouting.blocked_ids.extend(result.blocked_ids)
            else:
                rerouting.blocked_ids = list(result.blocked_ids)
            if state.last_node is not None:
                rerouting.rerouting_start_id = state.last_node.nodeid
                rerouting.rerouting_start_pose = pose
            else:
                rerouting.rerouting_start_id = None
                rerouting.rerouting_start_pose = None
            rerouting.curr_edge = state.current_edge
            return TrackerResult.INTERRUPTED
        return None

    def _is_boundary(self) -> bool:
        assert self.route is not None
        idx = self.state.route_edges_idx
        return idx == len(self.route.edges) - 1 or (idx == -1 and self.state.current_edge is None)

    def node_achieved(self, pose: Pose2D) -> bool:
        state, route = self.state, self.route
        assert state.next_node is not None and route is not None
        dx, dy = state.next_node.x - pose.x, state.next_node.y - pose.y
        dist = fmath.hypot(dx, dy)
        boundary = self._is_boundary()
        in_radius = dist <= (self.boundary_radius if boundary else self.radius)
        if dist < 1e-4 or (not in_radius and state.within_radius):
            return True
        state.within_radius = in_radius
        if boundary:
            return in_radius
        if not in_radius:
            return False
        assert state.current_edge is not None
        last = state.current_edge.start
        nx, ny = state.next_node.x - last.x, state.next_node.y - last.y
        after = route.edges[state.route_edges_idx + 1].end
        mx, my = after.x - state.next_node.x, after.y - state.next_node.y
        n_mag, m_mag = fmath.hypot(nx, ny), fmath.hypot(mx, my)
        if n_mag < 1e-6 or m_mag < 1e-6:
            return True
        bx, by = nx * m_mag + mx * n_mag, ny * m_mag + my * n_mag
        return normalized_dot(bx, by, dx, dy) <= 0.0
