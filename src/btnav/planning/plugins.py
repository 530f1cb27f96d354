"""Importing this module registers btnav's built-in planning plugins (entry point `btnav.plugins`)."""

from . import navfn_planner, simple_smoother, smac_planner_hybrid  # noqa: F401
