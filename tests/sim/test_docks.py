"""Docks in a world: a body the lidar sees and a docked robot touches without a collision,
and the dock detector that reports the dock's marker when it is in view."""

from __future__ import annotations

from pathlib import Path

import pytest

from btnav.core.errors import WorldError
from btnav.core.geometry import Pose2D
from btnav.core.messages import Twist
from btnav.core.rng import stream
from btnav.sim.dock_detector import DockDetector
from btnav.sim.world import World
from btnav.sim.world_spec import WorldSpec, load_world_spec

REPO = Path(__file__).resolve().parents[2]
OFFICE_DOCK = REPO / "worlds" / "office_dock.yaml"
DOCK = (11.6, 1.0, 0.0)  # worlds/office_dock.yaml's home_dock


def world_at(pose) -> World:
    spec = load_world_spec(OFFICE_DOCK)
    spec.robot.pose = pose
    return World(spec)


def test_the_lidar_sees_the_dock_body():
    world = world_at((10.9, 1.0, 0.0))
    hit = world.geometry().segments
    # some outline edge lies on the dock's face plane x = 11.82
    assert ((abs(hit[:, 0] - 11.82) < 1e-9) & (abs(hit[:, 2] - 11.82) < 1e-9)).any()


def test_pushing_against_the_dock_is_not_a_collision():
    world = world_at((11.55, 1.0, 0.0))
    world.set_cmd_vel(Twist(linear_x=0.2))
    for _ in range(100):
        world.step(0.01)
    assert world.touching_docks == ["home_dock"]
    assert world.robot_pose.x < 11.6 + 5e-3  # the body stops it at the dock pose
    assert world.collisions == 0 and world.contacts == []


def test_a_wall_still_is_a_collision_in_a_world_with_a_dock():
    world = world_at((11.6, 1.7, 0.0))  # beside the dock, 0.13 m from the east wall's face
    world.set_cmd_vel(Twist(linear_x=0.3))
    for _ in range(100):
        world.step(0.01)
    assert world.collisions == 1 and world.contacts[0].hit == "wall"


def test_two_docks_of_one_name_are_an_error():
    text = (
        OFFICE_DOCK.read_text()
        + "  - {name: home_dock, type: simple_charging_dock, pose: [2, 2, 0]}\n"
    )
    with pytest.raises(WorldError, match="two docks are named 'home_dock'"):
        WorldSpec.from_text(text, OFFICE_DOCK)


def detector(world, **params) -> DockDetector:
    sensor = DockDetector("dock_detector", DockDetector.Params(frame="dock_camera", **params))
    sensor.configure(world, stream(0, "sensor", "dock_camera"))
    return sensor


def test_the_detector_reports_the_marker_in_its_frame():
    world = world_at((10.9, 1.0, 0.0))
    found = detector(world, noise_std=(0.0, 0.0)).measure(1.0)
    assert found.dock == "home_dock" and found.pose is not None
    assert found.pose.frame_id == "dock_camera" and found.pose.stamp == 1.0
    # the marker is the middle of the face, the robot's radius (0.22) ahead of the dock pose
    assert found.pose.position == pytest.approx((11.82 - 10.9, 0.0, 0.0))


@pytest.mark.parametrize(
    "pose",
    [
        (8.5, 1.0, 0.0),  # beyond range (3 m)
        (10.9, 1.0, 1.2),  # outside the field of view
        (11.6, 1.75, -1.5708),  # the face seen from its side (beyond max_view_angle)
    ],
)
def test_no_detection_out_of_range_view_or_angle(pose):
    assert detector(world_at(pose)).measure(0.0).pose is None


def test_the_detection_noise_comes_from_the_seeded_stream():
    world = world_at((10.9, 1.0, 0.0))
    first, second = detector(world), detector(world)
    a = [first.measure(t).pose.position for t in (0.0, 0.1)]
    b = [second.measure(t).pose.position for t in (0.0, 0.1)]
    assert a == b and a[0] != a[1]
    assert abs(a[0][0] - 0.92) < 0.03


def test_the_detector_is_a_sensor_of_the_world_file():
    world = World.from_file(OFFICE_DOCK)
    names = [name for name, _, _ in world.sensor_specs()]
    assert names == ["lidar", "dock_detector"]
    assert world.robot_pose == Pose2D(1.0, 1.0, 0.0)
