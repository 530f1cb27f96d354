"""Nav2's smoother_server: SmoothPath with the `smoother_plugins` on the global costmap.

Goal `SmoothPathGoal(path, smoother_id, max_smoothing_duration, check_for_collisions)`;
the result's `value` is a `planning.Smoothed(path, was_completed)`. A smoother's
exception becomes SmoothPath's error code; with `check_for_collisions` a smoothed
path through a lethal or inscribed cell is SMOOTHED_PATH_IN_COLLISION, as Nav2's
server checks it. Smoothing finishes within the cycle it starts in (sim time does not
pass during a call), so `max_smoothing_duration` never expires here.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..core.error_codes import NavResult, SmoothPathError
from ..core.nav2_msgs import SmoothPathGoal
from ..costmap.cost_values import INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE
from ..planning.exceptions import SmootherException
from ..planning.smoother import Smoothed
from .actions import ActionServer, GoalHandle
from .server_plugins import PluginServer, pick


class SmootherServer(PluginServer):
    """smoother_server: owns the smoother plugins and the `smooth_path` action."""

    kind = "smoother"

    def action_servers(self) -> list[ActionServer[Any]]:
        self.action: ActionServer[SmoothPathGoal] = ActionServer(
            "SmoothPath", "smooth_path", on_start=self._smooth
        )
        return [self.action]

    def smooth(self, goal: SmoothPathGoal) -> NavResult:
        """Smooth now and return the action's result (what the action does)."""
        smoother = pick(self.plugins, goal.smoother_id)
        if smoother is None:
            return NavResult.failure(
                SmoothPathError.INVALID_SMOOTHER,
                f"smoother id '{goal.smoother_id}' is not one of: {', '.join(self.plugins)}",
            )
        if goal.path is None or len(goal.path) == 0:
            return NavResult.failure(SmoothPathError.INVALID_PATH, "the path is empty")
        costmap = self.costmap.costmap
        try:
            out: Smoothed = smoother.smooth(goal.path, costmap, lambda: False)
        except SmootherException as exc:
            code = SmoothPathError[exc.error_code.name]
            return NavResult.failure(code, str(exc) or code.message)
        if goal.check_for_collisions:
            costs = costmap.cost_at(np.asarray(out.path.poses)[:, :2])
            hit = (costs == LETHAL_OBSTACLE) | (costs == INSCRIBED_INFLATED_OBSTACLE)
            if hit.any():
                return NavResult.failure(
                    SmoothPathError.SMOOTHED_PATH_IN_COLLISION,
                    f"the smoothed path collides at pose {int(np.flatnonzero(hit)[0])}",
                )
        return NavResult.success(out)

    def _smooth(self, handle: GoalHandle[SmoothPathGoal], now: float) -> NavResult:
        return self.smooth(handle.goal)
