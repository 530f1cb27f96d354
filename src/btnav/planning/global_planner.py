"""The global planner plugin base (nav2_core::GlobalPlanner, in Python spelling)."""

from __future__ import annotations

from collections.abc import Callable
from typing import ClassVar

from ..core.geometry import Pose2D
from ..core.messages import Path
from ..costmap.costmap_2d import Costmap2D
from ..params.schema import ParamsModel


class GlobalPlanner:
    """Base of every `planner` plugin: plans a path on the global costmap.

    A failure raises one of `planning.exceptions` (Nav2's planner exceptions, each
    carrying ComputePathToPose's error code); the planner server turns it into a result.
    """

    class Params(ParamsModel):
        pass

    plugin_kind: ClassVar[str]
    plugin_name: ClassVar[str]

    def __init__(self, name: str, params: Params) -> None:
        self.name = name
        self.params = params

    def create_plan(
        self,
        start: Pose2D,
        goal: Pose2D,
        costmap: Costmap2D,
        cancel_checker: Callable[[], bool] | None = None,
    ) -> Path:
        raise NotImplementedError
