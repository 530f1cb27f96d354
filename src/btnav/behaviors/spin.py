"""Spin: turn in place by `target_yaw` (nav2_behaviors::Spin).

The speed follows a profile that brakes into the target: sqrt(2 * rotational_acc_lim
* remaining), clamped to [min_rotational_vel, max_rotational_vel]. The turn is
measured by integrating the shortest yaw change between cycles, so a spin of more
than half a turn (or several turns) works. Each cycle the rest of the rotation
within `simulate_ahead_time` is simulated on the local costmap with the footprint;
a lethal cell under it stops the robot with COLLISION_AHEAD (a round footprint can
only collide if it already touches something; a rectangular one sweeps corners).
"""

from __future__ import annotations

import math

import numpy as np

from ..core.geometry import angle_diff
from ..core.nav2_msgs import SpinFeedback, SpinGoal
from ..plugins import register
from .behavior import Behavior, BehaviorOutcome


@register("behavior", "nav2_behaviors::Spin", aliases=["btnav/Spin"])
class Spin(Behavior):
    """Turn in place by `target_yaw`, braking into it, checking the sweep for collisions."""

    action = "Spin"

    class Params(Behavior.Params):
        pass

    def on_run(self, goal: SpinGoal, now: float) -> BehaviorOutcome | None:
        if not math.isfinite(goal.target_yaw):
            return self.fail("UNKNOWN", f"target_yaw must be finite, got {goal.target_yaw}")
        self.prev_yaw = self.robot_pose().yaw
        self.relative_yaw = 0.0
        self.cmd_yaw = float(goal.target_yaw)
        self.check_collisions = not goal.disable_collision_checks
        self.set_time_allowance(goal.time_allowance, now)
        return None

    def on_cycle_update(self, now: float) -> BehaviorOutcome | None:
        if self.timed_out(now):
            return self.fail(
                "TIMEOUT", f"spin: time_allowance of {self.time_allowance:g} s ran out"
            )
        pose = self.robot_pose()
        self.relative_yaw += float(angle_diff(pose.yaw, self.prev_yaw))
        self.prev_yaw = pose.yaw
        self.publish_feedback(SpinFeedback(abs(self.relative_yaw)))

        remaining = abs(self.cmd_yaw) - abs(self.relative_yaw)
        if remaining < 1e-6:
            return self.succeed()

        s = self.server
        vel = math.sqrt(2.0 * s.rotational_acc_lim * remaining)
        vel = min(max(vel, s.min_rotational_vel), s.max_rotational_vel)
        w = math.copysign(vel, self.cmd_yaw)

        if self.check_collisions and self.collision_checker is not None:
            k = np.arange(max(1, int(self.cycle_frequency * s.simulate_ahead_time)))
            turn = w * k / self.cycle_frequency
            turn = turn[np.abs(turn) < remaining]  # only the rotation still to do
            poses = np.stack(
                [np.full(turn.shape, pose.x), np.full(turn.shape, pose.y), pose.yaw + turn],
                axis=1,
            )
            hit = self.collision_checker.first_collision(poses)
            if hit is not None:
                return self.fail(
                    "COLLISION_AHEAD",
                    f"spin: the footprint would hit an obstacle after turning "
                    f"{abs(turn[hit]):.2f} rad more; stopped",
                )
        self.publish_cmd(angular_z=w)
        return None
