"""nav2_route's GoalIntentExtractor: which graph nodes a request starts and ends at, and
the route's first and last edges pruned when the robot or the goal is already along them.

By node ids, the ids are the ends. By poses, each end is the nearest node; with
`enable_nn_search` and a costmap, when the straight line from the pose to that node
is blocked, the `num_nearest_nodes` nearest are searched breadth-first on the costmap
and the first reached is taken (a node behind a wall is not "nearest").

Pruning (requests by poses, or any reroute): the first edge is dropped when the start
projects onto it (past its first node by more than `min_prune_dist_from_start`, within
`max_prune_dist_from_edge` of it); the last edge when the goal projects onto it before
its end node (unless `prune_goal` is false), likewise.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from ..core import fmath
from ..core.geometry import Pose2D
from .context import CostmapView
from .exceptions import IndeterminantNodesOnGraph, RouteException
from .goal_intent_search import breadth_first_search, line_of_sight_blocked
from .graph import Graph, ReroutingState, Route, closest_point, normalized_dot
from .node_spatial_tree import NodeSpatialTree
from .route_planner import RoutePlanner

EPSILON = 1e-6


@dataclass(frozen=True)
class Intent:
    """A request with its poses in the route's frame (the start: the robot's, unless given)."""

    use_poses: bool
    start_id: int = 0
    goal_id: int = 0
    start: Pose2D = field(default_factory=Pose2D)
    goal: Pose2D = field(default_factory=Pose2D)


@dataclass(frozen=True)
class ExtractorParams:
    prune_goal: bool = True
    max_prune_dist_from_edge: float = 8.0
    min_prune_dist_from_goal: float = 0.15
    min_prune_dist_from_start: float = 0.10
    enable_nn_search: bool = True
    max_nn_search_iterations: int = 10000
    num_nearest_nodes: int = 5


class GoalIntentExtractor:
    def __init__(self, graph: Graph, params: ExtractorParams | None = None) -> None:
        self.params = params or ExtractorParams()
        self.tree = NodeSpatialTree(num_nearest_nodes=self.params.num_nearest_nodes)
        self.set_graph(graph)
        self.start = Pose2D()
        self.goal = Pose2D()

    def set_graph(self, graph: Graph) -> None:
        self.graph = graph
        self.tree.compute_tree(graph)

    def override_start(self, pose: Pose2D) -> None:
        """A reroute starts from where the robot is now."""
        self.start = pose

    # -- the ends -------------------------------------------------------------------------

    def find_start_and_goal(self, intent: Intent, costmap: CostmapView | None) -> tuple[int, int]:
        """The start and goal nodes' ids."""
        graph = self.graph
        if not intent.use_poses:
            for nodeid in (intent.start_id, intent.goal_id):
                if nodeid not in graph.id_to_index:
                    raise RouteException(f"node id {nodeid} is not in the route graph")
            self.start = _at(graph, intent.start_id)
            self.goal = _at(graph, intent.goal_id)
            return intent.start_id, intent.goal_id
        self.start, self.goal = intent.start, intent.goal
        start_nodes = self.tree.find_nearest_graph_nodes(intent.start.x, intent.start.y)
        goal_nodes = self.tree.find_nearest_graph_nodes(intent.goal.x, intent.goal.y)
        if not start_nodes or not goal_nodes:
            raise IndeterminantNodesOnGraph(
                "Could not determine node closest to start or goal pose requested!"
            )
        search = self.params.enable_nn_search and costmap is not None
        start_index = goal_index = None
        if search:
            assert costmap is not None
            start_index = self._searched(
                costmap, intent.start, start_nodes, self.params.max_nn_search_iterations
            )
            goal_index = self._searched(costmap, intent.goal, goal_nodes, None)
        start = start_nodes[start_index if start_index is not None else 0]
        goal = goal_nodes[goal_index if goal_index is not None else 0]
        return graph.nodes[start].nodeid, graph.nodes[goal].nodeid

    def _searched(
        self, costmap: CostmapView, pose: Pose2D, nodes: list[int], limit: int | None
    ) -> int | None:
        """Which candidate the costmap search picks, or None to keep the nearest."""
        if len(nodes) < 2:
            return None
        xy = [(self.graph.nodes[i].x, self.graph.nodes[i].y) for i in nodes]
        if not line_of_sight_blocked(costmap, xy[0], (pose.x, pose.y)):
            return None  # off the map (None) or in plain sight: the nearest it is
        return breadth_first_search(costmap, (pose.x, pose.y), xy, limit)

    # -- pruning --------------------------------------------------------------------------

    def prune_start_and_goal(
        self, route: Route, intent: Intent, rerouting: ReroutingState, planner: RoutePlanner
    ) -> Route:
        pruned = Route(route.start_node, list(route.edges), route.route_cost)
        last_curr_edge = rerouting.curr_edge
        rerouting.curr_edge = None
        first_time = rerouting.first_time
        rerouting.first_time = False
        if not route.edges or (not intent.use_poses and first_time):
            return pruned
        p = self.params
        first, nxt = pruned.start_node, pruned.edges[0].end
        vpx, vpy = self.start.x - first.x, self.start.y - first.y
        dot = normalized_dot(nxt.x - first.x, nxt.y - first.y, vpx, vpy)
        cx, cy = closest_point(self.start.x, self.start.y, first, nxt)
        if (
            dot > EPSILON
            and fmath.hypot(vpx, vpy) > p.min_prune_dist_from_start
            and fmath.hypot(cx - self.start.x, cy - self.start.y) <= p.max_prune_dist_from_edge
        ):
            if last_curr_edge is not None and last_curr_edge.edgeid == pruned.edges[0].edgeid:
                rerouting.closest_pt_on_edge = (cx, cy)
                rerouting.curr_edge = pruned.edges[0]
            pruned.start_node = nxt
            pruned.route_cost -= planner.traversal_cost(nxt.nodeid)
            pruned.edges.pop(0)
        if not p.prune_goal or not intent.use_poses or not pruned.edges:
            return pruned
        before, last = pruned.edges[-1].start, pruned.edges[-1].end
        vpx, vpy = self.goal.x - last.x, self.goal.y - last.y
        dot = normalized_dot(last.x - before.x, last.y - before.y, vpx, vpy)
        cx, cy = closest_point(self.goal.x, self.goal.y, before, last)
        if (
            dot < -EPSILON
            and fmath.hypot(vpx, vpy) > p.min_prune_dist_from_goal
            and fmath.hypot(cx - self.goal.x, cy - self.goal.y) <= p.max_prune_dist_from_edge
        ):
            pruned.route_cost -= planner.traversal_cost(last.nodeid)
            pruned.edges.pop()
        return pruned


def _at(graph: Graph, nodeid: int) -> Pose2D:
    node = graph.node(nodeid)
    return Pose2D(node.x, node.y, 0.0)
