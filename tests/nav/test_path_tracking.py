"""The controller server's tracking feedback: signed cross-track and heading errors."""

from __future__ import annotations

import math

import numpy as np
import pytest

from btnav.core.geometry import Pose2D
from btnav.core.messages import Path
from btnav.nav.path_tracking import PathTracker


def l_path() -> Path:
    """4 m east, then 3 m north, every 0.1 m."""
    east = np.stack([np.arange(0, 4.0, 0.1), np.zeros(40), np.zeros(40)], axis=1)
    north = np.stack([np.full(31, 4.0), np.arange(0, 3.01, 0.1), np.full(31, math.pi / 2)], axis=1)
    return Path(0.0, np.concatenate([east, north]))


def test_left_is_positive_right_negative_and_heading_against_the_path():
    tracker = PathTracker()
    tracker.set_path(l_path())
    index, error, heading, remaining = tracker.track(Pose2D(1.05, 0.3, 0.2))
    assert index == 10 and error == pytest.approx(0.3) and heading == pytest.approx(0.2)
    assert remaining == pytest.approx(7.0 - 1.05)
    _, error, heading, _ = tracker.track(Pose2D(1.5, -0.2, -0.1))
    assert error == pytest.approx(-0.2) and heading == pytest.approx(-0.1)


def test_the_search_follows_the_robot_forward_round_the_corner():
    tracker = PathTracker(search_dist=2.0)
    tracker.set_path(l_path())
    for x in np.arange(0.0, 4.0, 0.5):  # along the first leg
        tracker.track(Pose2D(x, 0.0, 0.0))
    index, error, heading, remaining = tracker.track(Pose2D(3.9, 1.0, math.pi / 2))
    assert index >= 40 and error == pytest.approx(0.1)  # left of the northbound leg
    assert heading == pytest.approx(0.0) and remaining == pytest.approx(2.0)
