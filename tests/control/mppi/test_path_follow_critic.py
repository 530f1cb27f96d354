"""PathFollowCritic pulls the rollouts' ends to a path point ahead, as Nav2's does.

Nav2 (path_follow_critic.cpp): skipped for a path under two points or while
state.local_path_length < threshold_to_consider (1.4). The target is the path point
offset_from_furthest (6) past the furthest one any rollout reaches (clamped to the
path's end), moved on past points in collision; each rollout pays cost_weight (5)
times the distance from its last point to the target, raised to cost_power.
"""

from __future__ import annotations

import numpy as np
import pytest

from btnav.control.mppi.critics import PathFollowCritic
from btnav.costmap.cost_values import LETHAL_OBSTACLE

from .batch import costmap, line, make_data, paint, path_length, polyline, straight_path

T = 13
PATH = straight_path(3.0)  # 61 points, 5 cm apart, along +x from the robot at the origin


def critic(**params) -> PathFollowCritic:
    return PathFollowCritic("PathFollowCritic", PathFollowCritic.Params(**params))


def rollouts():
    """Ends: (1.2, 0) on the path (point 24, the furthest reached); (1.2, 0.2) beside it;
    (0.96, 0.72) off to the left."""
    return [
        line(0.0, 0.0, 0.0, 0.1, T),
        line(0.0, 0.2, 0.0, 0.1, T),
        line(0.0, 0.0, np.arctan2(0.06, 0.08), 0.1, T),
    ]


def scored(trajs=None, path=PATH, cm=None, **params):
    data = make_data(rollouts() if trajs is None else trajs, path=path, cm=cm)
    critic(**params).score(data)
    return data


def test_defaults_are_nav2s():
    p = PathFollowCritic.Params()
    assert (p.cost_weight, p.cost_power, p.threshold_to_consider) == (5.0, 1, 1.4)
    assert p.offset_from_furthest == 6


def test_distance_from_each_end_to_the_point_six_past_the_furthest():
    data = scored()
    # Target: point 24 + 6 = 30, (1.5, 0).
    assert data.costs == pytest.approx(
        [5 * 0.3, 5 * np.hypot(0.3, 0.2), 5 * np.hypot(0.54, 0.72)], abs=1e-4
    )  # 1.5, 1.803, 4.5
    assert np.argmin(data.costs) == 0


def test_offset_from_furthest_moves_the_target_and_clamps_at_the_end():
    data = scored(offset_from_furthest=2)  # point 26, (1.3, 0)
    assert data.costs[0] == pytest.approx(5 * 0.1, abs=1e-4)
    data = scored(path=straight_path(1.5), offset_from_furthest=20)  # past the end: (1.5, 0)
    assert data.costs[0] == pytest.approx(5 * 0.3, abs=1e-4)


def test_target_in_collision_moves_on_to_the_next_free_point():
    cm = paint(costmap(), [(1.5, 0.0), (1.55, 0.0)], LETHAL_OBSTACLE)  # points 30 and 31
    data = scored(cm=cm)  # target: point 32, (1.6, 0)
    assert data.costs == pytest.approx(
        [5 * 0.4, 5 * np.hypot(0.4, 0.2), 5 * np.hypot(0.64, 0.72)], abs=1e-4
    )


def test_near_the_goal_it_is_off():
    assert (scored(path=straight_path(1.3)).costs == 0).all()
    assert scored(path=straight_path(1.3), threshold_to_consider=1.0).costs[0] > 0


def test_weight_and_power():
    data = scored(cost_weight=2.0, cost_power=2)
    assert data.costs == pytest.approx(
        [0.6**2, (2 * np.hypot(0.3, 0.2)) ** 2, (2 * 0.9) ** 2], abs=1e-4
    )
    assert (scored(enabled=False).costs == 0).all()


def test_switch_is_judged_by_the_path_length():
    # A U-turn: the goal is 0.5 m away in a straight line, 2.5 m along the path.
    path = polyline((0.0, 0.0), (1.0, 0.0), (1.0, 0.5), (0.0, 0.5))
    assert path_length(path) == pytest.approx(2.5)
    data = scored([line(0.0, 0.0, 0.0, 0.05, 11)], path=path)  # ends at point 10, (0.5, 0)
    assert data.costs[0] == pytest.approx(5 * 0.3, abs=1e-4)  # target point 16, (0.8, 0)


def test_furthest_point_is_bounded_by_the_distance_travelled():
    # A U-turn corridor: out 1 m along y = 0, across 0.3 m, back along y = 0.3 to x = -1.5.
    path = polyline((0.0, 0.0), (1.0, 0.0), (1.0, 0.3), (-1.5, 0.3))
    along = line(0.0, 0.0, 0.0, 0.05, T)[:11]  # to (0.5, 0): point 10
    across = np.concatenate(
        [line(0.0, 0.0, np.pi / 2, 0.05, 7), line(0.05, 0.3, 0.0, 0.05, 6)]
    )  # up to (0, 0.3) and on to (0.3, 0.3), on the return leg (point 40), 0.6 m travelled
    data = scored([along[np.minimum(np.arange(T), 10)], across], path=path)
    # Nav2: furthest is point 10, target point 16 (0.8, 0); keeping to the path is cheaper.
    assert data.costs == pytest.approx([5 * 0.3, 5 * np.hypot(0.5, 0.3)], abs=1e-4)


def test_a_blocked_second_to_last_target_is_kept():
    path = straight_path(1.8, step=0.2)  # 10 points, 0.2 m apart
    cm = paint(costmap(), [(1.6, 0.0)], LETHAL_OBSTACLE)  # point 8, the second to last
    parked = np.zeros((T, 3))
    data = scored([parked], path=path, cm=cm, offset_from_furthest=8)
    assert data.costs[0] == pytest.approx(5 * 1.6, abs=1e-4)
