"""Importing this module registers btnav's built-in SLAM (entry point `btnav.plugins`)."""

from .cartographer import slam as cartographer_slam  # noqa: F401
from .karto import slam_toolbox  # noqa: F401
