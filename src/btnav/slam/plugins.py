"""Importing this module registers btnav's built-in SLAM (entry point `btnav.plugins`)."""

from . import (
    cartographer_slam,  # noqa: F401
    slam_toolbox,  # noqa: F401
)
