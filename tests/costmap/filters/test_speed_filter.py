"""SpeedFilter: the limit under the robot, in % or m/s, published on change and lifted outside."""

from __future__ import annotations

from btnav.core.geometry import Pose2D
from btnav.costmap.filters import (
    KEEPOUT_FILTER,
    NO_SPEED_LIMIT,
    SPEED_FILTER_ABSOLUTE,
    SPEED_FILTER_PERCENT,
    CostmapFilterInfo,
    SpeedFilter,
    SpeedLimit,
)

from .zones import costmap_with, zone_mask

OUTSIDE, INSIDE = Pose2D(2.0, 2.0, 0.0), Pose2D(5.0, 5.0, 0.0)


def speed_filter() -> SpeedFilter:
    return SpeedFilter(
        "speed_filter", SpeedFilter.Params(filter_info_topic="speed_costmap_filter_info")
    )


def drive(info: CostmapFilterInfo, mask_value: int, *poses: Pose2D) -> list[SpeedLimit]:
    """The limits published while the robot stands at each pose in turn."""
    f = speed_filter()
    ros = costmap_with(f, info, zone_mask(mask_value))
    got: list[SpeedLimit] = []
    f.subscribe(got.append)
    for pose in poses:
        ros.update(pose, force=True)
    return got


def test_a_percentage_zone_limits_and_leaving_it_lifts_the_limit() -> None:
    info = CostmapFilterInfo(SPEED_FILTER_PERCENT, "speed_filter_mask", 100.0, -1.0)
    got = drive(info, 25, OUTSIDE, INSIDE, INSIDE, OUTSIDE)
    # only changes are published: in (75 % of full speed), then out (no limit)
    assert [(m.speed_limit, m.percentage) for m in got] == [(75.0, True), (NO_SPEED_LIMIT, True)]


def test_an_absolute_zone_limits_in_metres_per_second() -> None:
    info = CostmapFilterInfo(SPEED_FILTER_ABSOLUTE, "speed_filter_mask", 0.0, 0.01)
    got = drive(info, 30, INSIDE)
    assert len(got) == 1 and not got[0].percentage
    assert abs(got[0].speed_limit - 0.3) < 1e-6


def test_a_limit_out_of_range_is_no_limit() -> None:
    info = CostmapFilterInfo(SPEED_FILTER_PERCENT, "speed_filter_mask", 100.0, 1.0)
    f = speed_filter()
    costmap_with(f, info, zone_mask(25))
    assert f.speed_limit_at(INSIDE) == NO_SPEED_LIMIT  # 125 %: Nav2 drops it


def test_an_unknown_cell_or_a_pose_off_the_mask_keeps_the_last_limit() -> None:
    info = CostmapFilterInfo(SPEED_FILTER_PERCENT, "speed_filter_mask", 100.0, -1.0)
    f = speed_filter()
    mask = zone_mask(50)
    mask.data[:, :20] = -1  # x < 1 m: unknown
    ros = costmap_with(f, info, mask)
    ros.update(INSIDE, force=True)
    assert f.speed_limit == 50.0
    for pose in (Pose2D(0.5, 5.0, 0.0), Pose2D(-3.0, 5.0, 0.0)):  # unknown, then off the mask
        assert f.speed_limit_at(pose) is None
        ros.update(pose, force=True)
        assert f.speed_limit == 50.0


def test_a_keepout_info_is_refused() -> None:
    assert not speed_filter().set_filter_info(CostmapFilterInfo(KEEPOUT_FILTER, "mask"))
