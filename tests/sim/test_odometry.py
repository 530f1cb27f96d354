"""Odometry: exact without noise, drift statistics that match the alphas at any rate."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from scipy import stats

from btnav.core.clock import Rate, SimClock
from btnav.core.geometry import Pose2D
from btnav.core.messages import Twist
from btnav.core.rng import stream
from btnav.sim.odometry import WheelOdometry, make_odometry
from btnav.sim.odometry_noise import decompose, sample_motion
from btnav.sim.world import World
from btnav.sim.world_spec import WorldSpec

DT = 0.01
ALPHAS = (0.04, 0.005, 0.03, 0.02)

FIELD = """
bounds: [[-5, -5], [10, 5]]
walls:
  - [[3, -1], [3, 1]]
robot:
  pose: [-1.0, 0.5, 0.0]
  limits: {v_max: 0.5, w_max: 1.0, a_max: 1.0, alpha_max: 2.0}
  odometry: {noise: %s, rate: %s}
"""


def make(noise: str = "[0, 0, 0, 0]", rate: float = 50) -> World:
    return World(WorldSpec.from_text(FIELD % (noise, rate), "field.yaml"))


def truth_in_odom(world: World, start: Pose2D) -> Pose2D:
    return world.robot_pose.relative_to(start)


def test_noiseless_odometry_is_the_true_motion_from_the_start_pose():
    world = make()
    start = world.robot_pose
    odom = make_odometry(world, seed=0)
    assert odom.rate == 50 and odom.pose == Pose2D()
    clock, rate = SimClock(), Rate(odom.rate)
    rate.due(clock)
    # Into the wall and pushing against it, then backing out and curving about.
    commands = [Twist(0.5, 0, 0.0)] * 1000 + [Twist(-0.2, 0, -0.5)] * 300
    commands += [Twist(0.3, 0, 0.9)] * 400 + [Twist(0.5, 0, -0.3)] * 300
    msg = None
    for cmd in commands:
        world.set_cmd_vel(cmd)
        world.step(DT)
        clock.advance(DT)
        if rate.due(clock):
            msg = odom.update(clock.now)
    assert world.collisions >= 1
    assert msg is not None and msg.stamp == pytest.approx(world.time)
    assert msg.frame_id == "odom" and msg.child_frame_id == "base_footprint"
    truth = truth_in_odom(world, start)
    assert msg.pose.x == pytest.approx(truth.x, abs=1e-9)
    assert msg.pose.y == pytest.approx(truth.y, abs=1e-9)
    assert msg.pose.yaw == pytest.approx(truth.yaw, abs=1e-9)
    assert msg.twist == world.robot_twist


def test_same_seed_same_odometry_other_seed_other_odometry():
    def trace(seed: int) -> list[tuple[float, float, float]]:
        world = make("[0.05, 0.05, 0.05, 0.05]")
        odom = make_odometry(world, seed)
        out = []
        for k in range(300):
            world.set_cmd_vel(Twist(0.4, 0, 0.5 if k > 100 else 0.0))
            world.step(DT)
            if k % 2:
                out.append(tuple(odom.update(world.time).pose))
        return out

    assert trace(3) == trace(3)
    assert trace(3) != trace(4)


def test_wheel_odometry_draws_what_sample_motion_draws():
    """The one-run fast path and the vectorised sampler are one model."""
    world = make("[0.05, 0.02, 0.04, 0.03]")
    odom = make_odometry(world, seed=5)
    rng = stream(5, "odometry")
    poses = np.zeros((1, 3))
    prev, prev_yaw = world.robot_pose, world.robot.yaw_unwrapped
    for k in range(200):
        world.set_cmd_vel(Twist(0.4, 0, 0.7 if k > 50 else -0.2))
        world.step(DT)
        msg = odom.update(world.time)
        true, yaw = world.robot_pose, world.robot.yaw_unwrapped
        local = true.relative_to(prev)
        poses = sample_motion(poses, (local.x, local.y, yaw - prev_yaw), odom.alphas, rng)
        prev, prev_yaw = true, yaw
        assert msg.pose.x == pytest.approx(poses[0, 0], abs=1e-9)
        assert msg.pose.y == pytest.approx(poses[0, 1], abs=1e-9)
        assert msg.pose.yaw == pytest.approx(Pose2D(0, 0, poses[0, 2]).yaw, abs=1e-9)


def test_decompose_reads_reversing_as_a_straight_move_not_two_half_turns():
    rot1, trans, rot2 = decompose(-0.01, 0.0005, 0.1)
    assert trans == pytest.approx(-math.hypot(0.01, 0.0005))
    assert abs(rot1) < 0.06 and rot1 + rot2 == pytest.approx(0.1)
    rot1, trans, rot2 = decompose(0.3, 0.4, 0.0)
    assert trans == pytest.approx(0.5) and rot1 == -rot2 == pytest.approx(math.atan2(0.4, 0.3))


def test_solver_jitter_is_not_read_as_a_turn():
    """A nanometre sideways (the solver settling) must not add a quarter turn of noise."""
    rng = stream(0, "t")
    out = sample_motion(np.zeros((1000, 3)), (1e-9, -1e-9, 0.0), (1.0, 0.0, 0.0, 0.0), rng)
    assert np.abs(out[:, 2]).max() < 1e-3
    out = sample_motion(np.zeros((1000, 3)), (1e-9, -1e-9, 0.25), (1.0, 0.0, 0.0, 0.0), rng)
    assert out[:, 2].var() == pytest.approx(0.25, rel=0.15)  # alpha1 * |turn|


def test_reversing_with_rotation_noise_only_from_rotation_adds_no_heading_drift():
    """alpha1 (rotation from rotation) must not fire when driving straight backwards."""
    world = make()
    odom = WheelOdometry(world, alphas=(1.0, 0.0, 0.0, 0.0), rate=50, seed=0)
    world.set_cmd_vel(Twist(-0.3, 0, 0))
    for k in range(300):
        world.step(DT)
        if k % 2:
            odom.update(world.time)
    assert odom.pose.x == pytest.approx(truth_in_odom(world, Pose2D(-1.0, 0.5, 0.0)).x, abs=1e-9)
    assert odom.pose.x < -0.8
    assert odom.pose.yaw == pytest.approx(0.0, abs=1e-6)  # a half turn per update would be ~1 rad


# -- drift statistics ----------------------------------------------------------------------

D_LINE = 2.0  # m, nominal straight line
TURN = math.pi / 2  # rad, in-place turn after it


def straight_then_turn() -> tuple[list[Pose2D], list[float], World]:
    """The true trajectory (every physics step) of a straight line then a turn in place."""
    world = make()
    poses, yaws = [world.robot_pose], [world.robot.yaw_unwrapped]

    def advance(cmd: Twist, until) -> None:
        world.set_cmd_vel(cmd)
        while not until():
            world.step(DT)
            poses.append(world.robot_pose)
            yaws.append(world.robot.yaw_unwrapped)

    start = world.robot_pose
    advance(Twist(0.5, 0, 0), lambda: world.robot_pose.distance_to(start) >= D_LINE - 0.125)
    n = len(poses)
    advance(Twist(0, 0, 0), lambda: len(poses) > n + 60)
    yaw0 = world.robot.yaw_unwrapped
    advance(Twist(0, 0, 1.0), lambda: world.robot.yaw_unwrapped - yaw0 >= TURN - 0.25)
    n = len(poses)
    advance(Twist(0, 0, 0), lambda: len(poses) > n + 60)
    return poses, yaws, world


def predicted_variances(alphas, d: float, turn: float) -> np.ndarray:
    """First-order error variances (x, y, yaw in odom) after a line of d metres then a turn.

    Line: heading error is a random walk with 2*alpha2 per metre (rot1 and rot2), so
    the cross-track error, its integral, has variance 2*alpha2*d^3/3; along-track
    alpha3*d. Turn of angle A: heading alpha1*A; the translation noise alpha4 per
    radian points along the turning heading, so it splits into x and y as cos^2, sin^2.
    """
    a1, a2, a3, a4 = alphas
    cos2 = turn / 2 + math.sin(2 * turn) / 4  # integral of cos^2 over the turn
    sin2 = turn / 2 - math.sin(2 * turn) / 4
    return np.array([a3 * d + a4 * cos2, 2 * a2 * d**3 / 3 + a4 * sin2, 2 * a2 * d + a1 * turn])


def chi2_bounds(n: int, p: float = 1e-4) -> tuple[float, float]:
    """Ratio sample-variance / true-variance stays in these bounds with probability 1 - p."""
    return (
        stats.chi2.ppf(p / 2, n - 1) / (n - 1),
        stats.chi2.ppf(1 - p / 2, n - 1) / (n - 1),
    )


def odometry_errors(poses, yaws, every: int, n: int, seed: int) -> np.ndarray:
    """Final odometry error of n runs (vectorised) updating every `every` physics steps."""
    rng = stream(seed, "odometry-test", str(every))
    odom = np.zeros((n, 3))
    marks = list(range(0, len(poses), every))
    if marks[-1] != len(poses) - 1:
        marks.append(len(poses) - 1)
    for i, j in itertools.pairwise(marks):
        p, q = poses[i], poses[j]
        c, s = math.cos(p.yaw), math.sin(p.yaw)
        dx, dy = q.x - p.x, q.y - p.y
        odom = sample_motion(
            odom, (c * dx + s * dy, -s * dx + c * dy, yaws[j] - yaws[i]), ALPHAS, rng
        )
    truth = poses[-1].relative_to(poses[0])
    err = odom - np.array([truth.x, truth.y, yaws[-1] - yaws[0]])
    return err


def test_drift_variance_matches_the_alphas_and_not_the_rate():
    """4000 runs at 10 Hz and at 100 Hz: both match the per-unit-motion prediction.

    Tolerance: the sample variance of n normal errors lies within chi2 bounds
    (p = 1e-4 two-sided, about +/-9 % for n = 4000) of the truth; the prediction is
    first order in the noise, so allow 5 % more for the neglected terms. A model
    with variance quadratic in each step's motion (AMCL's sampler) would differ 10x
    between the two rates.
    """
    poses, yaws, _ = straight_then_turn()
    start = poses[0]
    d = poses[-1].distance_to(start)
    turn = yaws[-1] - yaws[0]
    assert d == pytest.approx(D_LINE, abs=0.01) and turn == pytest.approx(TURN, abs=0.01)
    expected = predicted_variances(ALPHAS, d, turn)
    n = 4000
    lo, hi = chi2_bounds(n)
    measured = {}
    for hz in (10, 100):
        err = odometry_errors(poses, yaws, every=round(1 / (hz * DT)), n=n, seed=hz)
        measured[hz] = err.var(axis=0, ddof=1)
        ratio = measured[hz] / expected
        print(f"{hz} Hz, {n} runs: var/predicted (x, y, yaw) = {np.round(ratio, 3)}")
        assert np.all(ratio > lo - 0.05) and np.all(ratio < hi + 0.05), (hz, ratio)
    rate_ratio = measured[100] / measured[10]
    assert np.all(np.abs(rate_ratio - 1) < 0.2), rate_ratio


@pytest.mark.slow
def test_wheel_odometry_over_200_seeds_matches_the_alphas_at_10_and_100_hz():
    """The real thing: 200 seeded `WheelOdometry`s on the world, scheduled by `Rate`.

    With 200 runs the chi2 bounds (p = 1e-4) are about -35 % / +45 %; the rates'
    variances must also agree with each other within that spread.
    """
    runs = 200
    world = make()
    start = world.robot_pose
    meters = {
        hz: [WheelOdometry(world, alphas=ALPHAS, rate=hz, seed=s) for s in range(runs)]
        for hz in (10, 100)
    }
    clock = SimClock()
    rates = {hz: Rate(hz) for hz in meters}
    for r in rates.values():
        r.due(clock)

    def step(cmd: Twist, until) -> None:
        world.set_cmd_vel(cmd)
        while not until():
            world.step(DT)
            clock.advance(DT)
            for hz, r in rates.items():
                if r.due(clock):
                    for m in meters[hz]:
                        m.update(clock.now)

    step(Twist(0.5, 0, 0), lambda: world.robot_pose.distance_to(start) >= D_LINE - 0.125)
    t = world.time
    step(Twist(0, 0, 0), lambda: world.time >= t + 0.6)
    yaw0 = world.robot.yaw_unwrapped
    step(Twist(0, 0, 1.0), lambda: world.robot.yaw_unwrapped - yaw0 >= TURN - 0.25)
    t = world.time
    step(Twist(0, 0, 0), lambda: world.time >= t + 0.6)
    for ms in meters.values():  # a last update at the very end
        for m in ms:
            m.update(world.time)

    truth = truth_in_odom(world, start)
    d, turn = world.robot_pose.distance_to(start), world.robot.yaw_unwrapped - start.yaw
    expected = predicted_variances(ALPHAS, d, turn)
    lo, hi = chi2_bounds(runs)
    for hz, ms in meters.items():
        err = np.array(
            [[m.pose.x - truth.x, m.pose.y - truth.y, m.pose.yaw - truth.yaw] for m in ms]
        )
        ratio = err.var(axis=0, ddof=1) / expected
        print(f"{hz} Hz, {runs} seeds: var/predicted (x, y, yaw) = {np.round(ratio, 3)}")
        assert np.all(ratio > lo - 0.05) and np.all(ratio < hi + 0.05), (hz, ratio)
