"""nav2_route's RoutePlanner: Dijkstra's search over the graph's directed edges.

Each edge costs what the edge scorers say (their sum), or its own `cost` when it is not
`overridable` or no scorer is loaded (a cost of zero or less is then NO_VALID_GRAPH).
An edge in `blocked_ids`, or one leading to a node in it, is not expanded; nor is one a
scorer refuses. The search stops at the goal; `max_iterations` (0: no limit) bounds
the nodes it takes from the queue (TIMEOUT past it).
"""

from __future__ import annotations

import heapq
from collections.abc import Collection
from dataclasses import dataclass

from ..core.geometry import Pose2D
from .edge_scorer import EdgeScorer
from .exceptions import NoValidGraph, NoValidRouteCouldBeFound, RouteTimedOut
from .graph import DirectionalEdge, EdgeType, Graph, Route, RouteRequest


@dataclass
class _Search:
    cost: float
    parent: DirectionalEdge | None = None
    #: The cost of the edge that reached the node (the goal intent extractor's pruning).
    traversal: float = 0.0


class RoutePlanner:
    def __init__(self, scorer: EdgeScorer | None = None, max_iterations: int = 0) -> None:
        self.scorer = scorer if scorer is not None else EdgeScorer([])
        self.max_iterations = max_iterations if max_iterations > 0 else None
        #: Each reached node's search state (by node id), kept after the search for pruning.
        self.states: dict[int, _Search] = {}

    def find_route(
        self,
        graph: Graph,
        start_id: int,
        goal_id: int,
        blocked_ids: Collection[int] = (),
        request: RouteRequest | None = None,
    ) -> Route:
        if len(graph) == 0:
            raise NoValidGraph("Graph is invalid for routing!")
        start, goal = graph.node(start_id), graph.node(goal_id)
        if request is None:
            request = RouteRequest(start_id, goal_id, Pose2D(), Pose2D(), False)
        blocked = set(blocked_ids)
        states = self.states = {start_id: _Search(0.0)}
        queue: list[tuple[float, int, int]] = [(0.0, 0, start_id)]  # (cost, order, node id)
        pushes = 1
        iterations = 0
        while queue:
            if self.max_iterations is not None and iterations >= self.max_iterations:
                raise RouteTimedOut("Maximum iterations was exceeded!")
            iterations += 1
            cost, _, nodeid = heapq.heappop(queue)
            if cost != states[nodeid].cost:
                continue  # reached again more cheaply since this entry was queued
            if nodeid == goal_id:
                break
            for edge in graph.node(nodeid).neighbors:
                traversal = self._traversal_cost(edge, blocked, request, start_id, goal_id)
                if traversal is None:
                    continue
                total = cost + traversal
                there = states.get(edge.end.nodeid)
                if there is None or total < there.cost:
                    states[edge.end.nodeid] = _Search(total, edge, traversal)
                    heapq.heappush(queue, (total, pushes, edge.end.nodeid))
                    pushes += 1
        reached = states.get(goal.nodeid)
        if reached is None or (reached.parent is None and goal is not start):
            raise NoValidRouteCouldBeFound("Could not find a route to the requested goal!")
        edges: list[DirectionalEdge] = []
        node = goal
        while node is not start:
            edge = states[node.nodeid].parent
            assert edge is not None
            edges.append(edge)
            node = edge.start
        edges.reverse()
        return Route(start, edges, reached.cost)

    def traversal_cost(self, nodeid: int) -> float:
        """The cost of the edge by which the last search reached `nodeid`."""
        state = self.states.get(nodeid)
        return state.traversal if state is not None else 0.0

    def _traversal_cost(
        self,
        edge: DirectionalEdge,
        blocked: set[int],
        request: RouteRequest,
        start_id: int,
        goal_id: int,
    ) -> float | None:
        if edge.edgeid in blocked or edge.end.nodeid in blocked:
            return None
        if not edge.overridable or len(self.scorer) == 0:
            if edge.cost <= 0.0:
                raise NoValidGraph(
                    f"Edge {edge.edgeid} doesn't contain and cannot compute a valid edge cost!"
                )
            return edge.cost
        if edge.start.nodeid == start_id:
            kind = EdgeType.START
        elif edge.end.nodeid == goal_id:
            kind = EdgeType.END
        else:
            kind = EdgeType.NONE
        return self.scorer.score(edge, request, kind)
