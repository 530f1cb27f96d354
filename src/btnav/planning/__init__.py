"""Global planners (NavFn, ...) and path smoothers."""

from .exceptions import (
    ComputePathToPoseCode,
    PlannerException,
    SmootherException,
    SmoothPathCode,
)
from .global_planner import GlobalPlanner
from .smoother import Smoothed, Smoother

__all__ = [
    "ComputePathToPoseCode",
    "GlobalPlanner",
    "PlannerException",
    "SmoothPathCode",
    "Smoothed",
    "Smoother",
    "SmootherException",
]
