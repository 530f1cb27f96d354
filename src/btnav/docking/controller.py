"""opennav_docking's Controller: the graceful control law towards a target, checked ahead.

`compute_velocity_command(target, is_docking, backward)` gives the control law's
command towards `target` (a pose in the robot's base frame) and whether the trajectory
that command leads onto is collision-free: the law is rolled out from the robot in
steps of `simulation_time_step` for at most `projection_time` (or until within 1 cm of
the target), and each pose's footprint is checked on the local costmap (lethal or
unknown under the outline, or off the map, is a collision), except near the dock:
within `dock_collision_threshold` of the target when docking, of the start when
undocking, so the dock itself is not an obstacle. `use_collision_detection: false`
skips the check. The rollout is kept in `trajectory` (Nav2's `docking_trajectory`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from ..core import fmath
from ..core.geometry import Pose2D
from ..core.messages import Path, Twist
from ..costmap.cost_values import LETHAL_OBSTACLE
from ..costmap.footprint_cost import footprint_costs
from ..params.docking import DockingControllerParams
from .smooth_control_law import SmoothControlLaw

#: The rollout stops this close (m) to the target.
_REACHED = 1e-2


class DockingController:
    """The approach controller; `costmap_ros` (the local costmap) is needed only for the
    collision check, `lookup(target, source)` is the frame tree's."""

    def __init__(
        self,
        params: DockingControllerParams,
        *,
        base_frame: str,
        costmap_ros: Any = None,
        lookup: Callable[[str, str], Pose2D] | None = None,
    ) -> None:
        self.base_frame = base_frame
        self.costmap_ros = costmap_ros
        self.lookup = lookup
        self.trajectory: Path | None = None
        self.set_params(params)

    def set_params(self, params: DockingControllerParams) -> None:
        """Nav2's dynamic parameters: the law takes the new constants at once."""
        self.params = params
        self.law = SmoothControlLaw(
            params.k_phi,
            params.k_delta,
            params.beta,
            params.lambda_,
            params.slowdown_radius,
            params.deceleration_max,
            params.v_linear_min,
            params.v_linear_max,
            params.v_angular_max,
        )

    def compute_velocity_command(
        self, target: Pose2D, is_docking: bool, backward: bool = False
    ) -> tuple[Twist, bool]:
        """The command towards `target` (base frame) and whether its trajectory is free."""
        cmd = self.law.velocity(target, None, backward)
        return cmd, self.is_trajectory_collision_free(target, is_docking, backward)

    def compute_rotate_to_heading_command(
        self, angular_distance: float, current_angular: float, dt: float
    ) -> Twist:
        """Turn in place towards a heading `angular_distance` away, within the angular
        acceleration and slowing so as to stop on it."""
        p = self.params
        sign = 1.0 if angular_distance > 0.0 else -1.0
        accel = p.rotate_to_heading_max_angular_accel
        w = min(
            max(sign * p.rotate_to_heading_angular_vel, current_angular - accel * dt),
            current_angular + accel * dt,
        )
        stop = math.sqrt(2.0 * accel * abs(angular_distance))
        if abs(w) > stop:
            w = sign * stop
        return Twist(angular_z=w)

    def rollout(self, target: Pose2D, backward: bool) -> np.ndarray:
        """(N, 3) poses in the base frame from the origin along the law, the origin first."""
        p = self.params
        max_poses = math.ceil(p.projection_time / p.simulation_time_step)
        poses = [Pose2D()]
        pose = poses[0]
        while True:
            pose = self.law.next_pose(p.simulation_time_step, target, pose, backward)
            poses.append(pose)
            if fmath.hypot(target.x - pose.x, target.y - pose.y) <= _REACHED:
                break
            if len(poses) >= max_poses:
                break
        return np.array([(q.x, q.y, q.yaw) for q in poses])

    def is_trajectory_collision_free(
        self, target: Pose2D, is_docking: bool, backward: bool = False
    ) -> bool:
        poses = self.rollout(target, backward)
        self.trajectory = Path(0.0, poses, self.base_frame)
        if not self.params.use_collision_detection or self.costmap_ros is None:
            return True
        checked = poses[1:]
        if is_docking:
            near = fmath.hypot(checked[:, 0] - target.x, checked[:, 1] - target.y)
        else:
            near = fmath.hypot(checked[:, 0], checked[:, 1])
        checked = checked[near > self.params.dock_collision_threshold]
        if not len(checked):
            return True
        costmap = self.costmap_ros.costmap
        assert self.lookup is not None, "a collision check needs the frame tree's lookup"
        to_costmap = self.lookup(self.costmap_ros.global_frame, self.base_frame)
        s, c = fmath.sincos(to_costmap.yaw)
        x = to_costmap.x + c * checked[:, 0] - s * checked[:, 1]
        y = to_costmap.y + s * checked[:, 0] + c * checked[:, 1]
        yaw = checked[:, 2] + to_costmap.yaw
        cost = footprint_costs(costmap, self.costmap_ros.footprint, x, y, yaw)
        return not bool((cost >= LETHAL_OBSTACLE).any())
