"""The Jazzy tutorial's DWB section (issue 34) on the office tour, completed as btnav's
errors tell a user: the documented critics pasted in, the behaviours named as the tree
calls them.

Nav2 reads that section with its own defaults for what it leaves out: max_vel_theta and
max_speed_xy 0.0 (the tutorial writes ROS 1's max_rot_vel), which leave DWB no valid
velocity, so FollowPath fails on every cycle in Nav2 too. The tutorial's own limits under
Nav2's names (max_vel_theta: 0.5, max_speed_xy: 0.3) make it drive the tour.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from btnav.core.errors import BtnavWarning
from btnav.mission import Mission
from btnav.mission.runner import run_mission

from ..params.tutorial import with_completed_sections
from .missions import TOUR

#: The limits the no-motion message names, as Nav2 spells them, at the tutorial's values.
LIMITS = "      max_vel_theta: 0.5\n      max_speed_xy: 0.3\n"


def tour(params: Path, out: Path):
    with pytest.warns(BtnavWarning):  # one per key Nav2 skips (min_rot_vel, spin_dist, ...)
        mission = Mission.load(TOUR, overrides={"mission.params": str(params)})
    return run_mission(mission, out)


def test_completed_section_stops_where_nav2_stops_and_says_why(tmp_path, nav2_params_file):
    params = with_completed_sections(nav2_params_file, tmp_path / "tutorial.yaml")
    report = tour(params, tmp_path / "out")
    assert report.missed_waypoints == [0, 1, 2, 3]
    assert report.collisions == 0
    lines = report.missed_lines()
    assert len(lines) == 4
    for line in lines:
        assert "error 106 NO_VALID_CONTROL" in line
        assert "max_speed_xy and max_vel_theta are 0.0" in line and "in Nav2 too" in line


@pytest.mark.slow
def test_with_the_limits_set_the_office_tour_reaches_all_four(tmp_path, nav2_params_file):
    params = with_completed_sections(nav2_params_file, tmp_path / "tutorial.yaml", extra=LIMITS)
    report = tour(params, tmp_path / "out")
    assert report.succeeded and report.missed_waypoints == [], report.summary()
    assert report.collisions == 0, report.contacts
    assert report.recoveries == 0
