"""Nav2's route_server (nav2_route): routes on a graph and tracks the robot along them.

`RouteServer(runtime, params, costmaps, controller_server=...)` loads the graph named by
`graph_filepath` (its `graph_file_loader` plugin; GeoJSON), builds the
`edge_cost_functions` and `operations` plugins of its params section and serves Nav2's
two actions:

- `compute_route` (ComputeRoute): goal `ComputeRouteGoal` (start and goal node ids, or
  poses with `use_poses`; the start is the robot's pose unless `use_start`); the result's
  value is a `ComputeRouteResult`: the sparse `route` (nav2_msgs/Route) and its dense
  `path` (a pose every `path_density` m, corners rounded with `smooth_corners`).
- `compute_and_track_route` (ComputeAndTrackRoute): the same route, then the robot is
  tracked along it at `tracker_update_rate`: feedback on each node passed (with the
  route and path), route operations run (speed limits, reroute requests, the route's
  collision monitor), a reroute when an operation asks; it succeeds when the route's
  last node is achieved. Nothing is driven: a tree follows the feedback's path.

A route failure is the action's error code (NO_VALID_ROUTE, TIMEOUT, TF_ERROR,
NO_VALID_GRAPH, INDETERMINANT_NODES_ON_GRAPH, INVALID_EDGE_SCORER_USE,
OPERATION_FAILED), never an exception in the caller. Routing finishes within the server
cycle the goal starts in (no sim time passes while the graph is searched).

The costmaps are Nav2's topics: `global_costmap/costmap_raw` is the global costmap
server, `local_costmap/costmap_raw` the local one, each seen from the route's frame.
Services: `route_server/set_route_graph`, `route_server/<DynamicEdgesScorer>/adjust_edges`,
`route_server/<ReroutingService>/reroute`; `trigger_services` holds the services a
TriggerEvent operation may call (a program adds its own: `{"open_door": fn}`).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..core.error_codes import ComputeAndTrackRouteError, ComputeRouteError, NavErrorCode, NavResult
from ..core.errors import FrameError
from ..core.geometry import Pose2D
from ..core.messages import Path as NavPath
from ..core.messages import PoseStamped
from ..core.nav2_route_msgs import (
    ComputeAndTrackRouteFeedback,
    ComputeAndTrackRouteGoal,
    ComputeAndTrackRouteResult,
    ComputeRouteGoal,
    ComputeRouteResult,
    RouteEdge,
    RouteNode,
)
from ..core.nav2_route_msgs import Route as RouteMsg
from ..params.paramsfile import ServerParams
from ..route import plugins as _route_plugins  # noqa: F401  (registers nav2_route's plugins)
from ..route.context import CostmapView, RouteContext
from ..route.edge_scorer import EdgeScorer
from ..route.exceptions import NoValidGraph, RouteException, RouteTFError
from ..route.goal_intent_extractor import ExtractorParams, GoalIntentExtractor, Intent
from ..route.graph import Graph, ReroutingState, Route, RouteRequest
from ..route.graph_files import resolve_graph_path
from ..route.operations_manager import OperationsManager
from ..route.path_converter import PathConverter
from ..route.route_planner import RoutePlanner
from ..route.route_tracker import RouteTracker, TrackerResult
from .actions import ActionServer, GoalHandle
from .runtime import Runtime, Stage
from .server_plugins import make_plugins

#: Nav2's costmap topics -> the costmap servers' names.
COSTMAP_TOPICS = {
    "global_costmap/costmap_raw": "global_costmap",
    "global_costmap/costmap": "global_costmap",
    "local_costmap/costmap_raw": "local_costmap",
    "local_costmap/costmap": "local_costmap",
}


def route_message(route: Route, frame: str, stamp: float) -> RouteMsg:
    """nav2_route's utils::toMsg: the route's nodes and edges as nav2_msgs/Route."""
    nodes = tuple(RouteNode(n.nodeid, n.x, n.y) for n in route.nodes)
    edges = tuple(
        RouteEdge(e.edgeid, (e.start.x, e.start.y), (e.end.x, e.end.y)) for e in route.edges
    )
    return RouteMsg(stamp, frame, float(route.route_cost), nodes, edges)


@dataclass
class _Tracking:
    """One ComputeAndTrackRoute goal's state between cycles."""

    goal: ComputeAndTrackRouteGoal
    rerouting: ReroutingState
    start_time: float
    route_msg: RouteMsg
    path: NavPath
    next_step: float = 0.0


class RouteServer:
    """route_server: the graph, the route search and tracking, and its two actions."""

    stage = Stage.SERVER

    def __init__(
        self,
        runtime: Runtime,
        params: ServerParams,
        costmaps: Mapping[str, Any],
        *,
        controller_server: Any = None,
        base_dir: Path | None = None,
        seed: int | None = None,
    ) -> None:
        self.runtime = runtime
        self.params = params
        self.costmaps = dict(costmaps)
        self.base_dir = base_dir
        self.seed = runtime.seed if seed is None else seed
        self.rate = 1.0 / runtime.physics_dt
        model = params.model
        #: Services a TriggerEvent operation may call, by name.
        self.trigger_services: dict[str, Callable[..., Any]] = {}
        set_speed_limit = getattr(controller_server, "set_speed_limit", None)
        self.context = RouteContext(
            route_frame=model.route_frame,
            base_frame=model.base_frame,
            costmap_topic=model.costmap_topic,
            costmaps=self.costmap_view,
            now=lambda: self.runtime.now,
            services=self.trigger_services,
            set_speed_limit=set_speed_limit,
        )
        self.scorers = make_plugins(params, "edge_cost_function", seed=self.seed)
        self.operations = make_plugins(params, "route_operation", seed=self.seed)
        for plugin in [*self.scorers.values(), *self.operations.values()]:
            plugin.configure(self.context)
        self.loader = next(iter(make_plugins(params, "graph_file_loader").values()))
        self.graph = Graph()
        if model.graph_filepath:
            self.graph = self.loader.load_graph(self._graph_path(model.graph_filepath))
        self._build()
        self._tracking: _Tracking | None = None
        self.compute_route: ActionServer[ComputeRouteGoal] = ActionServer(
            "ComputeRoute", "compute_route", on_start=self._compute
        )
        self.compute_and_track_route: ActionServer[ComputeAndTrackRouteGoal] = ActionServer(
            "ComputeAndTrackRoute",
            "compute_and_track_route",
            on_start=self._track_start,
            execute=self._track_step,
        )
        self.actions = [self.compute_route, self.compute_and_track_route]
        for action in self.actions:
            runtime.add_action_server(action)

    def _build(self) -> None:
        """The parts the server-level keys configure (again after set_parameters)."""
        m = self.params.model
        self.planner = RoutePlanner(EdgeScorer(list(self.scorers.values())), m.max_iterations)
        self.extractor = GoalIntentExtractor(
            self.graph,
            ExtractorParams(
                prune_goal=m.prune_goal,
                max_prune_dist_from_edge=m.max_prune_dist_from_edge,
                min_prune_dist_from_goal=m.min_prune_dist_from_goal,
                min_prune_dist_from_start=m.min_prune_dist_from_start,
                enable_nn_search=m.enable_nn_search,
                max_nn_search_iterations=m.max_nn_search_iterations,
                num_nearest_nodes=m.num_nearest_nodes,
            ),
        )
        self.converter = PathConverter(
            m.path_density, m.smooth_corners, m.smoothing_radius, m.smoothing_angle_threshold
        )
        self.tracker = RouteTracker(
            OperationsManager(self.operations),
            m.radius_to_achieve_node,
            m.boundary_radius_to_achieve_node,
            m.aggregate_blocked_ids,
        )

    def _graph_path(self, text: str) -> Path:
        return resolve_graph_path(text, self.base_dir)

    # -- the component ----------------------------------------------------------------------

    def update(self, now: float) -> None:
        for action in self.actions:
            action.update(now)

    # -- costmaps and frames ----------------------------------------------------------------

    def costmap_view(self, topic: str) -> CostmapView | None:
        """The costmap a topic names, with the route frame -> costmap frame transform."""
        server = self.costmaps.get(COSTMAP_TOPICS.get(topic.lstrip("/"), ""))
        if server is None:
            return None
        try:
            transform = self.runtime.lookup(server.global_frame, self.context.route_frame)
        except FrameError:
            return None
        return CostmapView(server.costmap, transform)

    def _in_route_frame(self, pose: Any) -> Pose2D:
        frame = self.context.route_frame
        if isinstance(pose, PoseStamped):
            p, source = pose.pose, pose.frame_id
        elif isinstance(pose, Pose2D):
            p, source = pose, frame
        else:
            p, source = Pose2D(*pose), frame
        if source == frame:
            return p
        try:
            return self.runtime.lookup(frame, source) @ p
        except FrameError as exc:
            raise RouteTFError(f"Failed to transform a pose to {frame}: {exc}") from None

    def robot_pose(self) -> Pose2D:
        try:
            return self.runtime.lookup(self.context.route_frame, self.context.base_frame)
        except FrameError as exc:
            raise RouteTFError(
                f"Failed to obtain the robot pose in {self.context.route_frame}: {exc}"
            ) from None

    # -- routing ----------------------------------------------------------------------------

    def _intent(self, goal: ComputeRouteGoal) -> Intent:
        if not goal.use_poses:
            return Intent(False, int(goal.start_id), int(goal.goal_id))
        if goal.goal is None:
            raise RouteException("a request by poses needs a goal pose")
        start = (
            self._in_route_frame(goal.start)
            if goal.use_start and goal.start is not None
            else self.robot_pose()
        )
        return Intent(True, start=start, goal=self._in_route_frame(goal.goal))

    def find_route(self, goal: ComputeRouteGoal, rerouting: ReroutingState) -> Route:
        """The pruned route for a request (nav2_route's RouteServer::findRoute)."""
        if len(self.graph) == 0:
            raise NoValidGraph("No graph set: graph_filepath is empty (or set_route_graph failed)")
        intent = self._intent(goal)
        view = self.costmap_view(self.context.costmap_topic)
        start_id, goal_id = self.extractor.find_start_and_goal(intent, view)
        if rerouting.rerouting_start_id is not None:
            start_id = rerouting.rerouting_start_id
            assert rerouting.rerouting_start_pose is not None
            self.extractor.override_start(rerouting.rerouting_start_pose)
        if start_id == goal_id:
            route = Route(self.graph.node(start_id), [], 0.0)
        else:
            request = RouteRequest(
                start_id, goal_id, self.extractor.start, self.extractor.goal, intent.use_poses
            )
            route = self.planner.find_route(
                self.graph, start_id, goal_id, rerouting.blocked_ids, request
            )
        return self.extractor.prune_start_and_goal(route, intent, rerouting, self.planner)

    def _result(
        self, codes: type[NavErrorCode], work: Callable[[], NavResult | None]
    ) -> NavResult | None:
        try:
            return work()
        except RouteException as exc:
            return NavResult.failure(codes[exc.code_name], str(exc))

    # -- ComputeRoute -----------------------------------------------------------------------

    def _compute(self, handle: GoalHandle[ComputeRouteGoal], now: float) -> NavResult | None:
        def work() -> NavResult:
            rerouting = ReroutingState()
            route = self.find_route(handle.goal, rerouting)
            frame = self.context.route_frame
            path = self.converter.densify(route, rerouting, frame, now)
            return NavResult.success(ComputeRouteResult(route_message(route, frame, now), path))

        return self._result(ComputeRouteError, work)

    # -- ComputeAndTrackRoute ---------------------------------------------------------------

    def _route_and_track(self, handle: GoalHandle[ComputeAndTrackRouteGoal], now: float) -> None:
        tracking = self._tracking
        assert tracking is not None
        route = self.find_route(tracking.goal, tracking.rerouting)
        frame = self.context.route_frame
        tracking.path = self.converter.densify(route, tracking.rerouting, frame, now)
        tracking.route_msg = route_message(route, frame, now)

        def feedback(
            rerouted: bool, next_id: int, last_id: int, edge_id: int, ops: list[str]
        ) -> None:
            handle.publish_feedback(
                ComputeAndTrackRouteFeedback(
                    last_id,
                    next_id,
                    edge_id,
                    tracking.route_msg,
                    tracking.path,
                    tuple(ops),
                    rerouted,
                ),
                self.runtime.now,
            )

        self.tracker.start(route, tracking.rerouting, feedback)

    def _track_start(
        self, handle: GoalHandle[ComputeAndTrackRouteGoal], now: float
    ) -> NavResult | None:
        def work() -> NavResult | None:
            self._tracking = _Tracking(
                handle.goal, ReroutingState(), now, RouteMsg(), NavPath(now, np.zeros((0, 3)))
            )
            self._route_and_track(handle, now)
            return self._track_cycle(handle, now)

        return self._result(ComputeAndTrackRouteError, work)

    def _track_step(
        self, handle: GoalHandle[ComputeAndTrackRouteGoal], now: float
    ) -> NavResult | None:
        tracking = self._tracking
        if tracking is None or now < tracking.next_step - 1e-9:
            return None
        return self._result(ComputeAndTrackRouteError, lambda: self._track_cycle(handle, now))

    def _track_cycle(
        self, handle: GoalHandle[ComputeAndTrackRouteGoal], now: float
    ) -> NavResult | None:
        tracking = self._tracking
        assert tracking is not None
        tracking.next_step = now + 1.0 / self.params.model.tracker_update_rate
        outcome = self.tracker.step(self.robot_pose(), tracking.rerouting)
        if outcome is TrackerResult.COMPLETED:
            self._tracking = None
            return NavResult.success(ComputeAndTrackRouteResult(now - tracking.start_time))
        if outcome is TrackerResult.INTERRUPTED:
            self._route_and_track(handle, now)
        return None

    # -- services ---------------------------------------------------------------------------

    def set_route_graph(self, graph_filepath: str) -> bool:
        """nav2_msgs/SetRouteGraph: load another graph; False (graph emptied) if it fails."""
        self.graph = Graph()
        try:
            self.graph = self.loader.load_graph(self._graph_path(graph_filepath))
        except Exception:
            self.extractor.set_graph(self.graph)
            return False
        self.extractor.set_graph(self.graph)
        return True

    def services(self) -> dict[str, Callable[..., Any]]:
        out: dict[str, Callable[..., Any]] = {"route_server/set_route_graph": self.set_route_graph}
        for name, plugin in [*self.scorers.items(), *self.operations.items()]:
            for service, fn in plugin.services().items():
                out[f"route_server/{name}/{service}"] = fn
        return out

    # -- dynamic parameters -----------------------------------------------------------------

    def set_parameters(self, params: ServerParams) -> None:
        """Apply params `validate_update` accepted: plugins take their new sections, and the
        search, the path and the tracker their new keys (from the next request on)."""
        self.params = params
        for name, section in params.plugins.items():
            plugin = self.scorers.get(name) or self.operations.get(name)
            if plugin is not None and section.params is not None:
                plugin.params = section.params
        self._build()

    def __repr__(self) -> str:
        return f"RouteServer({len(self.graph)} nodes, from {self.graph.source or 'no file'})"


def bring_up_route_server(stack: Any) -> RouteServer | None:
    """Nav2's launch starts route_server with the graph its `graph` argument names: here,
    when the params file has a `route_server` section with a `graph_filepath` (a mission's
    `route_graph:` writes it there); otherwise nothing is added."""
    pf = stack.params
    if "route_server" not in pf.servers:
        return None
    params = pf.server("route_server")
    if not params.model.graph_filepath:
        return None
    server = RouteServer(
        stack.runtime,
        params,
        {"global_costmap": stack.global_costmap, "local_costmap": stack.local_costmap},
        controller_server=stack.controller_server,
        base_dir=pf.path.parent,
    )
    return stack.add_server("route_server", stack.runtime.add(server))  # type: ignore[no-any-return]
