"""Recorded 2D laser logs for offline SLAM: CARMEN logs and ROS 1 / ROS 2 bags."""

from .recorded_log import LogError, RecordedLog, log_kind, read_log

__all__ = ["LogError", "RecordedLog", "log_kind", "read_log"]
