"""opennav_docking's Navigator: the docking server's trip to a staging pose, by NavigateToPose.

`start(pose, max_duration, now)` sends bt_navigator a NavigateToPose goal (with the
docking server's `navigator_bt_xml` tree, '' for bt_navigator's default); `step(now)`
polls it once per docking cycle and says whether the robot has arrived. A failed
navigation is tried once more with the time that is left, as Nav2 does; a second
failure, or running past `max_staging_time`, cancels the navigation and raises
FailedToStage.
"""

from __future__ import annotations

from typing import Any

from ..core.messages import PoseStamped
from ..core.nav2_msgs import NavigateToPoseGoal
from ..docking.exceptions import FailedToStage
from .actions import GoalHandle
from .runtime import Runtime

NAVIGATE_TO_POSE = "navigate_to_pose"


class StagingNavigator:
    def __init__(self, runtime: Runtime, behavior_tree: str = "") -> None:
        self.runtime = runtime
        self.behavior_tree = behavior_tree
        self.handle: GoalHandle[Any] | None = None
        self.pose: PoseStamped | None = None
        self.start_time = 0.0
        self.remaining = 0.0
        self.retried = False

    def start(self, pose: PoseStamped, max_duration: float, now: float) -> None:
        self.pose = pose
        self.retried = False
        self._send(max_duration, now)

    def _send(self, remaining: float, now: float) -> None:
        assert self.pose is not None
        self.start_time = now
        self.remaining = remaining
        if NAVIGATE_TO_POSE not in self.runtime.action_servers:
            self.handle = None
            return  # no server: this attempt fails at once (Nav2's send times out)
        client = self.runtime.action_client(NAVIGATE_TO_POSE)
        self.handle = client.send_goal(NavigateToPoseGoal(self.pose, self.behavior_tree))

    def step(self, now: float) -> bool:
        """True once the robot is at the staging pose; raises FailedToStage when it will not be."""
        handle = self.handle
        if handle is not None and handle.accepted:
            if now - self.start_time > self.remaining:
                self.cancel()
                raise FailedToStage("Navigation request to staging pose timed out.")
            if not handle.done:
                return False
            if handle.succeeded and handle.error_code == 0:
                self.handle = None
                return True
        if not self.retried:  # one more try with the time that is left
            self.retried = True
            self._send(self.remaining - (now - self.start_time), now)
            return False
        self.handle = None
        raise FailedToStage("Navigation request to staging pose failed.")

    def cancel(self) -> None:
        if self.handle is not None and self.handle.active:
            self.handle.cancel()
        self.handle = None
