"""Wait: do nothing for a while of sim time (nav2_behaviors::Wait)."""

from __future__ import annotations

import math

from ..core.nav2_msgs import WaitFeedback, WaitGoal
from ..plugins import register
from .behavior import Behavior, BehaviorOutcome


@register("behavior", "nav2_behaviors::Wait", aliases=["btnav/Wait"])
class Wait(Behavior):
    """Succeed once `time` seconds of sim time have passed (checked each cycle)."""

    action = "Wait"

    def on_run(self, goal: WaitGoal, now: float) -> BehaviorOutcome | None:
        if not math.isfinite(goal.time):
            return self.fail("UNKNOWN", f"wait time must be finite, got {goal.time}")
        self.wait_end = now + float(goal.time)
        return None

    def on_cycle_update(self, now: float) -> BehaviorOutcome | None:
        left = self.wait_end - now
        if left > 1e-9:
            self.publish_feedback(WaitFeedback(left))
            return None
        self.publish_feedback(WaitFeedback(0.0))
        return self.succeed()

    def _end(self, outcome: BehaviorOutcome) -> BehaviorOutcome:
        # Waiting sends no velocity, so it has none to stop, except on cancel (as Nav2).
        if outcome.status == "canceled":
            self.stop_robot()
        self.on_action_completion()
        return outcome
