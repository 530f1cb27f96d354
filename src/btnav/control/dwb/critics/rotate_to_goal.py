"""dwb_critics::RotateToGoal: near the goal, slow down, then only rotate, towards the goal yaw.

Once within the planner's `xy_goal_tolerance` (and the remaining plan shorter
than path_length_tolerance) the robot is "in window": trajectories not slower
than the current speed are illegal, and slower ones score `speed² *
slowing_factor` plus the yaw error at their end. Once it is also slower than
`trans_stopped_velocity` it is "rotating": any translation is illegal. Both
states last until the critic is reset (a new plan).
"""

from __future__ import annotations

import numpy as np

from ....core.geometry import angle_diff
from ....plugins import register
from ...goal_checkers import path_length
from ..critic import TrajectoryCritic


@register("critic", "dwb_critics::RotateToGoal", aliases=["dwb_critics::RotateToGoalCritic"])
class RotateToGoalCritic(TrajectoryCritic):
    class Params(TrajectoryCritic.Params):
        slowing_factor: float = 5.0
        lookahead_time: float = -1.0

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        self.reset()

    def reset(self) -> None:
        self.in_window = False
        self.rotating = False

    def prepare(self, pose, velocity, goal, plan, costmap) -> bool:
        pp = self.planner
        xy_tol = getattr(pp, "xy_goal_tolerance", 0.25)
        stopped = getattr(pp, "trans_stopped_velocity", 0.25)
        length_tol = getattr(pp, "path_length_tolerance", 1.0)
        d2 = (pose.x - goal.x) ** 2 + (pose.y - goal.y) ** 2
        self.in_window = self.in_window or (d2 <= xy_tol**2 and path_length(plan) <= length_tol)
        self.speed_sq = velocity.linear_x**2 + velocity.linear_y**2
        self.rotating = self.rotating or (self.in_window and self.speed_sq <= stopped**2)
        self.goal_yaw = goal.yaw
        return True

    def _rotation(self, trajs):
        """The yaw error at `lookahead_time` (dwb_core::projectPose: between two poses the
        yaw is slerped, past the end the last pose), or at the end when it is negative."""
        yaw = trajs.poses[:, :, 2]
        t = self.params.lookahead_time
        last = yaw.shape[1] - 1
        if t < 0.0 or t >= last * trajs.dt:
            at = yaw[:, -1]
        else:
            i = min(int(t / trajs.dt), last - 1)
            ratio = (t - i * trajs.dt) / trajs.dt
            at = yaw[:, i] + ratio * angle_diff(yaw[:, i + 1], yaw[:, i])
        return np.abs(angle_diff(self.goal_yaw, at))

    def score(self, trajs, costmap):
        S = len(trajs)
        if not self.in_window:
            return np.zeros(S)
        v = trajs.velocity
        speed_sq = v[:, 0] ** 2 + v[:, 1] ** 2
        if not self.rotating:
            s = speed_sq * self.params.slowing_factor + self._rotation(trajs)
            return np.where(speed_sq >= self.speed_sq, np.inf, s)
        moving = (np.abs(v[:, 0]) > 0) | (np.abs(v[:, 1]) > 0)
        return np.where(moving, np.inf, self._rotation(trajs))
