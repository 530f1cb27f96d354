"""dwb_critics::PathAlign: PathDist of a point `forward_point_distance` ahead of the trajectory's end.

Keeps the robot's nose on the path. Switched off (scale 0) within
forward_point_distance of the goal; its scale is `scale * resolution / 2`, as Nav2's.
"""

from __future__ import annotations

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
        d = self.params.forward_point_distance
        self.zero_scale = (pose.x - goal.x) ** 2 + (pose.y - goal.y) ** 2 <= d * d
        if self.zero_scale:
            return True
        return super().prepare(pose, velocity, goal, plan, costmap)

    def score(self, trajs, costmap):
        if self.zero_scale:
            import numpy as np

            return np.zeros(len(trajs))
        return super().score(trajs, costmap)

    def get_scale(self, costmap) -> float:
        return 0.0 if self.zero_scale else costmap.resolution * 0.5 * self.params.scale
