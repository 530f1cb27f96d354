"""Explore: a bt_navigator navigator whose tree explores until no reachable frontier is left.

A peer of NavigateToPose and NavigateThroughPoses (a `navigator` plugin, as a user's
custom navigator is in Nav2): its default tree is the bundled `explore`, its feedback
adds the frontiers left and the area mapped, and its result is the area mapped. Nav2's
params files do not list it, so the Python API adds it the first time it is asked to
explore (`BasicNavigator.explore`); a params file may list it like any navigator.
"""

from __future__ import annotations

from typing import Any

from ..core.error_codes import NavResult
from ..core.nav2_msgs import ExploreFeedback, ExploreGoal, ExploreResult
from ..nav.actions import GoalHandle
from ..plugins import register
from .bt_navigator import BehaviorTreeNavigator, BtNavigator, blackboard_value

#: The bundled tree an Explore goal runs unless it names another.
DEFAULT_EXPLORE_TREE = "explore"


@register("navigator", "btnav/ExploreNavigator")
class ExploreNavigator(BehaviorTreeNavigator):
    """Explore with `trees/explore.yaml` (frontiers from the stack's `explore` services)."""

    action_name = "Explore"
    goal_type = ExploreGoal
    feedback_type = ExploreFeedback

    def configure(self, bt: BtNavigator) -> None:
        super().configure(bt)
        self.default_tree = DEFAULT_EXPLORE_TREE  # (no bt_navigator key: Nav2 has no Explore)

    def _set_goal(self, goal: Any) -> None:
        """No pose: the tree's ComputeFrontiers writes `goal`."""

    def execute(self, handle: GoalHandle[Any], now: float) -> NavResult | None:
        result = super().execute(handle, now)
        if result is not None and result.succeeded:
            server = self.bt.stack.explore_server
            value = ExploreResult(server.explored_area(), len(server.blacklist))
            return NavResult.success(value)
        return result

    def _make_feedback(self, **kw: Any) -> Any:
        return ExploreFeedback(
            **kw,
            frontiers_left=int(blackboard_value("frontiers_left", 0) or 0),
            explored_area=self.bt.stack.explore_server.explored_area(),
        )
