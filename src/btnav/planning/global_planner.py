"""The global planner plugin base (nav2_core::GlobalPlanner, in Python spelling)."""

from __future__ import annotations

from collections.abc import Callable

from ..core.geometry import Pose2D
from ..core.messages import Path
from ..costmap.costmap_2d import Costmap2D
from ..params.schema import ParamsModel
from ..plugins import Plugin


class GlobalPlanner(Plugin):
    """Base of every `planner` plugin: plans a path on the global costmap.

    A failure raises one of `planning.exceptions` (Nav2's planner exceptions, each
    carrying ComputePathToPose's error code); the planner server turns it into a result.
    """

    class Params(ParamsModel):
        pass

    def create_plan(
        self,
        start: Pose2D,
        goal: Pose2D,
        costmap: Costmap2D,
        cancel_checker: Callable[[], bool] | None = None,
    ) -> Path:
        """Plan from `start` to `goal` (ComputePathToPose's `createPlan`).

        Args:
            start: the robot, in the costmap's frame.
            goal: the goal, in the costmap's frame.
            costmap: the global costmap, read only.
            cancel_checker: polled in long searches; True means the goal was cancelled
                or `max_planning_time` ran out (raise `PlannerCancelled`/`PlannerTimedOut`).

        Returns:
            The path, start first and the goal last, in the costmap's frame. A failure
            raises one of `planning.exceptions` (`NoValidPathCouldBeFound`,
            `GoalOccupied`, ...), never an empty path.
        """
        raise NotImplementedError
