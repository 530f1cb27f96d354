"""Drive: a teleop script, the deterministic spelling of "drive around with teleop to map".

teleop_twist_keyboard publishes `cmd_vel` straight to the base, past Nav2; so does
this action: each `(linear_x, angular_z, seconds)` command is held for its seconds of
sim time, then the next, then the robot is stopped. The base follows it within its
own drive limits (the world's `robot.limits`), as a real base follows a joystick.
Nothing checks for collisions, as nothing does for a person at the keyboard.

With `assisted` the script drives as a person does through Nav2's AssistedTeleop: the
action starts the behavior_server's `assisted_teleop` goal (no time allowance), the
commands go to `cmd_vel_teleop`, which the behaviour slows or stops before the local
costmap's obstacles, and the end of the script is the person's `preempt_teleop`.
"""

from __future__ import annotations

import math

from ..behaviors.assisted_teleop import PREEMPT_TOPIC, TELEOP_TOPIC
from ..core.error_codes import DriveError, NavResult
from ..core.messages import Twist
from ..core.nav2_msgs import AssistedTeleopGoal, DriveFeedback, DriveGoal
from .actions import ActionServer, GoalHandle
from .runtime import Runtime, Stage

#: Hz: how often the script's command is sent (teleop_twist_keyboard's key-repeat rate).
TELEOP_RATE = 20.0

#: The behavior_server's action an assisted drive goes through.
ASSISTED_TELEOP = "assisted_teleop"


class DriveServer(ActionServer[DriveGoal]):
    """The `drive` action: a teleop script on sim time."""

    stage = Stage.SERVER

    def __init__(self, runtime: Runtime, name: str = "drive") -> None:
        super().__init__("Drive", name, rate=TELEOP_RATE, preemptible=True)
        self.runtime = runtime
        self._ends: list[float] = []
        self._assist: GoalHandle[AssistedTeleopGoal] | None = None

    def validate_goal(self, goal: DriveGoal) -> str | None:
        for i, command in enumerate(goal.commands):
            if len(command) != 3 or not all(math.isfinite(float(c)) for c in command):
                return f"command {i} is not [linear_x, angular_z, seconds] in finite numbers"
            if float(command[2]) < 0.0:
                return f"command {i} lasts {command[2]} s; a duration is not negative"
        if goal.assisted and ASSISTED_TELEOP not in self.runtime.action_servers:
            return (
                "an assisted drive needs the behavior_server's assisted_teleop "
                "(behavior_plugins lists no 'assisted_teleop' with nav2_behaviors::AssistedTeleop)"
            )
        return None

    def on_start(self, handle: GoalHandle[DriveGoal], now: float) -> NavResult | None:
        self._ends, t = [], now
        for _, _, seconds in handle.goal.commands:
            t += float(seconds)
            self._ends.append(t)
        if handle.goal.assisted and self._assist is None:
            client = self.runtime.action_client(ASSISTED_TELEOP)
            self._assist = client.send_goal(AssistedTeleopGoal(time_allowance=0.0))
        return self.execute(handle, now)

    def on_preempt(
        self, old: GoalHandle[DriveGoal], new: GoalHandle[DriveGoal], now: float
    ) -> NavResult | None:
        if not new.goal.assisted:
            self._end_assist(cancel=True)
        return self.on_start(new, now)

    def execute(self, handle: GoalHandle[DriveGoal], now: float) -> NavResult | None:
        if self._assist is not None and self._assist.done:  # the behaviour gave up
            result = self._assist.result
            self._assist = None
            msg = result.error_msg if result is not None else ""
            return NavResult.failure(DriveError.UNKNOWN, f"assisted_teleop ended: {msg}")
        # the command whose span holds `now` (a small tolerance: sim time is in ns steps)
        i = next((k for k, end in enumerate(self._ends) if now < end - 1e-9), None)
        if i is None:
            self._send(handle.goal, Twist())
            self._end_assist(cancel=False)
            return NavResult.success()
        v, w, _ = handle.goal.commands[i]
        self._send(handle.goal, Twist(linear_x=float(v), angular_z=float(w)))
        handle.publish_feedback(DriveFeedback(i, self._ends[-1] - now), now)
        return None

    def on_cancel(self, handle: GoalHandle[DriveGoal], now: float) -> NavResult | None:
        self._send(handle.goal, Twist())
        self._end_assist(cancel=True)
        return NavResult.cancellation()

    def _send(self, goal: DriveGoal, cmd: Twist) -> None:
        """The person's command: to AssistedTeleop's topic, or straight to the base."""
        if goal.assisted:
            self.runtime.publish(TELEOP_TOPIC, cmd)
        else:
            self.runtime.command_base(cmd)

    def _end_assist(self, *, cancel: bool) -> None:
        """End the AssistedTeleop goal: the person's `preempt_teleop`, or a cancel."""
        if self._assist is None:
            return
        if cancel:
            self._assist.cancel()
        else:
            self.runtime.publish(PREEMPT_TOPIC, None)
        self._assist = None

    def __repr__(self) -> str:
        return f"DriveServer({self.name!r})"
