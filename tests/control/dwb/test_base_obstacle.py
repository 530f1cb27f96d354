"""BaseObstacle scores the cost under a trajectory and rejects one that hits anything.

Nav2 (base_obstacle.cpp): a pose off the grid, or on a lethal, inscribed or unknown
cell, makes the trajectory illegal; otherwise the score is the cost under the last pose
(with sum_scores, the sum over all poses). The planner weighs it by `scale`.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from btnav.control.dwb.critics.base_obstacle import BaseObstacleCritic
from btnav.costmap.cost_values import INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE, NO_INFORMATION
from btnav.plugins import lookup

from .trajs import costmap, set_cost, straight, trajectories

SOME_COST = 128


def critic(**params) -> BaseObstacleCritic:
    return BaseObstacleCritic("BaseObstacle", BaseObstacleCritic.Params(**params))


def nav2_test_map():
    """Nav2's test: lethal at cell (0, 0), unknown at (0, 1), 128 at (0, 2)."""
    cm = costmap()
    set_cost(cm, 0, 0, LETHAL_OBSTACLE)
    set_cost(cm, 0, 1, NO_INFORMATION)
    set_cost(cm, 0, 2, SOME_COST)
    return cm


def test_registered_under_nav2s_names():
    assert lookup("critic", "dwb_critics::BaseObstacle") is BaseObstacleCritic
    assert lookup("critic", "dwb_critics::BaseObstacleCritic") is BaseObstacleCritic


def test_score_is_the_cost_under_the_last_pose_and_obstacles_are_illegal():
    cm = nav2_test_map()
    set_cost(cm, 5, 5, INSCRIBED_INFLATED_OBSTACLE)
    set_cost(cm, 5, 7, 40)
    trajs = trajectories(
        [
            straight(0.45, 0.25, math.pi, 0.1, 5),  # along row 2 into (0, 2): 128 at the end
            straight(0.45, 0.05, math.pi, 0.1, 5),  # along row 0 into the lethal cell
            straight(0.45, 0.15, math.pi, 0.1, 5),  # along row 1 into the unknown cell
            straight(0.55, 0.25, math.pi / 2, 0.1, 5),  # up column 5 over the inscribed cell
            straight(0.15, 0.15, -math.pi / 2, 0.1, 5),  # off the bottom edge
            straight(0.55, 0.65, math.pi / 2, 0.1, 5),  # over 40 at (5, 7), ending in free space
            straight(1.05, 1.05, 0.0, 0.1, 5),  # free
        ]
    )
    scores = critic().score(trajs, cm)
    assert scores[0] == SOME_COST
    assert np.isinf(scores[1:5]).all()
    assert scores[5] == 0.0  # only the last pose counts
    assert scores[6] == 0.0


def test_sum_scores_adds_every_pose():
    cm = costmap()
    for mx, c in zip(range(10, 15), (10, 20, 30, 0, 5), strict=True):
        set_cost(cm, mx, 10, c)
    trajs = trajectories([straight(1.05, 1.05, 0.0, 0.1, 5)])
    assert critic(sum_scores=True).score(trajs, cm)[0] == 65.0
    assert critic().score(trajs, cm)[0] == 5.0


def test_heading_does_not_matter():
    cm = nav2_test_map()
    poses = [np.tile([0.05, 0.25, (i / 50) * math.pi], (3, 1)) for i in range(-50, 150, 10)]
    assert (critic().score(trajectories(poses), cm) == SOME_COST).all()


@pytest.mark.parametrize(
    "x, y",
    [(1.0, -0.1), (5.1, 1.0), (1.0, 5.1), (-0.1, 1.0)],  # Nav2's off-map poses
)
def test_leaving_the_map_is_illegal(x, y):
    poses = np.stack([np.array([2.55, 2.55, 0.0]), np.array([x, y, 0.0])])
    assert np.isinf(critic().score(trajectories([poses]), costmap())).all()


def test_scale_is_the_weight():
    assert critic(scale=0.02).get_scale(costmap()) == 0.02
