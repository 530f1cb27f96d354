"""Nav2's docking_server (opennav_docking): DockRobot and UndockRobot at `controller_frequency`.

`DockingServer(runtime, params, local_costmap)` builds the `dock_plugins`, the dock
database (`docks:` or `dock_database:`), the graceful approach controller (checking
ahead on the local costmap) and serves `dock_robot` and `undock_robot`. Its velocity
goes to the base directly (`runtime.command_base`): in Nav2's bringup the docking
server's `cmd_vel` is not remapped through the velocity smoother or collision monitor.
Detections from the robot's dock detectors reach every dock plugin as Nav2's
`detected_dock_pose`, taken into `fixed_frame` as they arrive (tf2 transforms a
detection at its stamp).

DockRobot, one step per cycle, as Nav2's `dockRobot` loop:

1. the dock: `dock_id` from the database (DOCK_NOT_IN_DB, DOCK_NOT_VALID) or
   `dock_pose` with `dock_type`; a charger the robot is docked at already succeeds;
2. the staging pose: unless the robot is within `dock_prestaging_tolerance` of it (an
   L2 norm over x, y and yaw) or `navigate_to_staging_pose` is false, NavigateToPose
   takes it there within `max_staging_time` (FAILED_TO_STAGE);
3. the initial perception: the plugin's refined pose within
   `initial_perception_timeout` (FAILED_TO_DETECT_DOCK);
4. the approach: turned round first if the plugin rotates to dock; the control law
   towards the dock pose projected 0.25 m beyond it, until the plugin says docked,
   within `dock_approach_timeout` (FAILED_TO_CONTROL; lost detection:
   FAILED_TO_DETECT_DOCK); then, at a charger, charging within `wait_charge_timeout`
   (FAILED_TO_CHARGE). A failure here drives back to the staging pose (within the
   undock tolerances) and tries again, `max_retries` times.

UndockRobot drives from the dock to its staging pose (within `undock_linear_tolerance`
and `undock_angular_tolerance`) in `max_undocking_time`, for the dock type docked at
last (or the goal's `dock_type`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..core import fmath
from ..core.error_codes import DockRobotError, NavResult, Outcome, UndockRobotError
from ..core.errors import FrameError, ParamsError
from ..core.geometry import Pose2D, angle_diff
from ..core.messages import PoseStamped, Twist
from ..core.nav2_docking_msgs import (
    DockDetection,
    DockingState,
    DockRobotFeedback,
    DockRobotGoal,
    DockRobotResult,
    UndockRobotGoal,
    UndockRobotResult,
)
from ..docking import plugins as _dock_plugins  # noqa: F401  (registers the dock plugins)
from ..docking.charging_dock import ChargingDock, DockDirection
from ..docking.controller import DockingController
from ..docking.dock_database import Dock, DockDatabase, docks_of
from ..docking.exceptions import (
    DockingException,
    DockNotValid,
    FailedToCharge,
    FailedToControl,
    FailedToDetectDock,
)
from ..docking.simple_dock import in_frame
from ..params.paramsfile import ServerParams
from ..sim.dock_detector import DockDetector
from .actions import ActionServer, GoalHandle
from .docking_navigator import StagingNavigator
from .runtime import Runtime, Stage
from .server_plugins import make_plugins

#: Nav2 aims the approach this far (m) beyond the dock, so the spiral's end, where the
#: law's angles jitter, is never reached before the robot is docked.
BACKWARD_PROJECTION = 0.25
#: UndockRobot's codes by number (its failures are DockRobot's exceptions, as in Nav2).
_UNDOCK_CODES = {int(code): code for code in UndockRobotError}


@dataclass
class _Docking:
    """One DockRobot goal in progress."""

    dock: Dock
    phase: str  # stage, perceive, rotate, approach, charge, reset
    since: float  # sim time the phase began
    dock_pose: PoseStamped | None = None
    staging_pose: PoseStamped | None = None
    backward: bool = False


@dataclass
class _Undocking:
    plugin: ChargingDock
    staging_pose: PoseStamped
    backward: bool
    since: float
    rotating_since: float | None = None


class DockingServer:
    """docking_server: the dock plugins, database and controller, and both actions."""

    stage = Stage.SERVER

    def __init__(
        self,
        runtime: Runtime,
        params: ServerParams,
        local_costmap: Any = None,
        *,
        base_dir: str | Path | None = None,
    ) -> None:
        self.runtime = runtime
        self.params = params
        model = params.model
        self.base_frame = model.base_frame
        self.rate = float(model.controller_frequency)
        plugins = self._plugins(params)
        self.database = DockDatabase(plugins, docks_of(model, Path(base_dir) if base_dir else None))
        self.controller = DockingController(
            model.controller,
            base_frame=model.base_frame,
            costmap_ros=local_costmap.costmap_ros if local_costmap is not None else None,
            lookup=runtime.lookup,
        )
        self.navigator = StagingNavigator(runtime, model.navigator_bt_xml)
        for sensor in runtime.sensors:
            if isinstance(sensor, DockDetector):
                runtime.subscribe(sensor.frame_id, self._on_detection)
        #: The dock type docked at last (what UndockRobot undocks from by default).
        self.curr_dock_type = ""
        self.num_retries = 0
        self.action_start = 0.0
        self._docking: _Docking | None = None
        self._undocking: _Undocking | None = None
        self.last_cmd = Twist()
        self.dock_action: ActionServer[DockRobotGoal] = ActionServer(
            "DockRobot",
            "dock_robot",
            on_start=self._dock_start,
            on_preempt=self._dock_preempt,
            execute=self._dock_execute,
            on_cancel=self._dock_cancel,
        )
        self.undock_action: ActionServer[UndockRobotGoal] = ActionServer(
            "UndockRobot",
            "undock_robot",
            on_start=self._undock_start,
            execute=self._undock_execute,
            on_cancel=self._undock_cancel,
        )
        for action in (self.dock_action, self.undock_action):
            runtime.add_action_server(action)

    def _plugins(self, params: ServerParams) -> dict[str, ChargingDock]:
        model = params.model
        where = dict(file=None, line=params.line, key=f"{params.key}.dock_plugins")
        if not model.dock_plugins:
            raise ParamsError(
                "docking_server needs dock_plugins: at least one dock plugin "
                "(e.g. [simple_charging_dock] with plugin: opennav_docking::SimpleChargingDock)",
                **where,
            )
        missing = [s.name for s in params.plugins_of("charging_dock") if s.cls is None]
        if missing:
            raise ParamsError(f"dock plugin '{missing[0]}' is not implemented in btnav", **where)
        plugins: dict[str, ChargingDock] = make_plugins(params, "charging_dock")
        for plugin in plugins.values():
            plugin.configure(self)
        return plugins

    # -- what the dock plugins read (their DockContext) ---------------------------------

    @property
    def now(self) -> float:
        return self.runtime.now

    def lookup(self, target: str, source: str) -> Pose2D:
        return self.runtime.lookup(target, source)

    @property
    def plugins(self) -> dict[str, ChargingDock]:
        return self.database.plugins

    def _on_detection(self, msg: DockDetection) -> None:
        """A detector's measurement: its pose, in fixed_frame, to every dock plugin."""
        if msg is None or msg.pose is None:
            return
        fixed = self.params.model.fixed_frame
        try:
            pose = in_frame(msg.pose, fixed, self.runtime.lookup(fixed, msg.pose.frame_id))
        except FrameError:
            return
        for plugin in self.plugins.values():
            plugin.on_detected_dock_pose(pose)

    # -- the scheduler ------------------------------------------------------------------

    def update(self, now: float) -> None:
        self.dock_action.update(now)
        self.undock_action.update(now)

    # -- DockRobot ----------------------------------------------------------------------

    def _dock_start(self, handle: GoalHandle[DockRobotGoal], now: float) -> NavResult | None:
        self.action_start = now
        self.num_retries = 0
        self._docking = None
        return self._guarded(handle, now, self._begin_docking)

    def _dock_preempt(
        self, old: GoalHandle[DockRobotGoal], new: GoalHandle[DockRobotGoal], now: float
    ) -> NavResult | None:
        self._stop_docking()
        return self._dock_start(new, now)

    def _dock_execute(self, handle: GoalHandle[DockRobotGoal], now: float) -> NavResult | None:
        return self._guarded(handle, now, self._dock_step)

    def _dock_cancel(self, handle: GoalHandle[DockRobotGoal], now: float) -> NavResult | None:
        self._stop_docking()
        return NavResult(Outcome.CANCELED, 0, "", DockRobotResult(False, self.num_retries))

    def _guarded(
        self, handle: GoalHandle[DockRobotGoal], now: float, step: Any
    ) -> NavResult | None:
        """Run a docking step; Nav2's exceptions become DockRobot's result codes."""
        try:
            return step(handle, now)  # type: ignore[no-any-return]
        except DockingException as exc:
            code, msg = exc.code, str(exc)
        except FrameError as exc:
            code, msg = DockRobotError.UNKNOWN, f"Transform error: {exc}"
        self._stop_docking()
        return NavResult.failure(code, msg, DockRobotResult(False, self.num_retries))

    def _stop_docking(self) -> None:
        self.navigator.cancel()
        self._publish(Twist())
        if self._docking is not None and self._docking.dock.plugin is not None:
            self._docking.dock.plugin.stop_detection_process()
        self._docking = None

    def _goal_dock(self, goal: DockRobotGoal) -> Dock:
        if goal.use_dock_id:
            return self.database.find_dock(goal.dock_id)
        plugin = self.database.find_dock_plugin(goal.dock_type)
        if plugin is None:
            raise DockNotValid(f"Dock type '{goal.dock_type}' has no valid plugin!")
        pose, frame = _pose_and_frame(goal.dock_pose)
        return Dock(pose, frame, goal.dock_type, "", plugin)

    def _begin_docking(self, handle: GoalHandle[DockRobotGoal], now: float) -> NavResult | None:
        goal = handle.goal
        dock = self._goal_dock(goal)
        plugin = dock.plugin
        assert plugin is not None
        if plugin.is_charger and (plugin.is_docked() or plugin.is_charging()):
            return self._docked(handle, dock)  # already docked (and charging)
        self._feedback(handle, DockingState.NAV_TO_STAGING_POSE, now)
        staging = dock.staging_pose()
        robot = self.runtime.lookup(staging.frame_id, self.base_frame)
        run = _Docking(dock, "stage", now)
        self._docking = run
        if (
            not goal.navigate_to_staging_pose
            or _l2(robot, staging.pose) < self.params.model.dock_prestaging_tolerance
        ):
            return self._begin_perception(handle, now)
        self.navigator.start(staging, float(goal.max_staging_time), now)
        return None

    def _dock_step(self, handle: GoalHandle[DockRobotGoal], now: float) -> NavResult | None:
        run = self._docking
        if run is None:
            return None
        if run.phase == "stage":
            if self.navigator.step(now):
                return self._begin_perception(handle, now)
            return None
        if run.phase == "perceive":
            return self._perceive(handle, run, now)
        try:
            if run.phase == "reset":
                return self._reset_approach(handle, run, now)
            if run.phase == "rotate":
                return self._rotate_to_dock(handle, run, now)
            if run.phase == "approach":
                return self._approach(handle, run, now)
            return self._wait_for_charge(handle, run, now)
        except DockingException as exc:
            if run.phase == "reset":
                raise  # failing to get back to the staging pose ends the goal
            self.num_retries += 1
            if self.num_retries > self.params.model.max_retries:
                raise type(exc)(
                    f"{exc} (all {self.params.model.max_retries} retries used)"
                ) from None
            self._publish(Twist())
            run.phase, run.since = "reset", now
            return None

    def _begin_perception(self, handle: GoalHandle[DockRobotGoal], now: float) -> NavResult | None:
        run = self._docking
        assert run is not None and run.dock.plugin is not None
        fixed = self.params.model.fixed_frame
        estimate = run.dock.pose_stamped
        tf = self.runtime.lookup(fixed, estimate.frame_id)
        run.dock_pose = PoseStamped(now, tf @ estimate.pose, fixed)
        self._feedback(handle, DockingState.INITIAL_PERCEPTION, now)
        if not run.dock.plugin.start_detection_process():
            raise FailedToDetectDock("Failed to start the detection process.")
        run.phase, run.since = "perceive", now
        return self._perceive(handle, run, now)

    def _perceive(
        self, handle: GoalHandle[DockRobotGoal], run: _Docking, now: float
    ) -> NavResult | None:
        plugin = run.dock.plugin
        assert plugin is not None and run.dock_pose is not None
        refined = plugin.get_refined_pose(run.dock_pose, run.dock.id)
        if refined is None:
            if now - run.since > self.params.model.initial_perception_timeout:
                raise FailedToDetectDock("Failed initial dock detection: Timeout exceeded")
            return None
        run.dock_pose = refined
        direction = self.params.model.dock_backwards
        run.backward = (
            direction if direction is not None else plugin.dock_direction is DockDirection.BACKWARD
        )
        staging = run.dock.staging_pose()
        if plugin.should_rotate_to_dock():
            staging = PoseStamped(staging.stamp, _turned(staging.pose), staging.frame_id)
        run.staging_pose = staging
        return self._begin_control(handle, run, now)

    def _begin_control(
        self, handle: GoalHandle[DockRobotGoal], run: _Docking, now: float
    ) -> NavResult | None:
        """One turn of Nav2's docking loop: rotate (if the plugin does), then approach."""
        assert run.dock.plugin is not None
        if run.dock.plugin.should_rotate_to_dock():
            run.phase, run.since = "rotate", now
            return self._rotate_to_dock(handle, run, now)
        run.phase, run.since = "approach", now
        return self._approach(handle, run, now)

    def _rotate_to_dock(
        self, handle: GoalHandle[DockRobotGoal], run: _Docking, now: float
    ) -> NavResult | None:
        assert run.dock_pose is not None
        if self._rotate_step(run.dock_pose, run.since, now):
            run.phase, run.since = "approach", now
            return self._approach(handle, run, now)
        return None

    def _rotate_step(self, pose: PoseStamped, since: float, now: float) -> bool:
        """One cycle of turning to face away from `pose` (Nav2's rotateToDock); True when done."""
        model = self.params.model
        robot = self.runtime.lookup(pose.frame_id, self.base_frame)
        error = angle_diff(pose.pose.yaw + math.pi, robot.yaw)
        if abs(error) < model.rotation_angular_tolerance:
            return True
        current = self.runtime.latest_odom.twist.angular_z
        self._publish(
            self.controller.compute_rotate_to_heading_command(error, current, 1.0 / self.rate)
        )
        if now - since > model.rotate_to_dock_timeout:
            raise FailedToControl("Timed out rotating to dock")
        return False

    def _approach(
        self, handle: GoalHandle[DockRobotGoal], run: _Docking, now: float
    ) -> NavResult | None:
        plugin = run.dock.plugin
        assert plugin is not None and run.dock_pose is not None
        self._feedback(handle, DockingState.CONTROLLING, now)
        if plugin.is_docked() or (plugin.is_charger and plugin.is_charging()):
            self._publish(Twist())
            run.phase, run.since = "charge", now
            return self._wait_for_charge(handle, run, now)
        refined = plugin.get_refined_pose(run.dock_pose, run.dock.id)
        if refined is None and not plugin.should_rotate_to_dock():
            raise FailedToDetectDock("Failed dock detection")
        if refined is not None:
            run.dock_pose = refined
        projected = run.dock_pose.pose @ Pose2D(BACKWARD_PROJECTION, 0.0, 0.0)
        target = self.runtime.lookup(self.base_frame, run.dock_pose.frame_id) @ projected
        if run.backward:
            target = _turned(target)
        cmd, free = self.controller.compute_velocity_command(target, True, run.backward)
        if not free:
            raise FailedToControl("Failed to get control")
        self._publish(cmd)
        if now - run.since > self.params.model.dock_approach_timeout:
            raise FailedToControl(
                "Timed out approaching dock; dock nor charging (if applicable) detected"
            )
        return None

    def _wait_for_charge(
        self, handle: GoalHandle[DockRobotGoal], run: _Docking, now: float
    ) -> NavResult | None:
        plugin = run.dock.plugin
        assert plugin is not None
        if plugin.is_charger:
            self._feedback(handle, DockingState.WAIT_FOR_CHARGE, now)
            if not plugin.is_charging():
                if now - run.since > self.params.model.wait_charge_timeout:
                    raise FailedToCharge("Timed out waiting for charge to start")
                return None
        return self._docked(handle, run.dock)

    def _toward_staging(self, run: _Docking) -> tuple[bool, Twist]:
        """Whether the robot is back at the staging pose (undocking's tolerances), and the
        command that drives it there (the other way round from docking)."""
        assert run.staging_pose is not None
        model = self.params.model
        return self._command_to_pose(
            run.staging_pose,
            model.undock_linear_tolerance,
            model.undock_angular_tolerance,
            is_docking=False,
            backward=not run.backward,
        )

    def _reset_approach(
        self, handle: GoalHandle[DockRobotGoal], run: _Docking, now: float
    ) -> NavResult | None:
        self._feedback(handle, DockingState.INITIAL_PERCEPTION, now)
        reached, cmd = self._toward_staging(run)
        if reached:
            return self._begin_control(handle, run, now)
        self._publish(cmd)
        if now - run.since > self.params.model.dock_approach_timeout:
            raise FailedToControl("Timed out resetting dock approach")
        return None

    def _docked(self, handle: GoalHandle[DockRobotGoal], dock: Dock) -> NavResult:
        self._publish(Twist())
        if dock.plugin is not None:
            dock.plugin.stop_detection_process()
        self.curr_dock_type = dock.type
        self._docking = None
        return NavResult.success(DockRobotResult(True, self.num_retries))

    def _feedback(self, handle: GoalHandle[DockRobotGoal], state: DockingState, now: float) -> None:
        handle.publish_feedback(
            DockRobotFeedback(state, now - self.action_start, self.num_retries), now
        )

    # -- UndockRobot --------------------------------------------------------------------

    def _undock_start(self, handle: GoalHandle[UndockRobotGoal], now: float) -> NavResult | None:
        self._undocking = None
        try:
            dock_type = handle.goal.dock_type or self.curr_dock_type
            plugin = self.database.find_dock_plugin(dock_type)
            if plugin is None:
                raise DockNotValid("No dock information to undock from!")
            if plugin.is_charger and not plugin.is_docked() and not plugin.is_charging():
                return NavResult(
                    Outcome.FAILED,
                    0,
                    "Robot is not in the dock, no need to undock",
                    UndockRobotResult(False),
                )
            direction = self.params.model.dock_backwards
            backward = (
                direction
                if direction is not None
                else plugin.dock_direction is DockDirection.BACKWARD
            )
            fixed = self.params.model.fixed_frame
            here = self.runtime.lookup(fixed, self.base_frame)
            if backward:
                here = _turned(here)
            staging = plugin.get_staging_pose(here, fixed)
            if plugin.should_rotate_to_dock():
                staging = PoseStamped(staging.stamp, _turned(staging.pose), staging.frame_id)
            self._undocking = _Undocking(plugin, staging, backward, now)
        except (DockingException, FrameError) as exc:
            return self._undock_failed(exc)
        return self._undock_execute(handle, now)

    def _undock_execute(self, handle: GoalHandle[UndockRobotGoal], now: float) -> NavResult | None:
        run = self._undocking
        if run is None:
            return None
        try:
            return self._undock_step(handle, run, now)
        except (DockingException, FrameError) as exc:
            return self._undock_failed(exc)

    def _undock_step(
        self, handle: GoalHandle[UndockRobotGoal], run: _Undocking, now: float
    ) -> NavResult | None:
        plugin = run.plugin
        if run.rotating_since is not None:
            if not self._rotate_step(run.staging_pose, run.rotating_since, now):
                return None
            return self._undocked(run)
        if now - run.since > handle.goal.max_undocking_time:
            raise FailedToControl("Undocking timed out")
        if plugin.is_charger and not plugin.disable_charging():
            return None
        reached, cmd = self._toward_staging(run)
        if not reached:
            self._publish(cmd)
            return None
        if plugin.should_rotate_to_dock():
            run.rotating_since = now
            return self._undock_step(handle, run, now)
        return self._undocked(run)

    def _undocked(self, run: _Undocking) -> NavResult:
        self._publish(Twist())
        if run.plugin.is_charger and not run.plugin.has_stopped_charging():
            raise FailedToControl("Failed to control off dock")
        self.curr_dock_type = ""
        self._undocking = None
        return NavResult.success(UndockRobotResult(True))

    def _undock_failed(self, exc: Exception) -> NavResult:
        self._publish(Twist())
        self._undocking = None
        if isinstance(exc, FrameError):
            code, msg = UndockRobotError.UNKNOWN, f"Transform error: {exc}"
        else:
            code = _UNDOCK_CODES.get(int(getattr(exc, "code", 0)), UndockRobotError.UNKNOWN)
            msg = str(exc)
        return NavResult.failure(code, msg, UndockRobotResult(False))

    def _undock_cancel(self, handle: GoalHandle[UndockRobotGoal], now: float) -> NavResult | None:
        self._publish(Twist())
        self._undocking = None
        return NavResult(Outcome.CANCELED, 0, "", UndockRobotResult(False))

    # -- pieces -------------------------------------------------------------------------

    def _command_to_pose(
        self,
        pose: PoseStamped,
        linear_tolerance: float,
        angular_tolerance: float,
        *,
        is_docking: bool,
        backward: bool,
    ) -> tuple[bool, Twist]:
        """Nav2's getCommandToPose: (reached, the command towards `pose` if not)."""
        robot = self.runtime.lookup(pose.frame_id, self.base_frame)
        distance = fmath.hypot(robot.x - pose.pose.x, robot.y - pose.pose.y)
        yaw = angle_diff(pose.pose.yaw, robot.yaw)
        if distance < linear_tolerance and abs(yaw) < angular_tolerance:
            return True, Twist()
        target = self.runtime.lookup(self.base_frame, pose.frame_id) @ pose.pose
        cmd, free = self.controller.compute_velocity_command(target, is_docking, backward)
        if not free:
            raise FailedToControl("Failed to get control")
        return False, cmd

    def _publish(self, cmd: Twist) -> None:
        self.last_cmd = cmd
        self.runtime.command_base(cmd)

    # -- dynamic parameters -------------------------------------------------------------

    def set_parameters(self, params: ServerParams) -> None:
        """Server keys and the controller take effect at once; a new controller_frequency
        reschedules the server. (Dock plugins keep the params they were built with.)"""
        old_rate = self.rate
        self.params = params
        self.base_frame = params.model.base_frame
        self.controller.set_params(params.model.controller)
        self.controller.base_frame = params.model.base_frame
        self.rate = float(params.model.controller_frequency)
        if self.rate != old_rate:
            self.runtime.remove(self)
            self.runtime.add(self)


def _turned(pose: Pose2D) -> Pose2D:
    """The same position, facing the other way."""
    return Pose2D(pose.x, pose.y, pose.yaw + math.pi)


def _l2(a: Pose2D, b: Pose2D) -> float:
    """Nav2's l2Norm over x, y and the yaw difference."""
    d = angle_diff(b.yaw, a.yaw)
    dx, dy = a.x - b.x, a.y - b.y
    return math.sqrt(dx * dx + dy * dy + d * d)


def _pose_and_frame(pose: Any) -> tuple[Pose2D, str]:
    """A goal's dock_pose (PoseStamped, Pose2D or (x, y, yaw)) and its frame (map by default)."""
    if isinstance(pose, PoseStamped):
        return pose.pose, pose.frame_id
    if isinstance(pose, Pose2D):
        return pose, "map"
    if pose is None:
        raise DockNotValid("use_dock_id is false but the goal gives no dock_pose")
    return Pose2D(*pose), "map"
