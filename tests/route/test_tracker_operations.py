"""Route tracking along a driven line: nodes achieved in order, operations run at their
moments (speed limits, graph operations, the route's collision monitor, reroutes)."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from btnav.core.geometry import Pose2D
from btnav.costmap.costmap_2d import Costmap2D
from btnav.route.context import CostmapView, RouteContext
from btnav.route.exceptions import OperationFailed
from btnav.route.graph import Operation, OperationTrigger, ReroutingState, Route
from btnav.route.operations_manager import OperationsManager
from btnav.route.route_operations.adjust_speed_limit import AdjustSpeedLimit
from btnav.route.route_operations.collision_monitor import CollisionMonitor
from btnav.route.route_operations.rerouting_service import ReroutingService
from btnav.route.route_operations.time_marker import TimeMarker
from btnav.route.route_operations.trigger_event import TriggerEvent
from btnav.route.route_tracker import RouteTracker, TrackerResult

from .graphs import edge_id, graph


def zigzag() -> Route:
    """0 (0, 0) -> 1 (4, 0) -> 2 (4, 4) -> 3 (8, 4), one way."""
    g = graph(
        {0: (0.0, 0.0), 1: (4.0, 0.0), 2: (4.0, 4.0), 3: (8.0, 4.0)},
        [(0, 1), (1, 2), (2, 3)],
        {(1, 2): {"speed_limit": 40.0}},
        both_ways=False,
    )
    return Route(g.node(0), [g.node(i).neighbors[0] for i in range(3)])


def drive(route: Route, step: float = 0.05):  # type: ignore[no-untyped-def]
    """Poses along the route's polyline, a little off it (as a controller would be)."""
    pts = np.array([(n.x, n.y) for n in route.nodes])
    for a, b in itertools.pairwise(pts):
        n = int(np.hypot(*(b - a)) / step)
        for t in np.arange(n) / n:
            x, y = a + (b - a) * t
            yield Pose2D(float(x) + 0.1, float(y) - 0.1)
    yield Pose2D(*pts[-1])


class Clock:
    def __init__(self) -> None:
        self.t = 0.0

    def __call__(self) -> float:
        return self.t


def track(route: Route, operations: dict, context: RouteContext, clock: Clock) -> tuple:  # type: ignore[type-arg]
    for op in operations.values():
        op.configure(context)
    tracker = RouteTracker(OperationsManager(operations), 1.0, 0.5)
    feedback: list[tuple] = []  # type: ignore[type-arg]
    rerouting = ReroutingState()
    tracker.start(route, rerouting, lambda *fb: feedback.append(fb))
    outcome = None
    for pose in drive(route):
        clock.t += 0.1
        outcome = tracker.step(pose, rerouting)
        if outcome is not None:
            break
    return outcome, feedback, rerouting


def test_nodes_are_achieved_in_order_and_speed_limits_follow_the_edges() -> None:
    limits: list[tuple[float, bool]] = []
    clock = Clock()
    context = RouteContext(now=clock, set_speed_limit=lambda v, pct: limits.append((v, pct)))
    ops = {
        "AdjustSpeedLimit": AdjustSpeedLimit("AdjustSpeedLimit"),
        "TimeMarker": TimeMarker("TimeMarker"),
    }
    route = zigzag()
    outcome, feedback, _ = track(route, ops, context, clock)
    assert outcome is TrackerResult.COMPLETED
    passed = [fb[2] for fb in feedback if not fb[0]]  # last_node_id of each change
    assert passed == [0, 1, 2, 3]
    assert feedback[0][0] is True  # the first feedback: a (new) route
    # 100% on the first edge, 40% on the marked one, 100% after it
    assert limits == [(100.0, True), (40.0, True), (100.0, True)]
    # TimeMarker wrote the time taken on each edge (4 m at 5 cm a step, 0.1 s a step)
    taken = [e.metadata.get("abs_time_taken") for e in route.edges]
    assert taken[:2] == [pytest.approx(8.0, abs=0.3)] * 2
    assert 6.0 < taken[2] < 7.5  # the last node is achieved on entering its 0.5 m radius


def test_a_graph_operation_calls_its_service_and_an_unknown_one_fails() -> None:
    route = zigzag()
    route.edges[1].end.operations.append(
        Operation("open_door", OperationTrigger.NODE, {"service_name": "door_42"})
    )
    calls: list[str] = []
    clock = Clock()
    context = RouteContext(now=clock, services={"door_42": lambda: calls.append("open")})
    outcome, feedback, _ = track(route, {"open_door": TriggerEvent("open_door")}, context, clock)
    assert outcome is TrackerResult.COMPLETED and calls == ["open"]
    assert any("open_door" in fb[4] for fb in feedback)
    with pytest.raises(OperationFailed, match="Operation open_door does not exist"):
        track(zigzag_with_op(), {}, RouteContext(now=Clock()), Clock())


def zigzag_with_op() -> Route:
    route = zigzag()
    route.edges[0].operations.append(Operation("open_door", OperationTrigger.ON_EXIT))
    return route


def test_the_collision_monitor_reroutes_round_a_blocked_edge_ahead() -> None:
    costs = np.zeros((120, 200), np.uint8)  # 10 x 6 m at 5 cm, from (-1, -1)
    cm = Costmap2D(costs, 0.05, -1.0, -1.0)
    (mx, my), _ = cm.world_to_map([4.0, 2.0])  # on the edge 1 -> 2
    costs[my, mx] = 254
    clock = Clock()
    context = RouteContext(now=clock, costmaps={"local_costmap/costmap_raw": CostmapView(cm)}.get)
    monitor = CollisionMonitor("CollisionMonitor", CollisionMonitor.Params(max_collision_dist=3.0))
    outcome, _, rerouting = track(zigzag(), {"CollisionMonitor": monitor}, context, clock)
    assert outcome is TrackerResult.INTERRUPTED
    assert rerouting.blocked_ids == [edge_id(1, 2)]
    assert rerouting.rerouting_start_id == 0  # the last node passed: the start
    # seen within 3 m, not before: the robot was on the first edge, past x = 1
    assert rerouting.rerouting_start_pose.x >= 1.0
    fail = CollisionMonitor("cm", CollisionMonitor.Params(reroute_on_collision=False))
    clock.t = 0.0
    with pytest.raises(OperationFailed, match="rerouting is not enabled"):
        track(zigzag(), {"cm": fail}, context, clock)


def test_a_reroute_request_interrupts_tracking() -> None:
    service = ReroutingService("ReroutingService")
    clock = Clock()
    route = zigzag()
    service.configure(RouteContext(now=clock))
    tracker = RouteTracker(OperationsManager({"ReroutingService": service}), 1.0, 0.5)
    rerouting = ReroutingState()
    tracker.start(route, rerouting, lambda *fb: None)
    assert tracker.step(Pose2D(0.5, 0.0), rerouting) is None
    assert service.services()["reroute"]() == (True, "")
    assert tracker.step(Pose2D(0.6, 0.0), rerouting) is TrackerResult.INTERRUPTED
