"""Which nodes a request by poses starts and ends at: the nearest, unless a wall is in the
way (then the nearest reachable on the costmap); and the first edge pruned when the robot
is already along it."""

from __future__ import annotations

import numpy as np

from btnav.core.geometry import Pose2D
from btnav.costmap.costmap_2d import Costmap2D
from btnav.route.context import CostmapView
from btnav.route.edge_cost_functions.distance_scorer import DistanceScorer
from btnav.route.edge_scorer import EdgeScorer
from btnav.route.goal_intent_extractor import ExtractorParams, GoalIntentExtractor, Intent
from btnav.route.graph import ReroutingState
from btnav.route.route_planner import RoutePlanner

from .graphs import graph

NODES = {0: (1.0, 1.0), 1: (3.0, 1.0), 2: (5.0, 1.0), 3: (5.0, 3.0)}


def walled() -> CostmapView:
    """6 x 4 m at 5 cm; a wall along x = 2 from y = 0 to 2.5 (a gap above)."""
    costs = np.zeros((80, 120), np.uint8)
    costs[:50, 39:42] = 254
    return CostmapView(Costmap2D(costs, 0.05))


def test_the_nearest_node_unless_a_wall_hides_it() -> None:
    g = graph(NODES, [(0, 1), (1, 2), (2, 3)])
    extractor = GoalIntentExtractor(g)
    intent = Intent(True, start=Pose2D(2.2, 1.0), goal=Pose2D(5.2, 3.0))
    assert extractor.find_start_and_goal(intent, None) == (1, 3)  # straight-line nearest
    # node 0 is 1.2 m away through the wall, node 1 0.8 m in plain sight: still node 1
    assert extractor.find_start_and_goal(intent, walled()) == (1, 3)
    # just left of the wall, node 1 (1.0 m) is behind it and node 0 (0.9 m) is not
    left = Intent(True, start=Pose2D(1.9, 1.0), goal=Pose2D(5.2, 3.0))
    assert extractor.find_start_and_goal(left, None) == (0, 3)
    # right of the wall, node 0 is nearer in a straight line but the search reaches node 1
    g2 = graph({0: (1.2, 1.0), 1: (3.2, 1.0), 3: (5.0, 3.0)}, [(0, 1), (1, 3)])
    right = Intent(True, start=Pose2D(2.15, 1.0), goal=Pose2D(5.2, 3.0))
    ex2 = GoalIntentExtractor(g2)
    assert ex2.find_start_and_goal(right, None)[0] == 0
    assert ex2.find_start_and_goal(right, walled())[0] == 1
    off = GoalIntentExtractor(g2, ExtractorParams(enable_nn_search=False))
    assert off.find_start_and_goal(right, walled())[0] == 0


def test_the_first_edge_is_pruned_when_the_robot_is_along_it() -> None:
    g = graph(NODES, [(0, 1), (1, 2), (2, 3)])
    planner = RoutePlanner(EdgeScorer([DistanceScorer("d")]))
    extractor = GoalIntentExtractor(g)
    along = Intent(True, start=Pose2D(1.6, 1.1), goal=Pose2D(5.0, 3.0))
    start, goal = extractor.find_start_and_goal(along, None)
    assert (start, goal) == (0, 3)
    route = planner.find_route(g, start, goal)
    pruned = extractor.prune_start_and_goal(route, along, ReroutingState(), planner)
    assert [n.nodeid for n in pruned.nodes] == [1, 2, 3]
    assert pruned.route_cost == route.route_cost - 2.0
    # a goal short of the last node (along the last edge) prunes that edge too
    short = Intent(True, start=Pose2D(1.0, 1.0), goal=Pose2D(5.0, 2.2))
    start, goal = extractor.find_start_and_goal(short, None)
    route = planner.find_route(g, start, goal)
    pruned = extractor.prune_start_and_goal(route, short, ReroutingState(), planner)
    assert [n.nodeid for n in pruned.nodes] == [0, 1, 2]
