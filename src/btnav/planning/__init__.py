"""Global planners (NavFn, ...) and path smoothers."""

from .exceptions import (
    ComputePathToPoseError,
    PlannerException,
    SmootherException,
    SmoothPathError,
)
from .global_planner import GlobalPlanner
from .smoother import Smoothed, Smoother

__all__ = [
    "ComputePathToPoseError",
    "GlobalPlanner",
    "PlannerException",
    "SmoothPathError",
    "Smoothed",
    "Smoother",
    "SmootherException",
]
