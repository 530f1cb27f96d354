"""Importing this module registers btnav's built-in planning plugins (entry point `btnav.plugins`)."""

from . import (  # noqa: F401
    navfn_planner,
    simple_smoother,
    smac_planner_2d,
    smac_planner_hybrid,
    smac_planner_lattice,
    theta_star_planner,
)
