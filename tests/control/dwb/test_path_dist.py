"""PathDist scores how many cells (Manhattan) a trajectory ends from the plan.

Nav2 (path_dist.cpp, map_grid.cpp): the plan is densified (adjustPlanResolution) and
every point of its first stretch on the map and not unknown seeds a cell (none: prepare
fails). A Manhattan-ordered flood gives each cell its Manhattan distance to the nearest
seed. The last pose is scored (aggregation_type "last"); any pose off the grid makes
the trajectory illegal.
"""

from __future__ import annotations

import numpy as np

from btnav.control.dwb.critics.path_dist import PathDistCritic
from btnav.core.geometry import Pose2D
from btnav.costmap.cost_values import NO_INFORMATION
from btnav.plugins import lookup

from .trajs import costmap, ending_at, line_plan, prepare, set_cost, straight, trajectories

ROBOT = Pose2D(0.55, 2.55, 0.0)
PLAN = line_plan(0.55, 2.55, 3.55, 2.55)  # cells (5..35, 25)


def critic(**params) -> PathDistCritic:
    return PathDistCritic("PathDist", PathDistCritic.Params(**params))


def prepared(plan=PLAN, cm=None, **params):
    cm = costmap() if cm is None else cm
    c = critic(**params)
    assert prepare(c, ROBOT, plan, cm)
    return c, cm


def test_registered_under_nav2s_names():
    assert lookup("critic", "dwb_critics::PathDist") is PathDistCritic
    assert lookup("critic", "dwb_critics::PathDistCritic") is PathDistCritic


def test_manhattan_cells_from_the_trajectory_end_to_the_plan():
    c, cm = prepared()
    trajs = trajectories(
        [
            ending_at(2.05, 2.55, 0.0),  # on the plan
            ending_at(2.05, 2.85, 0.5),  # (20, 28): 3 above it
            ending_at(4.05, 2.55, 0.0),  # (40, 25): 5 past its end
            ending_at(4.05, 2.95, 0.0),  # (40, 29): 5 + 4
            ending_at(0.25, 2.05, 3.0),  # (2, 20): 3 + 5 before its start
        ]
    )
    assert c.score(trajs, cm).tolist() == [0.0, 3.0, 5.0, 9.0, 8.0]


def test_the_plan_stops_at_unknown_space():
    cm = costmap()
    set_cost(cm, 20, 25, NO_INFORMATION)  # the plan's cells 5..19 seed, 21.. do not
    c, cm = prepared(cm=cm)
    assert c.score(trajectories([ending_at(3.05, 2.55, 0.0)]), cm).tolist() == [11.0]


def test_prepare_fails_when_no_plan_point_is_on_the_map():
    assert not prepare(critic(), ROBOT, line_plan(5.55, 1.05, 8.05, 1.05), costmap())


def test_a_pose_off_the_grid_is_illegal():
    c, cm = prepared()
    leaving = straight(2.05, 4.75, 1.5708, 0.1, 5)  # up and off the top edge
    assert np.isinf(c.score(trajectories([leaving]), cm)).all()


def test_scale_is_the_weight():
    assert critic(scale=32.0).get_scale(costmap()) == 32.0


def test_distance_is_the_smallest_manhattan_distance_to_the_plan():
    # A plan sloping up at 1 in 2 from (0.05, 0.05); a trajectory ending at cell (0, 10).
    plan = line_plan(0.05, 0.05, 4.05, 2.05)
    c = critic()
    assert prepare(c, Pose2D(0.05, 0.05, 0.0), plan, costmap())
    score = c.score(trajectories([ending_at(0.05, 1.05, 0.0)]), costmap())
    # Plan cells (x, ~x/2) are |x| + |10 - x/2| >= 10 away, 10 at the start cell (0, 0);
    # the Euclidean-nearest plan cell, (3, 2), is 3 + 8 = 11 away.
    assert score.tolist() == [10.0]


def test_sparse_plans_are_densified_as_nav2_does():
    # Two plan points 1 m apart along row 0. Nav2 inserts 6 points, 1/7 m apart, at
    # x = 0.193, 0.336, 0.479, 0.621, 0.764, 0.907: cells 0, 1, 3, 4, 6, 7, 9, 10 are seeded
    # and cell 2 is one cell from the plan.
    plan = np.array([[0.05, 0.05, 0.0], [1.05, 0.05, 0.0]])
    c = critic()
    assert prepare(c, Pose2D(0.05, 0.05, 0.0), plan, costmap())
    assert c.score(trajectories([ending_at(0.25, 0.05, 0.0)]), costmap()).tolist() == [1.0]
