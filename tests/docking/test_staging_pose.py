"""The staging pose: `staging_x_offset` along the dock's heading, turned by `staging_yaw_offset`."""

from __future__ import annotations

import math

import pytest

from btnav.core.geometry import Pose2D
from btnav.docking.simple_charging_dock import SimpleChargingDock
from btnav.docking.simple_non_charging_dock import SimpleNonChargingDock


class Context:
    base_frame = "base_link"
    now = 3.0

    def __init__(self, robot: Pose2D) -> None:
        self.robot = robot

    def lookup(self, target: str, source: str) -> Pose2D:
        assert (target, source) == ("map", "base_link")
        return self.robot


ORIGIN = Pose2D()


def dock(cls=SimpleChargingDock, robot: Pose2D = ORIGIN, **params):
    plugin = cls("simple_charging_dock", cls.Params(**params))
    plugin.configure(Context(robot))
    return plugin


@pytest.mark.parametrize(
    ("pose", "expected"),
    [
        (Pose2D(0.0, 0.0, 0.0), (-0.7, 0.0, 0.0)),  # Nav2's default offset: in front of it
        (Pose2D(2.0, 1.0, math.pi / 2), (2.0, 0.3, math.pi / 2)),
        (Pose2D(-1.0, 3.0, math.pi), (-0.3, 3.0, math.pi)),
    ],
)
def test_the_staging_pose_is_in_front_of_the_dock_along_its_heading(pose, expected):
    staging = dock().get_staging_pose(pose, "map")
    assert staging.frame_id == "map" and staging.stamp == 3.0
    assert staging.pose.x == pytest.approx(expected[0], abs=1e-12)
    assert staging.pose.y == pytest.approx(expected[1], abs=1e-12)
    assert math.cos(staging.pose.yaw - expected[2]) == pytest.approx(1.0)


def test_offsets_move_and_turn_the_staging_pose():
    staging = dock(staging_x_offset=-1.2, staging_yaw_offset=0.5).get_staging_pose(
        Pose2D(1.0, 1.0, -math.pi / 2), "map"
    )
    assert (staging.pose.x, staging.pose.y) == pytest.approx((1.0, 2.2))
    assert staging.pose.yaw == pytest.approx(-math.pi / 2 + 0.5)


def test_without_detection_the_dock_pose_is_the_database_pose_and_docked_is_the_threshold():
    plugin = dock(robot=Pose2D(0.96, 0.0, 0.0))
    assert not plugin.is_docked()  # no dock pose yet
    plugin.get_staging_pose(Pose2D(1.0, 0.0, 0.0), "map")
    assert plugin.is_docked() and plugin.is_charging()  # 4 cm < docking_threshold 0.05
    plugin.context.robot = Pose2D(0.94, 0.0, 0.0)
    assert not plugin.is_docked() and plugin.has_stopped_charging()


def test_a_non_charging_dock_does_not_charge():
    plugin = dock(SimpleNonChargingDock)
    assert not plugin.is_charger
    with pytest.raises(RuntimeError, match="non-charging"):
        plugin.is_charging()


def test_rotate_to_dock_needs_a_backward_dock():
    from btnav.core.errors import ParamsError
    from btnav.params.schema import validate_section

    with pytest.raises(ParamsError, match="dock_direction: backward"):
        validate_section(SimpleChargingDock.Params, {"rotate_to_dock": True})
    backward = validate_section(
        SimpleChargingDock.Params, {"rotate_to_dock": True, "dock_direction": "BACKWARD"}
    )
    assert backward.dock_direction == "backward"  # Nav2 reads it in any case
