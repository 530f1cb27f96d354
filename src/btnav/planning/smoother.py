"""The path smoother plugin base (nav2_core::Smoother, in Python spelling)."""

from __future__ import annotations

from collections.abc import Callable
from typing import NamedTuple

from ..core.messages import Path
from ..costmap.costmap_2d import Costmap2D
from ..params.schema import ParamsModel
from ..plugins import Plugin


class Smoothed(NamedTuple):
    """A smoother's answer: the path, and whether smoothing ran to convergence
    (SmoothPath's `was_completed`)."""

    path: Path
    was_completed: bool


class Smoother(Plugin):
    """Base of every `smoother` plugin: smooths a planned path on a costmap.

    `cancel_checker` is polled while smoothing; when it returns True the smoother
    raises `SmootherTimedOut` (the smoother server turns `max_smoothing_duration`
    into such a checker on sim time). A failure raises one of
    `planning.exceptions`' smoother exceptions, each carrying SmoothPath's code.
    """

    class Params(ParamsModel):
        pass

    def smooth(
        self,
        path: Path,
        costmap: Costmap2D | None = None,
        cancel_checker: Callable[[], bool] | None = None,
    ) -> Smoothed:
        """Smooth `path` (SmoothPath's `smooth`).

        Args:
            path: the planned path, in the costmap's frame.
            costmap: the costmap to keep clear of (None for a smoother that ignores it).
            cancel_checker: polled while smoothing; True means time is up.

        Returns:
            The smoothed path and whether smoothing converged.
        """
        raise NotImplementedError
