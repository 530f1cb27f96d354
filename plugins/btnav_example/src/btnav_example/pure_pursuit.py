"""`btnav_example::PurePursuitController`: textbook pure pursuit, with the controller contract kept.

Each cycle the robot drives at `desired_linear_vel` on the circle through itself and
the carrot, the first point of the plan `lookahead_dist` away. Around that core sits
what every controller owes the controller server (nav2_core::Controller):

- `set_plan` takes the plan in the local costmap's frame (an empty one is
  `InvalidPath`); `compute_velocity_commands` prunes it at the robot each cycle;
- goal checking: once the server's goal checker says the position is reached
  (`is_goal_xy_reached`), the robot turns in place to the goal's yaw, and the goal
  checker, not the controller, ends the goal;
- it turns in place first when the carrot is more than `rotate_to_heading_min_angle`
  off its heading, and slows down over the last `approach_dist` metres;
- the arc to the carrot is checked on the local costmap: a lethal or inscribed cell
  on it raises `NoValidControl` (the server waits `failure_tolerance`, then aborts
  and the tree's recoveries run);
- `set_speed_limit` (a speed filter's limit) caps the speed; `reset` forgets the last
  goal's state: the server calls it when a FollowPath goal starts (so after a success,
  an abort or a cancel), not when a replanned path preempts the running goal.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from btnav.control.controller import Controller
from btnav.control.exceptions import InvalidPath, NoValidControl
from btnav.core.geometry import Pose2D, angle_diff
from btnav.core.messages import Path, Twist
from btnav.costmap.cost_values import INSCRIBED_INFLATED_OBSTACLE, NO_INFORMATION
from btnav.costmap.costmap_2d import Costmap2D
from btnav.plugins import register
from pydantic import Field

#: The goal checker's xy tolerance when the server gives none (Nav2's default).
DEFAULT_XY_GOAL_TOLERANCE = 0.25


def carrot_index(distances: np.ndarray, lookahead: float) -> int:
    """The first pose at least `lookahead` from the robot, else the last one."""
    beyond = np.flatnonzero(distances >= lookahead)
    return int(beyond[0]) if beyond.size else len(distances) - 1


def arc_points(curvature: float, length: float, step: float) -> np.ndarray:
    """Points (robot frame) every `step` along the arc of `curvature` that starts along +x."""
    s = np.arange(1, max(int(length / step), 1) + 1) * step
    if abs(curvature) < 1e-6:
        return np.stack([s, np.zeros_like(s)], axis=-1)
    return np.stack(
        [np.sin(curvature * s) / curvature, (1.0 - np.cos(curvature * s)) / curvature], axis=-1
    )


@register("controller", "btnav_example::PurePursuitController")
class PurePursuitController(Controller):
    """Pure pursuit at a constant speed, turning in place where the path or the goal asks."""

    class Params(Controller.Params):
        desired_linear_vel: float = Field(0.4, gt=0.0, description="m/s")
        lookahead_dist: float = Field(0.6, gt=0.0, description="m from the robot to the carrot")
        max_angular_vel: float = Field(1.5, gt=0.0, description="rad/s")
        rotate_to_heading_angular_vel: float = Field(1.0, gt=0.0, description="rad/s")
        rotate_to_heading_min_angle: float = Field(0.785, ge=0.0, description="rad")
        approach_dist: float = Field(0.5, ge=0.0, description="slow down within this of the goal")
        min_approach_linear_vel: float = Field(0.05, gt=0.0, description="m/s")
        use_collision_detection: bool = True

    params: Params

    def __init__(self, name: str = "FollowPath", params: Params | None = None) -> None:
        super().__init__(name, params)
        self.plan = np.zeros((0, 3))
        self.speed_limit = self.params.desired_linear_vel
        self.rotating_to_goal = False
        #: The last carrot, in the costmap's frame (for plots and tests).
        self.carrot: np.ndarray | None = None

    # -- nav2_core::Controller ---------------------------------------------------------------

    def set_plan(self, path: Path) -> None:
        poses = np.asarray(path.poses, dtype=float).reshape(-1, 3)
        if len(poses) == 0:
            raise InvalidPath("received an empty plan")
        if len(self.plan) and not np.allclose(poses[-1], self.plan[-1]):
            self.rotating_to_goal = False  # a new goal, not a replan of this one
        self.plan = poses.copy()

    def set_speed_limit(self, speed_limit: float, percentage: bool) -> None:
        full = self.params.desired_linear_vel
        if speed_limit <= 0.0:
            self.speed_limit = full
        else:
            self.speed_limit = full * speed_limit / 100.0 if percentage else min(speed_limit, full)

    def reset(self) -> None:
        self.rotating_to_goal = False

    def compute_velocity_commands(
        self, pose: Pose2D, velocity: Twist, costmap: Costmap2D, goal_checker: Any = None
    ) -> Twist:
        p = self.params
        if len(self.plan) == 0:
            raise InvalidPath("no plan to follow")
        # prune what the robot has passed: keep the plan from its closest pose on
        dist = np.hypot(self.plan[:, 0] - pose.x, self.plan[:, 1] - pose.y)
        closest = int(np.argmin(dist))
        self.plan, dist = self.plan[closest:], dist[closest:]
        goal = Pose2D(*self.plan[-1])

        remaining = Path(0.0, self.plan, costmap.frame_id)
        if self.rotating_to_goal or self._at_goal_xy(pose, goal, velocity, remaining, goal_checker):
            self.rotating_to_goal = True
            return self._rotate(angle_diff(goal.yaw, pose.yaw))

        carrot = self.plan[carrot_index(dist, p.lookahead_dist), :2]
        self.carrot = carrot
        x, y = pose.inverse_transform_points(carrot[None, :])[0]
        heading_error = math.atan2(y, x)
        if abs(heading_error) > p.rotate_to_heading_min_angle:
            return self._rotate(heading_error)

        curvature = 2.0 * y / max(x * x + y * y, 1e-9)
        to_goal = float(dist[-1])
        v = self.speed_limit
        if to_goal < p.approach_dist:
            v = max(v * to_goal / p.approach_dist, p.min_approach_linear_vel)
        w = v * curvature
        if abs(w) > p.max_angular_vel:  # keep the curvature: slow down instead
            v *= p.max_angular_vel / abs(w)
            w = math.copysign(p.max_angular_vel, w)
        if p.use_collision_detection:
            self._check_arc(pose, curvature, math.hypot(x, y), costmap)
        return Twist(linear_x=v, angular_z=w)

    # -- pieces ------------------------------------------------------------------------------

    @staticmethod
    def _at_goal_xy(
        pose: Pose2D, goal: Pose2D, velocity: Twist, remaining: Path, goal_checker: Any
    ) -> bool:
        """The server's goal checker decides; without one, Nav2's default xy tolerance."""
        if goal_checker is not None and hasattr(goal_checker, "is_goal_xy_reached"):
            return bool(goal_checker.is_goal_xy_reached(pose, goal, velocity, remaining))
        return pose.distance_to(goal) <= DEFAULT_XY_GOAL_TOLERANCE

    def _rotate(self, angle: float) -> Twist:
        """Turn in place towards `angle` (rad, robot frame), slowing down for the last bit."""
        p = self.params
        w = min(p.rotate_to_heading_angular_vel, 2.0 * abs(angle))
        return Twist(linear_x=0.0, angular_z=math.copysign(w, angle))

    def _check_arc(self, pose: Pose2D, curvature: float, length: float, costmap: Costmap2D) -> None:
        """Raise NoValidControl if the arc to the carrot crosses a lethal or inscribed cell."""
        xy = pose.transform_points(arc_points(curvature, length, costmap.resolution))
        cost = costmap.cost_at(xy)
        if np.any((cost >= INSCRIBED_INFLATED_OBSTACLE) & (cost != NO_INFORMATION)):
            raise NoValidControl("PurePursuitController: obstacle on the arc to the carrot")
