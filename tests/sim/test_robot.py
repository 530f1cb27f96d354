"""The diff-drive robot: limits, walls that stop it, contacts counted as collisions."""

from __future__ import annotations

import math

import numpy as np
import pytest

from btnav.core.messages import Twist
from btnav.sim.world import World
from btnav.sim.world_spec import WorldSpec

DT = 0.01

# A 0.10 m wall along x = 3 (faces at 2.95 and 3.05) and an open field otherwise.
CORRIDOR = """
bounds: [[-5, -5], [10, 5]]
walls:
  - [[3, -4], [3, 4]]
robot:
  pose: [0, 0, 0]
  footprint: %s
  limits: {v_max: 0.5, v_min: -0.2, w_max: 1.5, a_max: 1.0, alpha_max: 3.0}
"""


def make(footprint: str = "{radius: 0.2}") -> World:
    return World(WorldSpec.from_text(CORRIDOR % footprint, "corridor.yaml"))


def run(world: World, cmd: Twist, seconds: float) -> list[Twist]:
    world.set_cmd_vel(cmd)
    out = []
    for _ in range(round(seconds / DT)):
        world.step(DT)
        out.append(world.robot_twist)
    return out


def test_robot_accelerates_at_a_max_up_to_v_max():
    world = make()
    twists = run(world, Twist(2.0, 0, 0), 1.0)
    v = np.array([t.linear_x for t in twists])
    # 1.0 m/s^2 from rest: 0.01, 0.02, ... then held at v_max = 0.5.
    np.testing.assert_allclose(v[:50], np.arange(1, 51) * 0.01, atol=1e-12)
    assert np.all(v <= 0.5 + 1e-12) and v[-1] == pytest.approx(0.5)
    assert np.all(np.abs(np.diff(v)) <= 1.0 * DT + 1e-12)
    # Each step moves v_k * dt: the distance is the sum of the velocity profile.
    assert world.robot_pose.x == pytest.approx(float(np.sum(v) * DT), abs=1e-9)


def test_angular_speed_respects_alpha_max_and_w_max():
    world = make()
    twists = run(world, Twist(0, 0, -5.0), 1.0)
    w = np.array([t.angular_z for t in twists])
    assert np.all(np.abs(np.diff(w)) <= 3.0 * DT + 1e-12)
    assert w.min() == pytest.approx(-1.5) and np.all(w >= -1.5 - 1e-12)
    # Deceleration is limited too: stopping from 1.5 rad/s takes 0.5 s.
    twists = run(world, Twist(0, 0, 0), 0.6)
    w = np.array([t.angular_z for t in twists])
    assert w[0] == pytest.approx(-1.47) and w[-1] == 0.0


def test_reversing_is_limited_by_v_min():
    world = make()
    twists = run(world, Twist(-1.0, 0, 0), 1.0)
    v = np.array([t.linear_x for t in twists])
    assert v.min() == pytest.approx(-0.2) and np.all(v >= -0.2 - 1e-12)
    assert world.robot_pose.x < 0


def test_default_v_min_is_minus_v_max():
    world = World(
        WorldSpec.from_text("bounds: [[-5, -5], [5, 5]]\nrobot: {pose: [0, 0, 0]}\n", "w.yaml")
    )
    twists = run(world, Twist(-9.0, 0, 0), 2.0)
    assert twists[-1].linear_x == pytest.approx(-0.5)


def test_driving_along_a_curve_tracks_the_commanded_arc():
    world = make()
    run(world, Twist(0.4, 0, 0.8), 0.5)  # reach the command (a_max, alpha_max allow it)
    start = world.robot_pose
    run(world, Twist(0.4, 0, 0.8), math.pi / 0.8)  # half a circle of radius 0.5
    end = world.robot_pose
    assert end.distance_to(start) == pytest.approx(1.0, abs=0.01)
    assert abs(end.yaw - start.yaw) == pytest.approx(math.pi, abs=0.02)


@pytest.mark.parametrize(
    ("footprint", "reach"),
    [
        ("{radius: 0.2}", 0.2),
        ("{polygon: [[0.3, 0.2], [-0.2, 0.2], [-0.2, -0.2], [0.3, -0.2]]}", 0.3),
    ],
)
def test_robot_driven_into_a_wall_collides_and_stops_at_it(footprint, reach):
    world = make(footprint)
    run(world, Twist(0.5, 0, 0), 10.0)  # would be 5 m without the wall
    x = world.robot_pose.x
    face = 2.95
    assert world.collisions == 1 and world.in_contact
    assert face - reach - 0.01 < x < face - reach + 0.005  # at the wall, not through it
    assert abs(world.robot_pose.y) < 1e-6 and abs(world.robot_pose.yaw) < 1e-6
    assert abs(world.robot_twist.linear_x) < 0.02  # stalled against it

    # Backing off ends the contact; driving in again is a second collision.
    run(world, Twist(-0.2, 0, 0), 1.5)
    assert not world.in_contact and world.collisions == 1
    run(world, Twist(0.5, 0, 0), 3.0)
    assert world.collisions == 2 and world.in_contact


def test_a_concave_footprint_is_solid_where_drawn():
    """A U-shaped robot (opening forward) drives around a thin post that enters its slot."""
    u_shape = "{polygon: [[0.4, 0.3], [-0.2, 0.3], [-0.2, -0.3], [0.4, -0.3], [0.4, -0.1], [0.0, -0.1], [0.0, 0.1], [0.4, 0.1]]}"
    text = f"""
bounds: [[-2, -2], [4, 2]]
obstacles:
  - circle: {{center: [1.0, 0.0], radius: 0.05}}
robot: {{pose: [0, 0, 0], footprint: {u_shape}}}
"""
    world = World(WorldSpec.from_text(text, "u.yaml"))
    run(world, Twist(0.5, 0, 0), 3.0)
    # The post passes into the slot and stops at its bottom (x = 0.0 in the robot frame).
    assert world.robot_pose.x == pytest.approx(1.0 - 0.05, abs=0.01)
    assert world.collisions == 1


def test_spinning_in_place_next_to_a_wall_is_not_a_collision():
    world = make()
    world.robot.body.position = (2.70, 0.0)  # 5 cm from the wall face
    run(world, Twist(0, 0, 1.5), 3.0)
    assert world.collisions == 0
