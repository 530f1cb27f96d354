"""Nav2's error codes (nav2_msgs/action/*.action) and the result type."""

from __future__ import annotations

import pytest

from btnav.core.error_codes import (
    BackUpError,
    ComputePathThroughPosesError,
    ComputePathToPoseError,
    DriveOnHeadingError,
    FollowPathError,
    FollowWaypointsError,
    NavigateThroughPosesError,
    NavigateToPoseError,
    SmoothPathError,
    SpinError,
    WaitError,
    error_name,
)
from btnav.core.errors import UnknownNameError
from btnav.nav import ERROR_CODES, NavResult, Outcome, error_codes, error_message


def test_every_action_btnav_serves_has_a_table():
    assert set(ERROR_CODES) == {
        "ComputePathToPose",
        "ComputePathThroughPoses",
        "FollowPath",
        "SmoothPath",
        "Spin",
        "BackUp",
        "DriveOnHeading",
        "Wait",
        "NavigateToPose",
        "NavigateThroughPoses",
        "FollowWaypoints",
        "Explore",
        "Drive",
        "AssistedTeleop",
        "ComputeRoute",
        "ComputeAndTrackRoute",
        "DockRobot",
        "UndockRobot",
    }
    for table in ERROR_CODES.values():
        assert table.NONE == 0
        assert "UNKNOWN" in table.__members__
        for code in table:
            if code:
                assert code.message, (table, code)


@pytest.mark.parametrize(
    ("code", "value"),
    [
        (ComputePathToPoseError.NO_VALID_PATH, 208),
        (ComputePathToPoseError.START_OCCUPIED, 205),
        (ComputePathToPoseError.GOAL_OCCUPIED, 206),
        (ComputePathToPoseError.GOAL_OUTSIDE_MAP, 204),
        (ComputePathToPoseError.TIMEOUT, 207),
        (ComputePathThroughPosesError.NO_VIAPOINTS_GIVEN, 309),
        (FollowPathError.FAILED_TO_MAKE_PROGRESS, 105),
        (FollowPathError.PATIENCE_EXCEEDED, 104),
        (FollowPathError.NO_VALID_CONTROL, 106),
        (SmoothPathError.SMOOTHED_PATH_IN_COLLISION, 503),
        (SpinError.COLLISION_AHEAD, 703),
        (BackUpError.COLLISION_AHEAD, 714),
        (BackUpError.INVALID_INPUT, 713),
        (DriveOnHeadingError.COLLISION_AHEAD, 723),
        (WaitError.TIMEOUT, 741),
        (FollowWaypointsError.STOP_ON_MISSED_WAYPOINT, 603),
        (NavigateToPoseError.FAILED_TO_LOAD_BEHAVIOR_TREE, 9001),
        (NavigateThroughPosesError.TIMEOUT, 9103),
        (ComputePathToPoseError.GOAL_REJECTED, 1),
    ],
)
def test_codes_are_nav2s(code, value):
    assert code == value


def test_lookup_by_action_name():
    assert error_codes("FollowPath") is FollowPathError
    assert error_name("ComputePathToPose", 208) == "NO_VALID_PATH"
    assert error_name("ComputePathToPose", 999) == "999"
    assert "progress" in error_message("FollowPath", 105)
    assert error_message("Spin", 0) == ""
    with pytest.raises(UnknownNameError, match="FollowPath"):
        error_codes("FolowPath")


def test_nav_result():
    ok = NavResult.success(value=[1, 2])
    assert ok.succeeded and ok.error_code == 0 and ok.value == [1, 2] and str(ok) == "succeeded"
    bad = NavResult.failure(ComputePathToPoseError.NO_VALID_PATH)
    assert bad.failed and bad.outcome is Outcome.FAILED and bad.error_code == 208
    assert bad.error_msg == ComputePathToPoseError.NO_VALID_PATH.message
    assert type(bad.error_code) is int
    assert str(bad).startswith("failed (208)")
    custom = NavResult.failure(FollowPathError.INVALID_PATH, "path has 0 poses")
    assert custom.error_msg == "path has 0 poses"
    assert NavResult.cancellation().canceled
