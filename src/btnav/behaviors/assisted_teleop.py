"""AssistedTeleop: a person's teleop commands, slowed or stopped before the local costmap's
obstacles (nav2_behaviors::AssistedTeleop).

While the goal runs, the latest `cmd_vel_teleop` twist is projected forward in steps of
the behavior_server's `simulation_time_step` up to `projection_time`, the footprint
checked on the local costmap at each step. A collision at the first step sends zero;
a collision at step time t scales the command by t / projection_time; a free projection
sends it as it is. `preempt_teleop` (the user saying "done") ends the goal SUCCEEDED;
`time_allowance` (0 or less: none) running out ends it TIMEOUT.

Nav2 projects a sideways velocity with its sign flipped in y (`vx sin - vy cos`); btnav
projects it as the robot moves (`vx sin + vy cos`). A differential robot (vy = 0) sees
no difference.
"""

from __future__ import annotations

import numpy as np

from ..core import fmath
from ..core.messages import Twist
from ..core.nav2_msgs import AssistedTeleopFeedback, AssistedTeleopGoal
from ..params.navigation import BehaviorServerParams
from ..plugins import register
from .behavior import Behavior, BehaviorEnv, BehaviorOutcome
from .collision import CollisionChecker

#: The topics the behaviour listens on (Nav2's default names).
TELEOP_TOPIC = "cmd_vel_teleop"
PREEMPT_TOPIC = "preempt_teleop"


@register("behavior", "nav2_behaviors::AssistedTeleop", aliases=["btnav/AssistedTeleop"])
class AssistedTeleop(Behavior):
    """Pass teleop commands on, scaled down as the footprint's projection nears an obstacle."""

    action = "AssistedTeleop"

    def configure(
        self,
        server: BehaviorServerParams,
        env: BehaviorEnv,
        collision_checker: CollisionChecker | None = None,
    ) -> None:
        """As every behaviour, and subscribed to `cmd_vel_teleop` and `preempt_teleop`
        (`env` is a Runtime: it has `subscribe`)."""
        super().configure(server, env, collision_checker)
        self.teleop_twist = Twist()
        self.preempt_teleop = False
        env.subscribe(TELEOP_TOPIC, self._teleop_received)  # type: ignore[attr-defined]
        env.subscribe(PREEMPT_TOPIC, self._preempt_received)  # type: ignore[attr-defined]

    def _teleop_received(self, twist: Twist) -> None:
        self.teleop_twist = twist

    def _preempt_received(self, _msg: object) -> None:
        self.preempt_teleop = True

    def on_run(self, goal: AssistedTeleopGoal, now: float) -> BehaviorOutcome | None:
        self.preempt_teleop = False
        self.set_time_allowance(goal.time_allowance, now)
        return None

    def on_action_completion(self) -> None:
        self.teleop_twist = Twist()
        self.preempt_teleop = False

    def on_cycle_update(self, now: float) -> BehaviorOutcome | None:
        self.publish_feedback(AssistedTeleopFeedback(now - (self.start_time or now)))
        if self.timed_out(now):
            return self.fail(
                "TIMEOUT",
                f"assisted_teleop: time_allowance of {self.time_allowance:g} s ran out",
            )
        if self.preempt_teleop:
            return self.succeed()
        twist = self.teleop_twist
        scale = self.collision_scale(twist)
        self.env.set_cmd_vel(
            Twist(twist.linear_x * scale, twist.linear_y * scale, twist.angular_z * scale)
        )
        return None

    def projection_times(self) -> list[float]:
        """Nav2's projection steps: dt, 2 dt, ... while below projection_time (summed as
        Nav2 sums them, so 1.0 s in 0.1 s steps is ten steps)."""
        dt, horizon = self.server.simulation_time_step, self.server.projection_time
        times, t = [], dt
        while t < horizon:
            times.append(t)
            t += dt
        return times

    def collision_scale(self, twist: Twist) -> float:
        """1 when the projected footprint stays free, t / projection_time when it first hits
        at time t, 0 when it hits at the first step."""
        if self.collision_checker is None:
            return 1.0
        times = self.projection_times()
        if not times:
            return 1.0
        dt = self.server.simulation_time_step
        start = self.robot_pose()
        k = np.arange(len(times))
        yaw_before = start.yaw + k * (dt * twist.angular_z)  # the heading each step starts from
        s, c = fmath.sincos(yaw_before)
        x = start.x + np.cumsum(dt * (twist.linear_x * c - twist.linear_y * s))
        y = start.y + np.cumsum(dt * (twist.linear_x * s + twist.linear_y * c))
        hit = self.collision_checker.first_collision(
            np.stack([x, y, yaw_before + dt * twist.angular_z], axis=1)
        )
        if hit is None:
            return 1.0
        return 0.0 if hit == 0 else times[hit] / self.server.projection_time
