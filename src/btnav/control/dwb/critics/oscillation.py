"""dwb_critics::Oscillation: forbid flipping the sign of a velocity until the robot has moved.

After the chosen command reverses a direction (forward then backward, left then
right turn), commands with the opposite sign are illegal until the robot has
moved `oscillation_reset_dist` or turned `oscillation_reset_angle` from where the
flip happened (or `oscillation_reset_time` passed; a negative distance, angle or time
disables that check). Sideways and rotation directions are only tracked while the
linear speed is at most `x_only_threshold` (always, when it is negative), but a flag
once set forbids the other sign whatever the linear speed.
"""

from __future__ import annotations

import numpy as np

from ....core import fmath
from ....core.geometry import angle_diff
from ....plugins import register
from ..critic import TrajectoryCritic


class _Trend:
    def __init__(self) -> None:
        self.reset()

    def reset(self) -> None:
        self.sign = 0
        self.positive_only = False
        self.negative_only = False

    def update(self, v: float) -> bool:
        flag = False
        if v < 0.0:
            if self.sign > 0:
                self.negative_only = flag = True
            self.sign = -1
        elif v > 0.0:
            if self.sign < 0:
                self.positive_only = flag = True
            self.sign = 1
        return flag

    def oscillating(self, v: np.ndarray) -> np.ndarray:
        return (self.positive_only & (v < 0.0)) | (self.negative_only & (v > 0.0))

    @property
    def has_flag(self) -> bool:
        return self.positive_only or self.negative_only


@register("critic", "dwb_critics::Oscillation", aliases=["dwb_critics::OscillationCritic"])
class OscillationCritic(TrajectoryCritic):
    class Params(TrajectoryCritic.Params):
        oscillation_reset_dist: float = 0.05
        oscillation_reset_angle: float = 0.2
        oscillation_reset_time: float = -1.0
        x_only_threshold: float = 0.05

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        self.reset()

    def reset(self) -> None:
        self.x, self.y, self.theta = _Trend(), _Trend(), _Trend()
        self.prev_stationary = None
        self.cycles_since_flag = 0

    def prepare(self, pose, velocity, goal, plan, costmap) -> bool:
        self.pose = pose
        return True

    def debrief(self, cmd, pose) -> None:
        p = self.params
        flagged = self.x.update(cmd.linear_x)
        if p.x_only_threshold < 0.0 or abs(cmd.linear_x) <= p.x_only_threshold:
            flagged |= self.y.update(cmd.linear_y)
            flagged |= self.theta.update(cmd.angular_z)
        if flagged:
            self.prev_stationary = pose
            self.cycles_since_flag = 0
        if self.prev_stationary is None or not (
            self.x.has_flag or self.y.has_flag or self.theta.has_flag
        ):
            return
        self.cycles_since_flag += 1
        if self._reset_available(pose):
            self.x.reset()
            self.y.reset()
            self.theta.reset()

    def _reset_available(self, pose) -> bool:
        """Nav2's resetAvailable: a negative distance, angle or time disables that check."""
        p, since = self.params, self.prev_stationary
        moved = fmath.hypot(pose.x - since.x, pose.y - since.y)
        if p.oscillation_reset_dist >= 0.0 and moved > p.oscillation_reset_dist:
            return True
        turned = abs(angle_diff(pose.yaw, since.yaw))
        if p.oscillation_reset_angle >= 0.0 and turned > p.oscillation_reset_angle:
            return True
        return (
            p.oscillation_reset_time >= 0.0
            and self.cycles_since_flag * 0.05 > p.oscillation_reset_time
        )

    def score(self, trajs, costmap):
        v = trajs.velocity
        bad = self.x.oscillating(v[:, 0]) | self.y.oscillating(v[:, 1])
        bad |= self.theta.oscillating(v[:, 2])
        return np.where(bad, np.inf, 0.0)
