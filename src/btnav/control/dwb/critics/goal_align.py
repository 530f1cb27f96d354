"""dwb_critics::GoalAlign: GoalDist of a point ahead of the trajectory's end, to a goal pushed
`forward_point_distance` further along the robot-to-goal direction: faces the robot to the goal.

Switched off (scale 0) within the planner's xy_goal_tolerance, where RotateToGoal turns
the robot to the goal's yaw (a btnav deviation, see `MapGridCritic.near_goal`).
"""

from __future__ import annotations

import numpy as np

from ....core import fmath
from ....plugins import register
from .goal_dist import GoalDistCritic


@register("critic", "dwb_critics::GoalAlign", aliases=["dwb_critics::GoalAlignCritic"])
class GoalAlignCritic(GoalDistCritic):
    stop_on_failure = False

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        self.forward_distance = self.params.forward_point_distance
        self.zero_scale = False

    def prepare(self, pose, velocity, goal, plan, costmap) -> bool:
        self.zero_scale = self.near_goal(pose, goal)
        if self.zero_scale:
            return True
        d = self.params.forward_point_distance
        s, c = fmath.sincos(fmath.arctan2(goal.y - pose.y, goal.x - pose.x))
        shifted = plan.copy()
        shifted[-1, 0] += d * c
        shifted[-1, 1] += d * s
        return super().prepare(pose, velocity, goal, shifted, costmap)

    def score(self, trajs, costmap):
        if self.zero_scale:
            return np.zeros(len(trajs))
        return super().score(trajs, costmap)

    def get_scale(self, costmap) -> float:
        return 0.0 if self.zero_scale else float(self.params.scale)
