"""GoalAlign scores a point ahead of the trajectory's end against a goal pushed on ahead.

Nav2 (goal_align.cpp): GoalDist with the plan's last pose moved forward_point_distance
further along the robot-to-goal direction, scoring the point forward_point_distance
ahead of each pose (aggregation "last": the last pose's only, and only that point off
the grid is illegal). The planner weighs it by `scale`, all the way to the goal.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from btnav.control.dwb.critics.goal_align import GoalAlignCritic
from btnav.control.dwb.local_planner import DWBParams
from btnav.core.geometry import Pose2D
from btnav.plugins import lookup

from .trajs import costmap, ending_at, line_plan, prepare, straight, trajectories

FPD = 0.3


def critic(planner=None, **params) -> GoalAlignCritic:
    params.setdefault("forward_point_distance", FPD)
    return GoalAlignCritic("GoalAlign", GoalAlignCritic.Params(**params), planner)


def test_registered_under_nav2s_names_with_nav2s_default():
    assert lookup("critic", "dwb_critics::GoalAlign") is GoalAlignCritic
    assert lookup("critic", "dwb_critics::GoalAlignCritic") is GoalAlignCritic
    assert GoalAlignCritic.Params().forward_point_distance == pytest.approx(0.325)


def test_scores_the_forward_point_against_the_pushed_goal():
    cm = costmap()
    c = critic()
    # The robot at (1.05, 2.55), the goal at (3.05, 2.55): pushed to (3.35, 2.55), cell 33.
    assert prepare(c, Pose2D(1.05, 2.55, 0.0), line_plan(1.05, 2.55, 3.05, 2.55), cm)
    trajs = trajectories(
        [
            ending_at(2.05, 2.55, 0.0),  # ahead: (2.35, 2.55), cell (23, 25): 10
            ending_at(2.05, 2.55, math.pi / 4),  # (2.26, 2.76), cell (22, 27): 11 + 2
            ending_at(2.05, 2.55, math.pi / 2),  # (2.05, 2.85), cell (20, 28): 13 + 3
            ending_at(2.05, 2.55, math.pi),  # (1.75, 2.55), cell (17, 25): 16
        ]
    )
    scores = c.score(trajs, cm)
    assert scores.tolist() == [10.0, 13.0, 16.0, 16.0]
    assert np.argmin(scores) == 0  # facing the goal is best
    assert c.get_scale(cm) == 1.0
    assert critic(scale=24.0).get_scale(cm) == 24.0


def test_goal_is_pushed_along_the_robot_to_goal_direction():
    cm = costmap()
    c = critic()
    # Robot (1.05, 1.05), goal (3.05, 3.05): pushed 0.3 m at 45 degrees to (3.26, 3.26).
    assert prepare(c, Pose2D(1.05, 1.05, 0.0), line_plan(1.05, 1.05, 3.05, 3.05), cm)
    score = c.score(trajectories([ending_at(2.95, 2.95, math.pi / 4)]), cm)
    # Forward point (3.16, 3.16): cell (31, 31) against (32, 32).
    assert score.tolist() == [2.0]


def test_only_the_last_forward_point_must_be_on_the_grid():
    cm = costmap()
    c = critic()
    assert prepare(c, Pose2D(1.05, 2.55, 0.0), line_plan(1.05, 2.55, 3.05, 2.55), cm)
    from_off_the_map = straight(-0.25, 2.55, 0.0, 0.1, 5)  # ends at (0.15, 2.55)
    to_the_edge = ending_at(4.85, 2.55, 0.0)  # its forward point, x = 5.15, is off the map
    scores = c.score(trajectories([from_off_the_map, to_the_edge]), cm)
    assert scores[0] == 29.0  # forward point (0.45, 2.55): cell 4 against 33
    assert np.isinf(scores[1])


@pytest.mark.xfail(
    strict=True,
    reason="btnav goal_align.py:27-29,42-43 (with map_grid.py:73-94, held until a new plan) switches GoalAlign off "
    "(scale 0, scores 0) within max(forward_point_distance, the planner's "
    "xy_goal_tolerance) of the goal; Nav2's GoalAlign has no such switch and keeps "
    "scoring up to the goal"
    "; kept on purpose (issue 34): run with Nav2's semantics instead, the documented DWB "
    "section misses the office tour's last waypoint (the robot turns to and fro 0.18 m "
    "from (2.5, 6.5), yaw 2.3-2.7 rad against 3.14, as navigation2 issue #5805 reports) "
    "and the turtlebot3 mapping stage touches a pillar",
)
@pytest.mark.parametrize(
    "fpd, planner",
    [(0.3, None), (0.1, DWBParams(xy_goal_tolerance=0.25))],
    ids=["within-forward-point-distance", "within-xy-goal-tolerance"],
)
def test_still_on_near_the_goal(fpd, planner):
    cm = costmap()
    c = critic(planner=planner, forward_point_distance=fpd)
    # 0.2 m from the goal at (3.05, 2.55), facing it: the trajectory's forward point is one
    # cell short of the pushed goal (fpd 0.3: cells 32 and 33; fpd 0.1: cells 30 and 31).
    assert prepare(c, Pose2D(2.85, 2.55, 0.0), line_plan(2.85, 2.55, 3.05, 2.55), cm)
    assert c.get_scale(cm) == 1.0
    assert c.score(trajectories([ending_at(2.95, 2.55, 0.0)]), cm).tolist() == [1.0]


def test_the_goal_window_holds_until_a_new_plan_as_rotate_to_goal_s_does():
    # The fishbot's last waypoint: in place at 0.2 m from the goal, turning to its yaw; AMCL
    # moved the estimate 0.06 m out of the 0.25 m window. With the switch per cycle GoalAlign
    # came back on (24 per cell) and turned the robot away from the yaw RotateToGoal
    # (still "rotating") was turning it to, until the progress checker gave up.
    cm = costmap()
    c = critic(planner=DWBParams(xy_goal_tolerance=0.25), forward_point_distance=0.1)
    plan = line_plan(2.85, 2.55, 3.05, 2.55)
    assert prepare(c, Pose2D(2.85, 2.55, 0.0), plan, cm) and c.get_scale(cm) == 0.0
    assert prepare(c, Pose2D(2.74, 2.55, 0.0), plan, cm) and c.get_scale(cm) == 0.0  # 0.31 m
    c.reset()  # a new plan
    assert prepare(c, Pose2D(2.74, 2.55, 0.0), plan, cm) and c.get_scale(cm) == 1.0
