"""GoalDist scores how many cells (Manhattan) a trajectory ends from the plan's last cell.

Nav2 (goal_dist.cpp, map_grid.cpp): the plan is densified to the costmap's resolution;
the goal cell is the last point of the plan's first stretch on the map and not unknown
(none: prepare fails). Cells are scored by a Manhattan flood from it. With
aggregation_type "last" (the default) the trajectory's last pose is scored; "sum" and
"product" combine all poses. Any pose off the grid makes the trajectory illegal.
"""

from __future__ import annotations

import numpy as np

from btnav.control.dwb.critics.goal_dist import GoalDistCritic
from btnav.core.geometry import Pose2D
from btnav.costmap.cost_values import NO_INFORMATION
from btnav.plugins import lookup

from .trajs import costmap, ending_at, line_plan, prepare, set_cost, straight, trajectories

ROBOT = Pose2D(0.55, 2.55, 0.0)


def critic(**params) -> GoalDistCritic:
    return GoalDistCritic("GoalDist", GoalDistCritic.Params(**params))


def prepared(plan, cm=None, **params):
    cm = costmap() if cm is None else cm
    c = critic(**params)
    assert prepare(c, ROBOT, plan, cm)
    return c, cm


def test_registered_under_nav2s_names():
    assert lookup("critic", "dwb_critics::GoalDist") is GoalDistCritic
    assert lookup("critic", "dwb_critics::GoalDistCritic") is GoalDistCritic


def test_manhattan_cells_from_the_trajectory_end_to_the_goal_cell():
    c, cm = prepared(line_plan(0.55, 2.55, 3.55, 2.55))  # goal cell (35, 25)
    trajs = trajectories(
        [
            ending_at(3.55, 2.55, 0.0),  # on the goal
            ending_at(2.55, 2.85, 1.0),  # (25, 28): 10 + 3
            ending_at(3.85, 2.15, -2.0),  # (38, 21): 3 + 4
            ending_at(1.55, 2.55, 0.0),  # (15, 25): 20
        ]
    )
    assert c.score(trajs, cm).tolist() == [0.0, 13.0, 7.0, 20.0]


def test_goal_is_the_last_plan_point_on_the_map():
    # The plan runs on past the map's right edge (x = 5 m): the goal cell is (49, 25).
    c, cm = prepared(line_plan(0.55, 2.55, 7.05, 2.55))
    scores = c.score(trajectories([ending_at(4.55, 2.55, 0.0), ending_at(4.95, 2.95, 0.0)]), cm)
    assert scores.tolist() == [4.0, 4.0]


def test_goal_stops_before_unknown_space_on_the_plan():
    cm = costmap()
    for mx in range(30, 35):
        set_cost(cm, mx, 25, NO_INFORMATION)
    c, cm = prepared(line_plan(0.55, 2.55, 4.55, 2.55), cm)  # goal cell (29, 25)
    assert c.score(trajectories([ending_at(2.55, 2.55, 0.0)]), cm).tolist() == [4.0]


def test_prepare_fails_when_no_plan_point_is_on_the_map():
    assert not prepare(critic(), ROBOT, line_plan(6.05, 1.05, 8.05, 1.05), costmap())


def test_a_pose_off_the_grid_is_illegal():
    c, cm = prepared(line_plan(0.55, 2.55, 3.55, 2.55))
    off_then_back = straight(-0.25, 2.55, 0.0, 0.1, 5)  # starts left of the map
    assert np.isinf(c.score(trajectories([off_then_back]), cm)).all()


def test_sum_and_product_aggregate_all_poses():
    plan = line_plan(0.55, 2.55, 3.55, 2.55)
    traj = trajectories([straight(3.05, 2.55, 0.0, 0.1, 4)])  # cells 30..33: 5, 4, 3, 2 off
    c, cm = prepared(plan, aggregation_type="sum")
    assert c.score(traj, cm).tolist() == [14.0]
    c, cm = prepared(plan, aggregation_type="product")
    assert c.score(traj, cm).tolist() == [120.0]
    c, cm = prepared(plan)
    assert c.score(traj, cm).tolist() == [2.0]


def test_scale_is_the_weight():
    assert critic(scale=24.0).get_scale(costmap()) == 24.0
    assert critic().get_scale(costmap()) == 1.0
