"""The behaviour plugin base: Nav2's TimedBehavior on sim time.

A behaviour is one recovery motion (Spin, BackUp, DriveOnHeading, Wait). The
behavior_server gives each its own action server and calls it at
`cycle_frequency`:

- `on_run(goal, now)` once when a goal starts: check the goal, note the start pose.
  Return None to go on, or `self.fail("INVALID_INPUT", ...)` (TF_ERROR, ...).
- `on_cycle_update(now)` on every cycle after that, starting in the same cycle as
  `on_run`: publish a velocity and feedback, and return None while running, or
  `self.succeed()` / `self.fail(code_name)` to finish. Codes are named as in the
  action definition (TIMEOUT, COLLISION_AHEAD, ...); the behavior_server turns the
  name into the number of the action's table, so this layer needs nothing of nav/.
- A client's cancel stops the robot and ends the goal CANCELED.
- However a goal ends (success, failure, cancel), a zero velocity is sent, so the
  base never keeps moving on a stale command; `on_action_completion()` then lets
  the behaviour forget the goal.

`time_allowance` (seconds; 0 or less means no limit, as in Nav2) is checked by
the behaviours that take one, with `self.timed_out(now)`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar, Protocol

from ..core.errors import BtnavError
from ..core.geometry import Pose2D
from ..core.messages import Twist
from ..core.nav2_msgs import BehaviorResult
from ..params.navigation import BehaviorServerParams
from ..params.schema import ParamsModel
from .collision import CollisionChecker


class BehaviorEnv(Protocol):
    """What a behaviour needs from the robot: transforms and a velocity command.

    The `Runtime` has this shape; a test may pass anything that does.
    """

    def lookup(self, target: str, source: str) -> Pose2D: ...

    def set_cmd_vel(self, cmd: Twist) -> None: ...


@dataclass(frozen=True)
class BehaviorOutcome:
    """How a goal ended: `status` "succeeded" | "failed" | "canceled", Nav2's code name
    (`error`, "NONE" on success) and a message; `result` is the action's result."""

    status: str
    error: str = "NONE"
    message: str = ""
    result: BehaviorResult = BehaviorResult(0.0)  # noqa: RUF009 (frozen: one shared zero is safe)

    @property
    def succeeded(self) -> bool:
        return self.status == "succeeded"


class Behavior:
    """Base of every `behavior` plugin (nav2_behaviors::TimedBehavior).

    Built as every plugin is, `cls(name, params)` with the plugin's own `Params` (its
    section under behavior_server); then, as nav2_behaviors' configure(), the server
    hands over `configure(server, env, collision_checker)`: the behavior_server's
    shared keys (cycle_frequency, frames, simulate_ahead_time, rotational limits), the
    robot (a Runtime), and a `CollisionChecker` on the local costmap, or None to skip
    collision checks.
    """

    #: Nav2's action type: picks the error-code table ("Spin", "BackUp", ...).
    action: ClassVar[str] = ""
    plugin_kind: ClassVar[str]
    plugin_name: ClassVar[str]

    class Params(ParamsModel):
        pass

    #: The robot, handed over by `configure`.
    env: BehaviorEnv

    def __init__(self, name: str, params: Any = None) -> None:
        self.name = name
        if params is None:
            params = self.Params()
        elif not isinstance(params, self.Params):
            params = self.Params.model_validate(dict(params))
        self.params = params
        self.server = BehaviorServerParams()
        self.collision_checker: CollisionChecker | None = None
        self.start_time: float | None = None
        self.time_allowance = 0.0
        self.end_time: float | None = None
        #: The latest feedback (the server hands it to the goal's client).
        self.feedback: Any = None

    def configure(
        self,
        server: BehaviorServerParams,
        env: BehaviorEnv,
        collision_checker: CollisionChecker | None = None,
    ) -> None:
        """behavior_server hands over what every behaviour shares, once, after construction.

        Args:
            server: behavior_server's shared keys (cycle_frequency, frames, limits).
            env: the robot: transforms and the velocity command (a `Runtime`).
            collision_checker: checks poses on the local costmap; None skips the checks.
        """
        self.server = server
        self.env = env
        self.collision_checker = collision_checker

    # -- what behaviours implement ----------------------------------------------------

    def on_run(self, goal: Any, now: float) -> BehaviorOutcome | None:
        """A goal starts (nav2_behaviors' onRun).

        Args:
            goal: the action's goal (`SpinGoal`, `BackUpGoal`, ...).
            now: sim seconds.

        Returns:
            None to go on to `on_cycle_update`, or a failed outcome with Nav2's code.
        """
        raise NotImplementedError

    def on_cycle_update(self, now: float) -> BehaviorOutcome | None:
        """One cycle at `cycle_frequency` (nav2_behaviors' onCycleUpdate).

        Args:
            now: sim seconds.

        Returns:
            None while running; the outcome (succeeded, or failed with Nav2's code) to end.
        """
        raise NotImplementedError

    def on_action_completion(self) -> None:
        """The goal ended (any way): forget its state."""

    # -- helpers for behaviours -------------------------------------------------------

    @property
    def cycle_frequency(self) -> float:
        return self.server.cycle_frequency

    def robot_pose(self) -> Pose2D:
        """The robot in `local_frame` (odom), as Nav2's behaviours read it."""
        return self.env.lookup(self.server.local_frame, self.server.robot_base_frame)

    def publish_cmd(self, linear_x: float = 0.0, angular_z: float = 0.0) -> None:
        self.env.set_cmd_vel(Twist(linear_x=float(linear_x), angular_z=float(angular_z)))

    def stop_robot(self) -> None:
        self.env.set_cmd_vel(Twist())

    def publish_feedback(self, feedback: Any) -> None:
        self.feedback = feedback

    def set_time_allowance(self, seconds: float, now: float) -> None:
        self.time_allowance = float(seconds)
        self.end_time = now + self.time_allowance

    def timed_out(self, now: float) -> bool:
        """`time_allowance` has run out (never, when it is 0 or less)."""
        return self.time_allowance > 0.0 and self.end_time is not None and now > self.end_time

    def fail(self, code_name: str, msg: str = "") -> BehaviorOutcome:
        """A failed outcome with the action's code `code_name` ("TIMEOUT", ...)."""
        return BehaviorOutcome("failed", code_name, msg, self._result_value())

    def succeed(self) -> BehaviorOutcome:
        return BehaviorOutcome("succeeded", "NONE", "", self._result_value())

    def _result_value(self) -> BehaviorResult:
        now = self._now if self._now is not None else 0.0
        start = self.start_time if self.start_time is not None else now
        return BehaviorResult(total_elapsed_time=now - start)

    _now: float | None = None

    # -- what the behavior_server calls -----------------------------------------------

    def start(self, goal: Any, now: float) -> BehaviorOutcome | None:
        """A goal begins: `on_run`, then its first cycle."""
        self._now = now
        self.start_time = now
        self.time_allowance, self.end_time = 0.0, None
        self.feedback = None
        try:
            outcome = self.on_run(goal, now)
        except BtnavError as exc:  # a frame that does not resolve: Nav2's TF_ERROR
            outcome = self.fail("TF_ERROR", f"{self.name}: {exc}")
        if outcome is not None:
            return self._end(outcome)
        return self.cycle(now)

    def cycle(self, now: float) -> BehaviorOutcome | None:
        """One cycle of the running goal."""
        self._now = now
        try:
            outcome = self.on_cycle_update(now)
        except BtnavError as exc:
            outcome = self.fail("TF_ERROR", f"{self.name}: {exc}")
        return None if outcome is None else self._end(outcome)

    def cancel(self, now: float) -> BehaviorOutcome:
        """The client canceled: stop now."""
        self._now = now
        return self._end(BehaviorOutcome("canceled", "NONE", "", self._result_value()))

    def _end(self, outcome: BehaviorOutcome) -> BehaviorOutcome:
        self.stop_robot()
        self.on_action_completion()
        return outcome

    def __repr__(self) -> str:
        return f"{type(self).__name__}({self.name!r})"
