"""Drive: a teleop script, the deterministic spelling of "drive around with teleop to map".

teleop_twist_keyboard publishes `cmd_vel` straight to the base, past Nav2; so does
this action: each `(linear_x, angular_z, seconds)` command is held for its seconds of
sim time, then the next, then the robot is stopped. The base follows it within its
own drive limits (the world's `robot.limits`), as a real base follows a joystick.
Nothing checks for collisions, as nothing does for a person at the keyboard.
"""

from __future__ import annotations

import math

from ..core.error_codes import NavResult
from ..core.messages import Twist
from ..core.nav2_msgs import DriveFeedback, DriveGoal
from .actions import ActionServer, GoalHandle
from .runtime import Runtime, Stage

#: Hz: how often the script's command is sent (teleop_twist_keyboard's key-repeat rate).
TELEOP_RATE = 20.0


class DriveServer(ActionServer[DriveGoal]):
    """The `drive` action: a teleop script on sim time."""

    stage = Stage.SERVER

    def __init__(self, runtime: Runtime, name: str = "drive") -> None:
        super().__init__("Drive", name, rate=TELEOP_RATE, preemptible=True)
        self.runtime = runtime
        self._ends: list[float] = []

    def validate_goal(self, goal: DriveGoal) -> str | None:
        for i, command in enumerate(goal.commands):
            if len(command) != 3 or not all(math.isfinite(float(c)) for c in command):
                return f"command {i} is not [linear_x, angular_z, seconds] in finite numbers"
            if float(command[2]) < 0.0:
                return f"command {i} lasts {command[2]} s; a duration is not negative"
        return None

    def on_start(self, handle: GoalHandle[DriveGoal], now: float) -> NavResult | None:
        self._ends, t = [], now
        for _, _, seconds in handle.goal.commands:
            t += float(seconds)
            self._ends.append(t)
        return self.execute(handle, now)

    def on_preempt(
        self, old: GoalHandle[DriveGoal], new: GoalHandle[DriveGoal], now: float
    ) -> NavResult | None:
        return self.on_start(new, now)

    def execute(self, handle: GoalHandle[DriveGoal], now: float) -> NavResult | None:
        # the command whose span holds `now` (a small tolerance: sim time is in ns steps)
        i = next((k for k, end in enumerate(self._ends) if now < end - 1e-9), None)
        if i is None:
            self.runtime.command_base(Twist())
            return NavResult.success()
        v, w, _ = handle.goal.commands[i]
        self.runtime.command_base(Twist(linear_x=float(v), angular_z=float(w)))
        handle.publish_feedback(DriveFeedback(i, self._ends[-1] - now), now)
        return None

    def on_cancel(self, handle: GoalHandle[DriveGoal], now: float) -> NavResult | None:
        self.runtime.command_base(Twist())
        return NavResult.cancellation()

    def __repr__(self) -> str:
        return f"DriveServer({self.name!r})"
