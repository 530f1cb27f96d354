"""Importing this module registers btnav's built-in SLAM (entry point `btnav.plugins`)."""

from . import slam_toolbox  # noqa: F401
