"""The path smoother plugin base (nav2_core::Smoother, in Python spelling)."""

from __future__ import annotations

from collections.abc import Callable
from typing import ClassVar, NamedTuple

from ..core.messages import Path
from ..costmap.costmap_2d import Costmap2D
from ..params.schema import ParamsModel


class Smoothed(NamedTuple):
    """A smoother's answer: the path, and whether smoothing ran to convergence
    (SmoothPath's `was_completed`)."""

    path: Path
    was_completed: bool


class Smoother:
    """Base of every `smoother` plugin: smooths a planned path on a costmap.

    `cancel_checker` is polled while smoothing; when it returns True the smoother
    raises `SmootherTimedOut` (the smoother server turns `max_smoothing_duration`
    into such a checker on sim time). A failure raises one of
    `planning.exceptions`' smoother exceptions, each carrying SmoothPath's code.
    """

    class Params(ParamsModel):
        pass

    plugin_kind: ClassVar[str]
    plugin_name: ClassVar[str]

    def __init__(self, name: str, params: Params) -> None:
        self.name = name
        self.params = params

    def smooth(
        self,
        path: Path,
        costmap: Costmap2D | None = None,
        cancel_checker: Callable[[], bool] | None = None,
    ) -> Smoothed:
        raise NotImplementedError
