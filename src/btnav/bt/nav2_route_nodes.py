"""Nav2's route server nodes: ComputeRoute, ComputeAndTrackRoute, CancelComputeAndTrackRoute,
ExtractRouteNodesAsGoals and the WouldARouteRecoveryHelp condition.

ComputeRoute and ComputeAndTrackRoute ask the route server (`compute_route`,
`compute_and_track_route`) for a route by node ids (`start_id`, `goal_id`) or, with
`use_poses`, by poses (`goal`, and `start` with `use_start`; else the robot's pose).
ComputeRoute writes the sparse `route` (nav2_msgs/Route) and its dense `path`;
ComputeAndTrackRoute writes, from each feedback, the route and path (a reroute makes a
new one), the node ids passed and ahead and the current edge, and on a changed request
sends it again.
"""

from __future__ import annotations

from typing import Any, ClassVar

from py_trees.common import Status

from ..core.error_codes import ComputeAndTrackRouteError, ComputeRouteError, NavResult
from ..core.geometry import Pose2D
from ..core.messages import Path, PoseStamped
from ..core.nav2_route_msgs import (
    ComputeAndTrackRouteFeedback,
    ComputeAndTrackRouteGoal,
    ComputeRouteGoal,
    Route,
)
from ..plugins import register
from .base import F, S, input_port, output_port
from .nav2_actions import BASIC_INPUTS, BASIC_OUTPUTS, BtActionNode, _cancel_node
from .nav2_conditions import AreErrorCodesPresent, _codes
from .nav2_context import Nav2Leaf, PoseLike, empty_path, same_goal

#: The request ports both route actions take (Nav2's ComputeRoute's and its tracking
#: twin's), in Nav2's order.
REQUEST_PORTS: dict[str, Any] = {
    "start": input_port(
        PoseLike, "Start pose of the path if overriding current robot pose and using poses over IDs"
    ),
    "goal": input_port(PoseLike, "Goal pose of the path if using poses over IDs"),
    "start_id": input_port(int, "ID of the start node"),
    "goal_id": input_port(int, "ID of the goal node"),
    "use_start": input_port(
        bool, "Whether to use the start pose or the robot's current pose", False
    ),
    "use_poses": input_port(bool, "Whether to use poses or IDs for start and goal", False),
}


class _RouteRequestNode(BtActionNode):
    """The request both route actions send, from the ports (Nav2's `on_tick`)."""

    GOAL: ClassVar[type[ComputeRouteGoal]] = ComputeRouteGoal

    def make_goal(self) -> Any:
        if self.get_input("use_poses"):
            use_start = bool(self.get_input("use_start"))
            return self.GOAL(
                goal=self.optional("goal"),
                start=self.optional("start") if use_start else None,
                use_start=use_start,
                use_poses=True,
            )
        return self.GOAL(
            start_id=int(self.optional("start_id") or 0),
            goal_id=int(self.optional("goal_id") or 0),
            use_poses=False,
        )


@register("bt_node", "ComputeRoute")
class ComputeRoute(_RouteRequestNode):
    """Route on the graph; the route goes to `route`, its dense path to `path`."""

    ACTION = "ComputeRoute"
    SERVER = "compute_route"
    INPUT_PORTS: ClassVar = {**REQUEST_PORTS, **BASIC_INPUTS}
    OUTPUT_PORTS: ClassVar = {
        "route": output_port(Route, "The route computed by ComputeRoute node"),
        "path": output_port(Path, "Path created by ComputeRoute node"),
        "planning_time": output_port(float, "Time taken to compute route"),
        **BASIC_OUTPUTS,
    }

    def reset_ports(self) -> None:
        self._set_output("path", empty_path())
        self._set_output("route", Route())
        self._set_output("planning_time", 0.0)

    def on_success(self, result: NavResult) -> Status:
        self._set_output("path", result.value.path)
        self._set_output("route", result.value.route)
        self._set_output("planning_time", float(result.value.planning_time))
        return super().on_success(result)

    def on_aborted(self, result: NavResult) -> Status:
        self.reset_ports()
        return super().on_aborted(result)

    def on_cancelled(self) -> Status:
        self.reset_ports()
        return super().on_cancelled()

    def on_halt(self) -> None:
        self.reset_ports()


@register("bt_node", "ComputeAndTrackRoute")
class ComputeAndTrackRoute(_RouteRequestNode):
    """Route and have the server track the robot along it; RUNNING until the route's end."""

    ACTION = "ComputeAndTrackRoute"
    SERVER = "compute_and_track_route"
    GOAL = ComputeAndTrackRouteGoal
    INPUT_PORTS: ClassVar = {**REQUEST_PORTS, **BASIC_INPUTS}
    OUTPUT_PORTS: ClassVar = {
        "execution_duration": output_port(float, "Time taken to compute and track route"),
        "last_node_id": output_port(int, "ID of the previous node"),
        "next_node_id": output_port(int, "ID of the next node"),
        "current_edge_id": output_port(int, "ID of current edge"),
        "route": output_port(Route, "List of RouteNodes to go from start to end"),
        "path": output_port(Path, "Path created by ComputeAndTrackRoute node"),
        "rerouted": output_port(bool, "Whether the plan has rerouted"),
        **BASIC_OUTPUTS,
    }

    def on_wait_for_result(self, feedback: Any) -> None:
        wanted = self.make_goal()
        if not _same_request(self.goal, wanted):
            self.goal = wanted
            self.goal_updated = True
        if isinstance(feedback, ComputeAndTrackRouteFeedback):
            self._write_feedback(feedback)

    def _write_feedback(self, fb: ComputeAndTrackRouteFeedback) -> None:
        self._set_output("last_node_id", int(fb.last_node_id))
        self._set_output("next_node_id", int(fb.next_node_id))
        self._set_output("current_edge_id", int(fb.current_edge_id))
        self._set_output("route", fb.route)
        self._set_output("path", fb.path if fb.path is not None else empty_path())
        self._set_output("rerouted", bool(fb.rerouted))

    def _reset(self, duration: float = 0.0) -> None:
        self._write_feedback(ComputeAndTrackRouteFeedback())
        self._set_output("execution_duration", duration)

    def on_success(self, result: NavResult) -> Status:
        self._reset(float(getattr(result.value, "execution_duration", 0.0)))
        return super().on_success(result)

    def on_aborted(self, result: NavResult) -> Status:
        self._reset()
        return super().on_aborted(result)

    def on_cancelled(self) -> Status:
        self._reset()
        return super().on_cancelled()


def _same_request(a: Any, b: Any) -> bool:
    if a is None or b is None:
        return a is b
    if a.use_poses != b.use_poses:
        return False
    if not b.use_poses:
        return bool(a.start_id == b.start_id and a.goal_id == b.goal_id)
    if a.use_start != b.use_start or not same_goal(a.goal, b.goal):
        return False
    return not b.use_start or same_goal(a.start, b.start)


CancelComputeAndTrackRoute = _cancel_node("CancelComputeAndTrackRoute", "compute_and_track_route")


@register("bt_node", "ExtractRouteNodesAsGoals")
class ExtractRouteNodesAsGoals(Nav2Leaf):
    """The route's nodes as goal poses (in the route's frame); FAILURE for an empty route."""

    INPUT_PORTS: ClassVar = {"route": input_port(Route, "Route to extract nodes from")}
    OUTPUT_PORTS: ClassVar = {"goals": output_port(list, "Output goals for navigation")}

    def update(self) -> Status:
        route = self.optional("route")
        if route is None or not route.nodes:
            return F
        goals = [
            PoseStamped(route.stamp, Pose2D(float(n.x), float(n.y), 0.0), route.frame_id)
            for n in route.nodes
        ]
        self._set_output("goals", goals)
        return S


@register("bt_node", "WouldARouteRecoveryHelp")
class WouldARouteRecoveryHelp(AreErrorCodesPresent):
    """SUCCESS when a route action's `error_code` is one a recovery may fix."""

    DEFAULT_CODES = _codes(
        ComputeRouteError.UNKNOWN,
        ComputeRouteError.NO_VALID_ROUTE,
        ComputeRouteError.TIMEOUT,
        ComputeAndTrackRouteError.UNKNOWN,
        ComputeAndTrackRouteError.TIMEOUT,
        ComputeAndTrackRouteError.NO_VALID_ROUTE,
    )


__all__ = [
    "CancelComputeAndTrackRoute",
    "ComputeAndTrackRoute",
    "ComputeRoute",
    "ExtractRouteNodesAsGoals",
    "WouldARouteRecoveryHelp",
]
