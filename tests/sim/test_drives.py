"""Drive plugins: a car never turns tighter than its steering allows, an omni base strafes,
a diff drive cannot, and a world names its drive (misspelt: file, line, right name)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from btnav import plugins
from btnav.core.errors import BtnavError
from btnav.core.messages import Twist
from btnav.sim.odometry import WheelOdometry
from btnav.sim.world import World
from btnav.sim.world_spec import WorldSpec

DT = 0.01

FIELD = """
bounds: [[-10, -10], [10, 10]]
walls:
  - [[9, -9], [9, 9]]
robot:
  pose: [0, 0, 0]
  drive: %s
  footprint: {polygon: [[-0.1, -0.15], [0.45, -0.15], [0.45, 0.15], [-0.1, 0.15]]}
  limits: {v_max: 1.0, v_min: -0.5, w_max: 1.5, a_max: 2.0, alpha_max: 3.0}
  odometry: {noise: %s}
"""

CAR = "{ackermann: {wheelbase: 0.33, max_steering_angle: 0.35, max_steering_speed: 2.0}}"
R_MIN = 0.33 / math.tan(0.35)


def make(drive: str, noise: str = "[0, 0, 0, 0]") -> World:
    return World(WorldSpec.from_text(FIELD % (drive, noise), "field.yaml"))


def drive_for(world: World, cmd: Twist, seconds: float) -> np.ndarray:
    """Ground-truth poses after each step of driving `cmd`."""
    world.set_cmd_vel(cmd)
    poses = []
    for _ in range(round(seconds / DT)):
        world.step(DT)
        p = world.robot_pose
        poses.append((p.x, p.y, world.robot.yaw_unwrapped))
    return np.array(poses)


def curvature(poses: np.ndarray) -> np.ndarray:
    """|dyaw / ds| between ground-truth samples that moved."""
    ds = np.hypot(*np.diff(poses[:, :2], axis=0).T)
    dyaw = np.diff(poses[:, 2])
    moved = ds > 1e-6
    return np.abs(dyaw[moved] / ds[moved])


def test_the_built_in_drives_are_registered_plugins():
    assert {"diff_drive", "ackermann", "omni"} <= set(plugins.names("drive"))


@pytest.mark.parametrize("w", [0.4, 3.0, -50.0])
def test_a_car_never_curves_tighter_than_its_minimum_turning_radius(w):
    world = make(CAR)
    poses = drive_for(world, Twist(0.6, 0.0, w), 8.0)
    assert world.collisions == 0
    k = curvature(poses)
    assert k.max() <= 1.0 / R_MIN + 1e-9
    if abs(w) > 0.6 / R_MIN:  # asked for more than it can: it drives its tightest circle
        assert k[-100:].min() == pytest.approx(1.0 / R_MIN, rel=1e-6)
    else:  # a curvature it can follow is followed: w / v
        assert k[-100:] == pytest.approx(abs(w) / 0.6, rel=1e-6)


def test_a_car_cannot_turn_in_place():
    world = make(CAR)
    poses = drive_for(world, Twist(0.0, 0.0, 1.0), 2.0)
    assert np.abs(poses[-1]).max() < 1e-12


def test_the_steering_turns_at_its_rate_limit():
    world = make(CAR)
    world.set_cmd_vel(Twist(0.5, 0.0, 10.0))
    angles = []
    for _ in range(30):
        world.step(DT)
        angles.append(world.robot.drive.steering)
    assert np.diff([0.0, *angles]).max() <= 2.0 * DT + 1e-12
    assert angles[-1] == pytest.approx(0.35)


def test_a_car_reverses_along_the_arc_its_command_asks_for():
    world = make(CAR)
    poses = drive_for(world, Twist(-0.4, 0.0, 0.4), 5.0)  # backwards, turning left (yaw up)
    assert poses[-1, 0] < -0.5 and poses[-1, 2] > 1.5
    assert curvature(poses).max() <= 1.0 / R_MIN + 1e-9
    twist = world.robot_twist
    assert twist.linear_x == pytest.approx(-0.4) and twist.angular_z == pytest.approx(0.4)


def test_an_omni_base_strafes_and_a_diff_drive_does_not():
    omni = make("omni")
    poses = drive_for(omni, Twist(0.0, 0.3, 0.0), 3.0)
    # 2 m/s^2 from rest: 0.02, 0.04, ... 0.3 m/s in 15 steps, then 285 steps at 0.3.
    assert poses[-1, 1] == pytest.approx(DT * (0.02 * sum(range(1, 16)) + 285 * 0.3), abs=1e-9)
    assert abs(poses[-1, 0]) < 1e-12 and abs(poses[-1, 2]) < 1e-12
    assert omni.robot_twist.linear_y == pytest.approx(0.3)
    diff = make("diff_drive")
    poses = drive_for(diff, Twist(0.0, 0.3, 0.0), 3.0)
    assert np.abs(poses[-1]).max() < 1e-12


def test_an_omni_base_strafes_while_it_turns():
    world = make("omni")
    poses = drive_for(world, Twist(0.0, 0.3, 0.5), 4.0)
    # Sideways in the robot frame while turning: the track curves, the speed stays 0.3.
    speeds = np.hypot(*np.diff(poses[-100:, :2], axis=0).T) / DT
    assert speeds == pytest.approx(0.3, rel=1e-3)
    assert world.robot_twist.linear_y == pytest.approx(0.3)


def test_omni_odometry_drifts_across_a_strafe_by_alpha5():
    # Only alpha5 (strafe noise per metre): driving 2 m sideways spreads the odometry
    # across the motion, variance alpha5 * 2 m, and not along it.
    finals = []
    for seed in range(200):
        world = make("omni", "[0, 0, 0, 0, 0.01]")
        odom = WheelOdometry(world, rate=50.0, rng=np.random.default_rng(seed))
        world.set_cmd_vel(Twist(0.0, 0.5, 0.0))
        for k in range(1, 451):
            world.step(DT)
            if k % 2 == 0:
                odom.update(world.time)
        truth = world.robot_pose
        finals.append((odom.pose.x - truth.x, odom.pose.y - truth.y))
    err = np.array(finals)
    travelled = truth.y
    assert np.var(err[:, 0]) == pytest.approx(0.01 * travelled, rel=0.25)  # across: x
    assert np.var(err[:, 1]) < 1e-12  # along the strafe: exact


def test_a_misspelt_drive_names_the_line_and_the_right_name():
    with pytest.raises(BtnavError) as info:
        make("ackerman")
    assert info.value.line == FIELD.splitlines().index("  drive: %s") + 1
    assert "field.yaml" in str(info.value) and "'ackermann'" in str(info.value)


def test_a_drive_param_misspelt_names_the_right_spelling():
    with pytest.raises(BtnavError) as info:
        make("{ackermann: {wheel_base: 0.3}}")
    assert "robot.drive.ackermann" in str(info.value.key) and "wheelbase" in str(info.value)
