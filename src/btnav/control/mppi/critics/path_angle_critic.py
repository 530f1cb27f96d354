"""PathAngleCritic: turns rollouts towards the path when the robot faces away from it."""

from __future__ import annotations

import math

import numpy as np
from pydantic import Field

from ....core import fmath
from ....plugins import register
from ..angles import abs_angle_diff
from ..critic_data import CriticData
from ..critic_function import NAMESPACE, CriticFunction

FORWARD_PREFERENCE = 0
NO_DIRECTIONAL_PREFERENCE = 1
CONSIDER_FEASIBLE_PATH_ORIENTATIONS = 2


def _angle_to(pose: np.ndarray, x: float, y: float) -> float:
    yaw = fmath.arctan2(y - float(pose[1]), x - float(pose[0]))
    d = (yaw - pose[2] + math.pi) % (2 * math.pi) - math.pi
    return abs(d)


@register("critic", NAMESPACE + "PathAngleCritic")
class PathAngleCritic(CriticFunction):
    """The angle between each rollout's last heading and the direction from its last point
    to a path point `offset_from_furthest` past the furthest reached, applied when the
    robot's own angle to that point exceeds `max_angle_to_furthest`.

    `mode`: 0 forward preference; 1 no directional preference (heading or its reverse,
    whichever is closer); 2 follow the path's own orientation (forward or reverse as
    the path's yaw at that point says).
    """

    class Params(CriticFunction.Params):
        cost_weight: float = Field(2.2, ge=0.0)
        threshold_to_consider: float = Field(0.5, ge=0.0)
        offset_from_furthest: int = Field(4, ge=0)
        max_angle_to_furthest: float = Field(0.785398, ge=0.0)
        mode: int = Field(0, ge=0, le=2)
        forward_preference: bool | None = Field(
            None, description="Nav2's older spelling of mode 0 (true) / mode 1 (false)"
        )

    def score(self, data: CriticData) -> None:
        p = self.params
        n = len(data.path)
        if not self.enabled or n < 2 or data.local_path_length() < p.threshold_to_consider:
            return
        mode = p.mode
        if p.forward_preference is not None and "mode" not in p.model_fields_set:
            mode = FORWARD_PREFERENCE if p.forward_preference else NO_DIRECTIONAL_PREFERENCE
        if mode == NO_DIRECTIONAL_PREFERENCE and abs(data.vx_min) < 1e-6:
            mode = FORWARD_PREFERENCE  # Nav2: no reversing, so no "either way" either
        idx = min(data.furthest_reached_path_point() + p.offset_from_furthest, n - 1)
        gx, gy, gyaw = (float(v) for v in data.path[idx])
        robot = data.robot
        fwd = _angle_to(robot, gx, gy)
        if mode == FORWARD_PREFERENCE:
            angle = fwd
        elif mode == NO_DIRECTIONAL_PREFERENCE:
            angle = min(fwd, math.pi - fwd)
        else:
            # The path says which way to drive there: compare with the path's heading.
            reverse = (
                abs(
                    ((gyaw - fmath.arctan2(gy - float(robot[1]), gx - float(robot[0]))) + math.pi)
                    % (2 * math.pi)
                    - math.pi
                )
                > math.pi / 2
            )
            angle = math.pi - fwd if reverse else fwd
        if angle < p.max_angle_to_furthest:
            return
        # Nav2 scores each rollout's last pose: its heading against the direction from its
        # last point to the target
        last_x, last_y, last_yaw = data.x[:, -1], data.y[:, -1], data.yaws[:, -1]
        to_target = fmath.arctan2(np.float32(gy) - last_y, np.float32(gx) - last_x)
        err = abs_angle_diff(last_yaw, to_target)
        half_turn = np.float32(math.pi)
        if mode == NO_DIRECTIONAL_PREFERENCE:
            err = np.minimum(err, half_turn - err)
        elif mode == CONSIDER_FEASIBLE_PATH_ORIENTATIONS:
            # per rollout: drive backwards where the path's yaw there points away
            backwards = abs_angle_diff(np.float32(gyaw), to_target) > half_turn / 2
            err = np.where(backwards, half_turn - err, err)
        self.add(data, err)
