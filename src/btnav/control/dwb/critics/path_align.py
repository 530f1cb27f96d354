"""dwb_critics::PathAlign: PathDist of a point `forward_point_distance` ahead of the trajectory's end.

Keeps the robot's nose on the path. Its scale is `scale * resolution / 2`, as Nav2's.
Switched off (scale 0) near the goal: within forward_point_distance, as Nav2's, and
within the planner's xy_goal_tolerance, where RotateToGoal turns the robot to the
goal's yaw (see `MapGridCritic.near_goal`).
"""

from __future__ import annotations

import numpy as np

from ....plugins import register
from .path_dist import PathDistCritic


@register("critic", "dwb_critics::PathAlign", aliases=["dwb_critics::PathAlignCritic"])
class PathAlignCritic(PathDistCritic):
    stop_on_failure = False

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        self.forward_distance = self.params.forward_point_distance
        self.zero_scale = False

    def prepare(self, pose, velocity, goal, plan, costmap) -> bool:
        self.zero_scale = self.near_goal(pose, goal)
        if self.zero_scale:
            return True
        return super().prepare(pose, velocity, goal, plan, costmap)

    def score(self, trajs, costmap):
        if self.zero_scale:
            return np.zeros(len(trajs))
        return super().score(trajs, costmap)

    def get_scale(self, costmap) -> float:
        return 0.0 if self.zero_scale else costmap.resolution * 0.5 * self.params.scale
