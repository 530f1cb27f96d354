"""Every contact is a record a user can act on: when, where the robot was, what it hit."""

from __future__ import annotations

import pytest

from btnav.core.messages import Twist
from btnav.sim.world import World
from btnav.sim.world_spec import WorldSpec

WORLD = """\
world: crash_test
bounds: [[0, 0], [10, 4]]
walls:
  - [[0, 0], [10, 0], [10, 4], [0, 4], [0, 0]]
obstacles:
  - circle: {center: [1.0, 3.2], radius: 0.2}
  - box: {center: [4.0, 2.0], size: [0.4, 1.0]}
  - polygon: {points: [[7, 3], [8, 3], [7.5, 3.6]]}
robot: {pose: [1.0, 2.0, 0.0], footprint: {radius: 0.2}}
"""


def drive(world: World, cmd: Twist, seconds: float) -> None:
    world.set_cmd_vel(cmd)
    for _ in range(round(seconds / 0.01)):
        world.step(0.01)


def line_of(text: str, needle: str) -> int:
    return next(n for n, line in enumerate(text.splitlines(), 1) if needle in line)


def test_driving_into_a_box_records_the_box_its_line_and_the_pose():
    world = World(WorldSpec.from_text(WORLD, "crash_test.yaml"))
    drive(world, Twist(0.5, 0.0, 0.0), 10.0)  # the box's face is at x = 3.8
    assert world.collisions == 1
    [contact] = world.contacts
    assert (contact.hit, contact.index, contact.kind) == ("obstacle", 1, "box")
    assert contact.line == line_of(WORLD, "- box:")
    assert contact.label == "obstacles[1] (box)"
    # It began when the footprint reached the face: 0.5 s ramping up to 0.5 m/s (0.125 m),
    # then the rest of the 2.6 m at 0.5 m/s.
    assert contact.pose.x == pytest.approx(3.8 - 0.2, abs=0.01)
    assert contact.pose.y == pytest.approx(2.0, abs=1e-6)
    assert contact.time == pytest.approx(0.5 + (2.6 - 0.125) / 0.5, abs=0.02)
    assert contact.to_dict() == {
        "time": contact.time,
        "pose": [contact.pose.x, contact.pose.y, contact.pose.yaw],
        "hit": "obstacle",
        "index": 1,
        "kind": "box",
        "line": contact.line,
    }


def test_a_wall_and_then_an_obstacle_are_two_records_in_order():
    world = World(WorldSpec.from_text(WORLD, "crash_test.yaml"))
    drive(world, Twist(0.5, 0.0, 0.0), 10.0)  # into the box
    drive(world, Twist(-0.5, 0.0, 0.0), 10.0)  # backwards into the left wall
    assert world.collisions == len(world.contacts) == 2
    box, wall = world.contacts
    assert box.hit == "obstacle" and wall.hit == "wall"
    assert (wall.index, wall.kind, wall.line) == (0, "polyline", line_of(WORLD, "  - [[0, 0]"))
    assert wall.label == "walls[0]"
    assert box.time < wall.time <= world.time
    assert wall.pose.x == pytest.approx(0.05 + 0.2, abs=0.01)


def test_a_world_without_a_file_still_names_what_was_hit():
    spec = WorldSpec.model_validate(
        {
            "bounds": [[0, 0], [6, 4]],
            "obstacles": [{"circle": {"center": [3.0, 2.0], "radius": 0.3}}],
            "robot": {"pose": [1.0, 2.0, 0.0]},
        }
    )
    world = World(spec)
    drive(world, Twist(0.5, 0.0, 0.0), 8.0)
    [contact] = world.contacts
    assert contact.label == "obstacles[0] (circle)" and contact.line is None
