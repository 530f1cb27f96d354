"""Importing this module registers btnav's built-in simulator plugins: sensors and drives."""

from . import ackermann_drive, diff_drive, lidar, omni_drive  # noqa: F401
