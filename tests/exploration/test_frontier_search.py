"""Frontier search on costmaps drawn by hand: which frontiers there are, and which comes first."""

from __future__ import annotations

import numpy as np
import pytest

from btnav.costmap.cost_values import INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE, NO_INFORMATION
from btnav.costmap.costmap_2d import Costmap2D
from btnav.exploration.frontier_search import find_frontiers

RES = 0.05


def two_rooms() -> np.ndarray:
    """A known 5 x 5 m square in unknown space, split by a wall with a 0.5 m doorway;
    the square's right edge is a closed wall, its other three edges open onto the unknown."""
    c = np.full((200, 200), NO_INFORMATION, np.uint8)
    c[50:150, 50:150] = 0
    c[50:150, 100] = LETHAL_OBSTACLE
    c[60:70, 100] = 0  # the doorway, y 3.0-3.5
    c[50:150, 149] = LETHAL_OBSTACLE
    return c


def search(costs: np.ndarray, robot=(3.0, 5.0), **kw):
    args = dict(min_frontier_size=0.5, potential_scale=3.0, gain_scale=1.0) | kw
    return find_frontiers(Costmap2D(costs, RES), robot, **args)


def test_frontiers_are_the_edges_of_known_space_the_robot_can_reach():
    frontiers = search(two_rooms())
    # the left room's three open edges (one frontier), the right room's top and bottom
    assert len(frontiers) == 3
    left = frontiers[0]
    assert left.size == pytest.approx((100 + 2 * 51) * RES, abs=0.2)
    for f in frontiers:  # every goal is a known free cell beside its frontier
        c = Costmap2D(two_rooms(), RES).cost_at_point(f.goal.x, f.goal.y)
        assert c == 0
        gap = np.hypot(*(f.cells - (f.goal.x, f.goal.y)).T).min()
        assert gap == pytest.approx(RES, abs=1e-9)


def test_a_frontier_behind_a_wall_is_as_far_as_the_way_round():
    right = [f for f in search(two_rooms()) if f.centroid[0] > 5.0]
    top, bottom = sorted(right, key=lambda f: f.centroid[1], reverse=True)
    # straight-line distances are alike; through the doorway (y 3.0-3.5) the bottom is nearer
    assert bottom.distance < top.distance - 2.0
    assert top.distance > np.hypot(top.goal.x - 3.0, top.goal.y - 5.0) + 1.0


def test_a_frontier_only_reachable_through_a_closed_doorway_is_none():
    costs = two_rooms()
    costs[60:70, 100] = LETHAL_OBSTACLE
    assert all(f.centroid[0] < 5.0 for f in search(costs))


def test_a_robot_in_an_inflated_ring_still_sees_the_frontiers():
    """Pushed against a post, every cell round the robot is inscribed: explore_lite starts
    its search from the nearest free cell, so the map is not taken for explored."""
    costs = two_rooms()
    costs[92:109, 52:69] = INSCRIBED_INFLATED_OBSTACLE  # a post's inscribed ring, 0.85 m
    costs[100, 60] = LETHAL_OBSTACLE
    frontiers = search(costs, robot=(3.0, 5.0))  # cell (60, 100): inside the ring
    assert len(frontiers) == 3


def test_small_frontiers_are_ignored():
    costs = np.full((100, 100), NO_INFORMATION, np.uint8)
    costs[20:80, 20:80] = 0
    costs[20:80, 20] = costs[20:80, 79] = costs[20, 20:80] = costs[79, 20:80] = LETHAL_OBSTACLE
    costs[50:55, 79] = 0  # a 0.25 m gap in the right wall
    assert search(costs, robot=(2.5, 2.5), min_frontier_size=0.5) == []
    (gap,) = search(costs, robot=(2.5, 2.5), min_frontier_size=0.2)
    assert gap.goal.yaw == pytest.approx(0.0)  # facing the unknown beyond the gap


def test_a_blacklisted_frontier_is_left_out_and_the_order_follows_the_cost():
    frontiers = search(two_rooms())
    first = frontiers[0]
    rest = search(two_rooms(), blacklist=[(first.goal.x, first.goal.y)])
    assert [f.centroid for f in rest] == [f.centroid for f in frontiers[1:]]
    costs = [f.cost for f in frontiers]
    assert costs == sorted(costs)
    # a heavy gain weight prefers the big frontier, a heavy distance weight the near one
    near_first = search(two_rooms(), robot=(7.5, 3.2), potential_scale=10.0, gain_scale=0.0)
    assert near_first[0].centroid[0] > 5.0


def test_nothing_known_or_a_robot_off_the_map_gives_no_frontier():
    assert search(np.full((50, 50), NO_INFORMATION, np.uint8)) == []
    assert search(two_rooms(), robot=(50.0, 50.0)) == []
