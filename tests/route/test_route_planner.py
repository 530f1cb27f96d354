"""The route planner takes the cheapest route by its edge scorers, each scorer one way."""

from __future__ import annotations

import math

import numpy as np
import pytest

from btnav.core.geometry import Pose2D
from btnav.costmap.costmap_2d import Costmap2D
from btnav.route import plugins as _plugins  # noqa: F401
from btnav.route.context import RouteContext
from btnav.route.edge_cost_functions.costmap_scorer import CostmapScorer
from btnav.route.edge_cost_functions.distance_scorer import DistanceScorer
from btnav.route.edge_cost_functions.dynamic_edges_scorer import DynamicEdgesScorer
from btnav.route.edge_cost_functions.orientation_scorers import (
    GoalOrientationScorer,
    StartPoseOrientationScorer,
)
from btnav.route.edge_cost_functions.penalty_scorer import PenaltyScorer
from btnav.route.edge_cost_functions.semantic_scorer import SemanticScorer
from btnav.route.edge_cost_functions.time_scorer import TimeScorer
from btnav.route.edge_scorer import EdgeScorer
from btnav.route.exceptions import (
    InvalidEdgeScorerUse,
    NoValidGraph,
    NoValidRouteCouldBeFound,
    RouteTimedOut,
)
from btnav.route.graph import RouteRequest
from btnav.route.route_planner import RoutePlanner

from .graphs import diamond, edge_id, graph

ABOVE, BELOW = [0, 1, 3], [0, 2, 3]


def route_ids(planner: RoutePlanner, g, start: int = 0, goal: int = 3, **kw) -> list[int]:  # type: ignore[no-untyped-def]
    return [n.nodeid for n in planner.find_route(g, start, goal, **kw).nodes]


def by(*scorers) -> RoutePlanner:  # type: ignore[no-untyped-def]
    return RoutePlanner(EdgeScorer(list(scorers)))


def test_distance_takes_the_short_way_and_a_speed_limit_makes_an_edge_longer() -> None:
    assert route_ids(by(DistanceScorer("d")), diamond()) == ABOVE
    route = by(DistanceScorer("d")).find_route(diamond(), 0, 3)
    assert route.route_cost == pytest.approx(2 * math.hypot(2, 1))
    slow = diamond({(0, 1): {"speed_limit": 0.25}})  # a quarter speed: 4x the cost
    assert route_ids(by(DistanceScorer("d")), slow) == BELOW


def test_time_prefers_the_faster_edges_and_the_measured_time() -> None:
    fast_below = diamond({(0, 2): {"abs_speed_limit": 2.0}, (2, 3): {"abs_speed_limit": 2.0}})
    assert route_ids(by(TimeScorer("t")), diamond()) == ABOVE
    assert route_ids(by(TimeScorer("t")), fast_below) == BELOW
    measured = diamond({(1, 3): {"abs_time_taken": 60.0}})  # TimeMarker's record of a slow edge
    assert route_ids(by(TimeScorer("t")), measured) == BELOW


def test_penalty_and_semantic_class_push_the_route_off_the_short_way() -> None:
    penalised = diamond({(0, 1): {"penalty": 5.0}})
    assert route_ids(by(DistanceScorer("d"), PenaltyScorer("p")), penalised) == BELOW
    classes = SemanticScorer.Params(semantic_classes=["kitchen"], kitchen=10.0)
    kitchen = diamond({(0, 1): {"class": "kitchen"}})
    assert route_ids(by(DistanceScorer("d"), SemanticScorer("s", classes)), kitchen) == BELOW
    by_key = SemanticScorer.Params(semantic_classes=["kitchen"], kitchen=10.0, semantic_key="")
    keyed = diamond({(0, 1): {"kitchen": "any value"}})
    assert route_ids(by(DistanceScorer("d"), SemanticScorer("s", by_key)), keyed) == BELOW


def test_semantic_classes_need_their_costs() -> None:
    with pytest.raises(ValueError, match="semantic class 'kitchen' needs its cost"):
        SemanticScorer.Params(semantic_classes=["kitchen"])


def test_costmap_scorer_refuses_an_edge_through_an_obstacle() -> None:
    costs = np.zeros((100, 100), np.uint8)  # 5 cm cells over x -0.5..4.5, y -3.5..1.5
    cm = Costmap2D(costs, 0.05, -0.5, -3.5)
    context = RouteContext.with_costmaps({"global_costmap/costmap_raw": cm})
    scorer = CostmapScorer("c")
    scorer.configure(context)
    assert route_ids(by(DistanceScorer("d"), scorer), diamond()) == ABOVE
    (mx, my), _ = cm.world_to_map([3.0, 0.5])  # on the edge 1 -> 3
    costs[my, mx] = 254
    assert route_ids(by(DistanceScorer("d"), scorer), diamond()) == BELOW
    # a cost below lethal adds to the edge's score as a fraction of max_cost
    costs[:] = 0
    scorer.prepare()
    edge = diamond().node(0).neighbors[0]
    request = RouteRequest(0, 3, Pose2D(), Pose2D(), True)
    assert scorer.score(edge, request, 0) == 0.0
    costs[:] = 100
    assert scorer.score(edge, request, 0) == pytest.approx(100 / 253)


def _request(start_yaw: float = 0.0, goal_yaw: float = 0.0) -> RouteRequest:
    return RouteRequest(0, 3, Pose2D(0, 0, start_yaw), Pose2D(4, 0, goal_yaw), True)


def test_orientation_scorers_leave_and_arrive_facing_the_requested_way() -> None:
    thresholded = {"use_orientation_threshold": True, "orientation_tolerance": 1.0}
    start = StartPoseOrientationScorer("s", StartPoseOrientationScorer.Params(**thresholded))
    goal = GoalOrientationScorer("g", GoalOrientationScorer.Params(**thresholded))
    g = diamond()
    # leaving facing down (-90 degrees): only the edge towards node 2 is within 1 rad
    facing_down = _request(start_yaw=-math.pi / 2)
    assert route_ids(by(DistanceScorer("d"), start), g, request=facing_down) == BELOW
    # arriving facing up: only the edge 2 -> 3 (heading up-right) is within 1 rad
    arrive_up = _request(goal_yaw=math.pi / 2)
    assert route_ids(by(DistanceScorer("d"), goal), g, request=arrive_up) == BELOW
    assert route_ids(by(DistanceScorer("d"), goal), g, request=_request()) == ABOVE
    # weighted (no threshold): the angle off the pose adds to the cost
    weighted = GoalOrientationScorer("g", GoalOrientationScorer.Params(orientation_weight=10.0))
    assert route_ids(by(DistanceScorer("d"), weighted), g, request=arrive_up) == BELOW
    by_ids = RouteRequest(0, 3, Pose2D(), Pose2D(), False)
    with pytest.raises(InvalidEdgeScorerUse):
        by(goal).find_route(g, 0, 3, request=by_ids)


def test_dynamic_edges_close_and_reopen_and_blocked_ids_are_avoided() -> None:
    dynamic = DynamicEdgesScorer("dyn")
    planner = by(DistanceScorer("d"), dynamic)
    dynamic.adjust_edges(closed_edges=[edge_id(1, 3)])
    assert route_ids(planner, diamond()) == BELOW
    dynamic.adjust_edges(opened_edges=[edge_id(1, 3)], adjust_edges={edge_id(0, 1): 9.0})
    assert route_ids(planner, diamond()) == BELOW  # now open, but 9 dearer
    dynamic.adjust_edges(adjust_edges={edge_id(0, 1): 0.0})
    assert route_ids(planner, diamond()) == ABOVE
    assert route_ids(planner, diamond(), blocked_ids=[edge_id(0, 1)]) == BELOW
    assert route_ids(planner, diamond(), blocked_ids=[1]) == BELOW  # a blocked node


def test_no_route_no_cost_and_too_few_iterations_are_route_errors() -> None:
    one_way = graph({0: (0, 0), 1: (1, 0)}, [(0, 1)], both_ways=False)
    with pytest.raises(NoValidRouteCouldBeFound):
        by(DistanceScorer("d")).find_route(one_way, 1, 0)
    with pytest.raises(NoValidGraph, match="Edge 101"):
        by().find_route(one_way, 0, 1)  # no scorers: the file's cost, which is 0
    one_way.node(0).neighbors[0].cost = 3.0
    assert by().find_route(one_way, 0, 1).route_cost == 3.0
    with pytest.raises(RouteTimedOut):
        RoutePlanner(EdgeScorer([DistanceScorer("d")]), max_iterations=1).find_route(
            diamond(), 0, 3
        )


def test_an_edge_that_is_not_overridable_keeps_its_cost() -> None:
    g = diamond()
    for edge in g.node(0).neighbors:
        if edge.end.nodeid == 2:
            edge.cost, edge.overridable = 0.1, False
    assert route_ids(by(DistanceScorer("d")), g) == BELOW
