"""BinaryFilter: the state flips from default_state inside the zone and back outside."""

from __future__ import annotations

from btnav.core.geometry import Pose2D
from btnav.costmap.filters import BINARY_FILTER, BinaryFilter, CostmapFilterInfo

from .zones import costmap_with, zone_mask

OUTSIDE, INSIDE = Pose2D(2.0, 2.0, 0.0), Pose2D(5.0, 5.0, 0.0)
INFO = CostmapFilterInfo(BINARY_FILTER, "binary_filter_mask", 0.0, 1.0)


def binary(**params) -> BinaryFilter:
    return BinaryFilter(
        "binary_filter",
        BinaryFilter.Params(filter_info_topic="binary_costmap_filter_info", **params),
    )


def test_the_state_flips_in_the_zone_and_back_and_subscribers_hear_each_flip() -> None:
    f = binary()
    ros = costmap_with(f, INFO, zone_mask(100))
    heard: list[bool] = []
    f.subscribe(heard.append)
    states = []
    for pose in (OUTSIDE, INSIDE, INSIDE, OUTSIDE):
        ros.update(pose, force=True)
        states.append(f.binary_state)
    assert states == [False, True, True, False]
    assert heard == [True, False]


def test_default_state_true_flips_to_false_in_the_zone() -> None:
    f = binary(default_state=True)
    ros = costmap_with(f, INFO, zone_mask(100))
    ros.update(INSIDE, force=True)
    assert f.binary_state is False
    ros.update(OUTSIDE, force=True)
    assert f.binary_state is True


def test_flip_threshold_is_compared_with_base_plus_multiplier_times_value() -> None:
    f = binary(flip_threshold=60.0)
    ros = costmap_with(f, INFO, zone_mask(50))  # 50 is not above 60: no flip
    ros.update(INSIDE, force=True)
    assert f.binary_state is False
    f.set_filter_info(CostmapFilterInfo(BINARY_FILTER, "binary_filter_mask", 20.0, 1.0))
    f.set_mask(zone_mask(50))  # 20 + 50 = 70 > 60: flips
    ros.update(INSIDE, force=True)
    assert f.binary_state is True


def test_off_the_mask_is_the_default_state() -> None:
    f = binary()
    ros = costmap_with(f, INFO, zone_mask(100))
    ros.update(INSIDE, force=True)
    ros.update(Pose2D(-4.0, 5.0, 0.0), force=True)
    assert f.binary_state is False
