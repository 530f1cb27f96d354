"""What a run's report counts from the tree: recoveries and replans, over every goal.

A bt_navigator tick listener. `recoveries` adds up Nav2's `number_recoveries` of each
navigation goal (the count its RecoveryNodes keep on the blackboard, which the
navigator resets per goal); `replans` counts each new non-empty `path` on the
blackboard after the first of a goal (a failed ComputePathToPose writes an empty one).
"""

from __future__ import annotations

from typing import Any

from ..bt.nav2_context import recovery_count
from ..core.messages import Path
from ..navigators.bt_navigator import blackboard_value


class NavigationCounters:
    def __init__(self) -> None:
        self.recoveries = 0
        self.replans = 0
        self.goals = 0
        self._goal: Any = None
        self._goal_recoveries = 0
        self._path: Any = None  # the path the current goal last had
        # The blackboard's path at the last call. py_trees' blackboard is process-wide, so
        # at the start it may hold an earlier run's path: that one is not a plan of ours.
        self._seen: Any = blackboard_value("path")
        self._planned = False

    def __call__(self, navigator: Any, now: float) -> None:
        goal = navigator.current
        path = blackboard_value("path")
        if goal is not self._goal:
            self._goal = goal
            self.goals += goal is not None
            self._goal_recoveries = 0
            self._path = self._seen  # the last goal's path, still on the blackboard
            self._planned = False
        count = recovery_count()
        if count > self._goal_recoveries:
            self.recoveries += count - self._goal_recoveries
            self._goal_recoveries = count
        if isinstance(path, Path) and len(path) and path is not self._path:
            self.replans += self._planned
            self._planned = True
            self._path = path
        self._seen = path
