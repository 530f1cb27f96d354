"""Nav2's controller_server: FollowPath at `controller_frequency` on the local costmap.

`ControllerServer(runtime, params, local_costmap)` builds its `controller_plugins`,
`goal_checker_plugins`, `progress_checker_plugins` and path handler from its params
section and serves `follow_path` (FollowPath; goal `FollowPathGoal(path,
controller_id, goal_checker_id, progress_checker_id)`). One cycle, as Nav2's
`computeControl` loop does it:

1. the robot pose in the costmap's frame (`odom` for Nav2's rolling local costmap);
   a missing transform aborts with TF_ERROR;
2. the progress checker: no progress for `movement_time_allowance` aborts with
   FAILED_TO_MAKE_PROGRESS;
3. the path handler prunes the global plan (in `map`) at the robot and gives the
   local plan in the costmap frame; the controller is given the remaining plan in
   the costmap frame whenever a new path arrives or `map -> odom` has moved (a
   localiser's correction);
4. the controller computes a command from the pose and the odometry twist
   (thresholded by `min_*_velocity_threshold`). `NoValidControl` is tolerated for
   `failure_tolerance` seconds (zero velocity meanwhile; -1 forever), then
   PATIENCE_EXCEEDED; any other controller exception aborts with its code;
5. the command goes to `runtime.set_cmd_vel`; feedback is Nav2's TrackingFeedback (the signed
   cross-track and heading errors against the plan, distance_to_goal, speed, ...);
6. the goal checker (`goal_checker_id`) decides success.

A finished, aborted or canceled goal leaves a zero command. A new path sent while one
runs preempts it: the plan is swapped, the progress checker and the controller keep
their state (Nav2's `updateGlobalPath`), the goal checker is reset.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..control.exceptions import ControllerException, NoValidControl
from ..core import fmath
from ..core.error_codes import FollowPathError, NavResult
from ..core.errors import FrameError
from ..core.frames import MAP
from ..core.geometry import Pose2D, angle_diff, compose_arrays
from ..core.messages import Path, TrackingFeedback, Twist
from ..core.nav2_msgs import FollowPathGoal
from ..params.paramsfile import ServerParams
from .actions import ActionServer, GoalHandle
from .costmap_server import CostmapServer
from .path_tracking import PathTracker
from .runtime import Runtime
from .server_plugins import PluginServer, make_plugin, make_plugins, pick

#: A map -> odom change beyond these re-sends the plan to the controller in the odom frame.
_REPLAN_XY = 0.01
_REPLAN_YAW = 0.005


class ControllerServer(PluginServer):
    """controller_server: owns the controller, goal checker, progress checker and path
    handler plugins and the `follow_path` action, run at `controller_frequency`."""

    kind = "controller"

    def __init__(
        self,
        runtime: Runtime,
        params: ServerParams,
        costmap: CostmapServer,
        *,
        seed: int | None = None,
    ) -> None:
        super().__init__(runtime, params, costmap, seed=seed)
        self.rate = float(params.model.controller_frequency)
        self.goal_checkers: dict[str, Any] = make_plugins(params, "goal_checker")
        self.progress_checkers: dict[str, Any] = make_plugins(params, "progress_checker")
        handlers = make_plugins(params, "path_handler")
        if not handlers:
            from ..control.path_handler import FeasiblePathHandler

            handlers = {"PathHandler": FeasiblePathHandler()}
        self.path_handler = next(iter(handlers.values()))
        self.tracker = PathTracker()
        self._set_control_duration()
        self.controller: Any = None
        #: The speed limit in force (Nav2's SpeedLimit message: limit, percentage); 0: none.
        self.speed_limit: tuple[float, bool] = (0.0, True)
        self.goal_checker: Any = None
        self.progress_checker: Any = None
        self.last_valid_cmd_time = 0.0
        self.last_cmd = Twist()
        self.local_plan: Path | None = None
        self._fed_transform: Pose2D | None = None
        self._fed_plan: Any = None

    def action_servers(self) -> list[ActionServer[Any]]:
        self.action: ActionServer[FollowPathGoal] = ActionServer(
            "FollowPath",
            "follow_path",
            on_start=self.on_start,
            on_preempt=self.on_preempt,
            execute=self.execute,
            on_cancel=self.on_cancel,
        )
        return [self.action]

    @property
    def controllers(self) -> dict[str, Any]:
        """The controller plugins by name (the server's `plugins`)."""
        return self.plugins

    # -- hooks ------------------------------------------------------------------------------

    def on_start(self, handle: GoalHandle[FollowPathGoal], now: float) -> NavResult | None:
        failed = self._select(handle.goal)
        if failed is not None:
            return self._abort(failed)
        self.progress_checker.reset()
        self.controller.reset()
        failed = self._set_path(handle.goal.path)
        if failed is not None:
            return self._abort(failed)
        self.last_valid_cmd_time = now
        return self.execute(handle, now)

    def on_preempt(
        self, old: GoalHandle[FollowPathGoal], new: GoalHandle[FollowPathGoal], now: float
    ) -> NavResult | None:
        previous = self.controller
        failed = self._select(new.goal)
        if failed is not None:
            return self._abort(failed)
        if self.controller is not previous:
            self.controller.reset()
        failed = self._set_path(new.goal.path)
        if failed is not None:
            return self._abort(failed)
        return self.execute(new, now)

    def execute(self, handle: GoalHandle[FollowPathGoal], now: float) -> NavResult | None:
        try:
            frame = self.costmap.global_frame
            pose = self.runtime.lookup(frame, self.costmap.robot_base_frame)
            plan_frame = self.path_handler.global_plan.frame_id or MAP
            plan_to_costmap = self.runtime.lookup(frame, plan_frame)
        except FrameError as exc:
            return self._abort(NavResult.failure(FollowPathError.TF_ERROR, str(exc)))

        if not self.progress_checker.check(pose, now):
            return self._abort(NavResult.failure(FollowPathError.FAILED_TO_MAKE_PROGRESS))

        velocity = self._odom_twist()
        try:
            pose_in_plan = plan_to_costmap.inverse() @ pose
            self.local_plan = self.path_handler.transform_global_plan(
                pose_in_plan, self.costmap.costmap, plan_to_costmap
            )
            self._feed_controller(plan_to_costmap)
            cmd = self.controller.compute_velocity_commands(
                pose, velocity, self.costmap.costmap, self.goal_checker
            )
            self.last_valid_cmd_time = now
        except NoValidControl as exc:
            tolerance = self.params.model.failure_tolerance
            if tolerance == 0.0:
                return self._abort(NavResult.failure(exc.error_code, str(exc)))
            cmd = Twist()
            if tolerance != -1.0 and now - self.last_valid_cmd_time > tolerance:
                return self._abort(
                    NavResult.failure(
                        FollowPathError.PATIENCE_EXCEEDED,
                        f"controller patience exceeded ({tolerance} s): {exc}",
                    )
                )
        except ControllerException as exc:
            return self._abort(NavResult.failure(exc.error_code, str(exc)))

        self._publish(cmd)
        goal = self.path_handler.transformed_goal(plan_to_costmap)
        handle.publish_feedback(self._tracking_feedback(pose_in_plan, velocity, now), now)
        if self.goal_checker.is_goal_reached(pose, goal, velocity, self.local_plan):
            self._publish(Twist())
            return NavResult.success()
        return None

    def on_cancel(self, handle: GoalHandle[FollowPathGoal], now: float) -> NavResult | None:
        self._publish(Twist())
        return NavResult.cancellation()

    # -- pieces -----------------------------------------------------------------------------

    def _tracking_feedback(
        self, pose_in_plan: Pose2D, velocity: Twist, now: float
    ) -> TrackingFeedback:
        """Nav2's FollowPath feedback (nav2_msgs/TrackingFeedback) against the global plan."""
        plan = self.path_handler.global_plan
        self.tracker.set_path(plan)
        index, error, heading, remaining = self.tracker.track(pose_in_plan)
        return TrackingFeedback(
            stamp=now,
            position_tracking_error=error,
            heading_tracking_error=heading,
            current_path_index=index,
            robot_pose=pose_in_plan,
            distance_to_goal=self.local_plan.length() if self.local_plan is not None else 0.0,
            speed=fmath.hypot(velocity.linear_x, velocity.linear_y),
            remaining_path_length=remaining,
            frame_id=plan.frame_id or MAP,
        )

    def _select(self, goal: FollowPathGoal) -> NavResult | None:
        chosen = []
        for what, plugins, wanted in (
            ("controller", self.controllers, goal.controller_id),
            ("goal checker", self.goal_checkers, goal.goal_checker_id),
            ("progress checker", self.progress_checkers, goal.progress_checker_id),
        ):
            plugin = pick(plugins, wanted)
            if plugin is None:  # Nav2 answers every unknown id with INVALID_CONTROLLER
                return NavResult.failure(
                    FollowPathError.INVALID_CONTROLLER,
                    f"{what} id '{wanted}' is not one of: {', '.join(plugins)}",
                )
            chosen.append(plugin)
        controller, goal_checker, progress_checker = chosen
        if self.progress_checker is not None and progress_checker is not self.progress_checker:
            progress_checker.reset()
        self.controller, self.goal_checker = controller, goal_checker
        self.progress_checker = progress_checker
        return None

    def _set_path(self, path: Path) -> NavResult | None:
        if path is None or len(path) == 0:
            return NavResult.failure(FollowPathError.INVALID_PATH, "Path is empty.")
        self.path_handler.set_plan(path)
        self.goal_checker.reset()
        self._fed_transform = None
        self._fed_plan = None
        return None

    def _feed_controller(self, plan_to_costmap: Pose2D) -> None:
        """Give the controller the remaining plan in the costmap frame when it has changed."""
        plan = self.path_handler.plan_up_to_constraint
        fed = self._fed_transform
        if (
            fed is not None
            and self._fed_plan is self.path_handler.global_plan
            and fmath.hypot(fed.x - plan_to_costmap.x, fed.y - plan_to_costmap.y) < _REPLAN_XY
            and abs(angle_diff(fed.yaw, plan_to_costmap.yaw)) < _REPLAN_YAW
        ):
            return
        poses = compose_arrays(plan_to_costmap.as_array(), np.asarray(plan, float))
        msg = Path(self.runtime.now, poses, self.costmap.global_frame)
        if self._fed_plan is self.path_handler.global_plan:
            self.controller.refresh_plan(msg)  # only map -> odom moved: keep its state
        else:
            self.controller.set_plan(msg)
        self._fed_transform = plan_to_costmap
        self._fed_plan = self.path_handler.global_plan

    def _odom_twist(self) -> Twist:
        t = self.runtime.latest_odom.twist
        m = self.params.model
        return Twist(
            linear_x=t.linear_x if abs(t.linear_x) >= m.min_x_velocity_threshold else 0.0,
            linear_y=t.linear_y if abs(t.linear_y) >= m.min_y_velocity_threshold else 0.0,
            angular_z=t.angular_z if abs(t.angular_z) >= m.min_theta_velocity_threshold else 0.0,
        )

    def _publish(self, cmd: Twist) -> None:
        self.last_cmd = cmd
        self.runtime.set_cmd_vel(cmd)

    def _abort(self, result: NavResult) -> NavResult:
        if self.params.model.publish_zero_velocity:
            self._publish(Twist())
        return result

    def set_speed_limit(self, speed_limit: float, percentage: bool) -> None:
        """Nav2's `speed_limit` topic (a speed filter, a route's AdjustSpeedLimit): every
        controller takes it, as Nav2's speedLimitCallback hands it to each; 0 lifts it."""
        self.speed_limit = (float(speed_limit), bool(percentage))
        for controller in self.controllers.values():
            controller.set_speed_limit(*self.speed_limit)

    def _set_control_duration(self) -> None:
        period = 1.0 / self.params.model.controller_frequency
        for controller in self.controllers.values():
            if hasattr(controller, "control_duration"):
                controller.control_duration = period

    # -- dynamic parameters -----------------------------------------------------------------

    def set_parameters(self, params: ServerParams) -> None:
        """Apply params `validate_update` accepted: checkers take their new sections; a
        controller whose section changed is rebuilt (and given the running plan);
        a new `controller_frequency` reschedules the server."""
        old_rate = self.rate
        self.params = params
        self.rate = float(params.model.controller_frequency)
        for name, section in params.plugins.items():
            if section.params is None:
                continue
            if name in self.goal_checkers:
                self.goal_checkers[name].params = section.params
            elif name in self.progress_checkers:
                self.progress_checkers[name].params = section.params
            elif self.path_handler.name == name:
                self.path_handler.params = section.params
            elif name in self.controllers and section.params != self.controllers[name].params:
                fresh = make_plugin(section, seed=self.seed, server=params.name)
                fresh.configure(self.costmap.costmap_ros)
                fresh.set_speed_limit(*self.speed_limit)
                if self.controller is self.controllers[name]:
                    self.controller = fresh
                    self._fed_transform = None
                self.controllers[name] = fresh
        self._set_control_duration()
        if self.rate != old_rate:  # rescheduled at the new rate
            self.runtime.remove(self)
            self.runtime.add(self)
