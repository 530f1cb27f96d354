"""MPPIController: Nav2's nav2_mppi_controller::MPPIController as a btnav controller plugin."""

from __future__ import annotations

from typing import Any

import numpy as np

from ...core import fmath
from ...core.geometry import Pose2D
from ...core.messages import Path, Twist
from ...core.rng import stream
from ...costmap.costmap_2d import Costmap2D
from ...plugins import register
from ..controller import Controller
from ..exceptions import InvalidPath
from .critic_function import CriticFunction
from .motion_models import ControlConstraints, MotionModel, make_motion_model
from .optimizer import Optimizer, OptimizerSettings
from .params import MPPIParams, critic_class
from .path_pruning import PathPruner


@register("controller", "nav2_mppi_controller::MPPIController", aliases=["btnav/MPPIController"])
class MPPIController(Controller):
    """Model Predictive Path Integral control, vectorised over the whole batch.

    Randomness: pass a `numpy.random.Generator` (`rng=`) or a `seed` (the generator is
    then `core.rng.stream(seed, "mppi", name)`); the same seed gives the same commands.
    The plan given to `set_plan` and the pose given each cycle must be in the
    costmap's frame.
    """

    Params = MPPIParams

    def __init__(
        self,
        name: str = "FollowPath",
        params: MPPIParams | None = None,
        *,
        rng: np.random.Generator | None = None,
        seed: int = 0,
    ) -> None:
        params = params if params is not None else MPPIParams()
        super().__init__(name, params)
        self.params: MPPIParams = params
        self.rng = rng if rng is not None else stream(seed, "mppi", name)
        p = params
        self.base_constraints = ControlConstraints(
            vx_max=p.vx_max,
            vx_min=p.vx_min,
            vy_max=p.vy_max,
            wz_max=p.wz_max,
            ax_max=p.ax_max,
            ax_min=p.ax_min,
            ay_max=p.ay_max,
            ay_min=p.ay_min,
            az_max=p.az_max,
        )
        self.model = self._make_model(ControlConstraints(**vars(self.base_constraints)))
        self.critics: list[CriticFunction] = [
            critic_class(n)(n, p.critic_sections[n]) for n in p.critics
        ]
        v = p.trajectory_validator
        settings = OptimizerSettings(
            batch_size=p.batch_size,
            time_steps=p.time_steps,
            model_dt=p.model_dt,
            iteration_count=p.iteration_count,
            temperature=p.temperature,
            gamma=p.gamma,
            vx_std=p.vx_std,
            vy_std=p.vy_std,
            wz_std=p.wz_std,
            retry_attempt_limit=p.retry_attempt_limit,
            regenerate_noises=p.regenerate_noises,
            model_delay=(p.model_delay_vx, p.model_delay_vy, p.model_delay_wz),
            collision_lookahead_time=v.collision_lookahead_time,
            validator_consider_footprint=v.consider_footprint,
            clamp_raw_controls=p.clamp_raw_controls,
            sgf_order=p.sgf_order,
        )
        self.optimizer = Optimizer(settings, self.model, self.critics, self.rng)
        self.pruner = PathPruner(
            p.prune_distance,
            p.max_robot_pose_search_dist,
            p.enforce_path_inversion,
            p.inversion_xy_tolerance,
            p.inversion_yaw_tolerance,
        )
        self._has_plan = False

    @property
    def control_duration(self) -> float:
        """The controller server's period (1 / controller_frequency), set by the server."""
        return self.optimizer.s.controller_period

    @control_duration.setter
    def control_duration(self, period: float) -> None:
        self.optimizer.s.controller_period = period

    def _make_model(self, constraints: ControlConstraints) -> MotionModel:
        choice = self.params.model_section()
        return make_motion_model(choice.cls, constraints, self.params.model_dt, choice.params)

    # -- nav2_core::Controller ------------------------------------------------------------

    def configure(self, costmap_ros: Any) -> None:
        """As Nav2's critic manager configures each critic with the costmap server."""
        super().configure(costmap_ros)
        self.optimizer.costmap_ros = costmap_ros
        for critic in self.critics:
            critic.configure(costmap_ros)

    def set_plan(self, path: Path) -> None:
        poses = np.asarray(path.poses, dtype=np.float64)
        if poses.ndim != 2 or poses.shape[0] == 0 or poses.shape[1] < 2:
            raise InvalidPath("MPPI: the path is empty")
        if poses.shape[1] == 2:
            poses = np.concatenate([poses, np.zeros((len(poses), 1))], axis=1)
        self.pruner.set_plan(poses[:, :3])
        self._has_plan = True

    def compute_velocity_commands(
        self, pose: Pose2D, velocity: Twist, costmap: Costmap2D, goal_checker: Any = None
    ) -> Twist:
        if not self._has_plan:
            raise InvalidPath("MPPI: no path set")
        robot = np.array([pose.x, pose.y, pose.yaw], dtype=np.float64)
        half_diag = 0.5 * fmath.hypot(*costmap.size_in_meters)
        path = self.pruner.local_path(robot, half_diag)
        goal = np.asarray(self.pruner.goal(), dtype=np.float64)
        speed = (float(velocity.linear_x), float(velocity.linear_y), float(velocity.angular_z))
        vx, vy, wz = self.optimizer.eval_control(
            robot, speed, path, goal, costmap, goal_checker, self.params.open_loop
        )
        return Twist(linear_x=vx, linear_y=vy, angular_z=wz)

    def set_speed_limit(self, speed_limit: float, percentage: bool) -> None:
        """Scale vx/vy/wz limits (Nav2: a percentage, or an absolute vx that sets the ratio)."""
        base, c = self.base_constraints, self.model.c
        if speed_limit <= 0.0:
            ratio = 1.0
        elif percentage:
            ratio = min(speed_limit / 100.0, 1.0)
        else:
            ratio = min(speed_limit / base.vx_max, 1.0) if base.vx_max > 0 else 1.0
        c.vx_max, c.vx_min = base.vx_max * ratio, base.vx_min * ratio
        c.vy_max, c.wz_max = base.vy_max * ratio, base.wz_max * ratio

    def reset(self) -> None:
        self.optimizer.reset()
        self._has_plan = False

    # -- introspection ------------------------------------------------------------------

    def local_plan(self, pose: Pose2D) -> np.ndarray | None:
        """The optimal trajectory (what MPPI publishes as its local plan)."""
        return self.optimal_trajectory(pose) if self._has_plan else None

    def optimal_trajectory(self, pose: Pose2D) -> np.ndarray:
        """(T, 3) poses of the current (already shifted) control sequence, for plots and tests."""
        return self.optimizer.optimal_trajectory(np.array([pose.x, pose.y, pose.yaw]))
