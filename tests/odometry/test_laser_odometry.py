"""Laser odometry (rf2o's role): a robot without wheels publishes `odom` from its scans.

The acceptance test of the issue: over the same route through the small office, laser
odometry alone drifts less than the wheel odometry with the world's noise. The robot is
steered on ground truth (as loop_drive does), so both runs drive the very same route.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

from btnav.core.errors import WorldError
from btnav.core.frames import BASE_FOOTPRINT, ODOM
from btnav.core.geometry import Pose2D, angle_diff
from btnav.core.messages import LaserScan, Twist
from btnav.nav.runtime import Runtime
from btnav.odometry.laser_odometry import LaserOdometry, OdometryWithCovariance
from btnav.sim.world import World
from btnav.sim.world_spec import load_world_spec

from ..slam.loop_drive import REPO, _dense

OFFICE = REPO / "worlds" / "small_office.yaml"
#: Through the left room, the doorway, round the lower right room and back (about 21 m).
ROUTE = [
    (1.0, 1.0), (3.0, 1.0), (3.0, 3.5), (5.5, 3.5), (6.5, 2.4), (8.8, 2.4), (8.8, 1.0),
    (6.5, 2.4), (5.5, 3.5), (3.0, 3.5), (3.0, 1.0), (1.2, 1.0),
]  # fmt: skip


def office_world(tmp: Path, odometry: str) -> Path:
    """The small office with its robot's `odometry:` block's opening rewritten."""
    text = OFFICE.read_text()
    assert "odometry: {noise" in text
    path = tmp / f"office_{odometry.split(': ')[-1]}.yaml"
    path.write_text(text.replace("odometry: {noise", f"odometry: {{{odometry}, noise"))
    return path


@dataclass
class Run:
    runtime: Runtime
    stamps: np.ndarray  # (K,) times of the odometry the run kept (every scan's)
    truth: np.ndarray  # (K, 3) ground truth at those times
    odom: np.ndarray  # (K, 3) odom -> base_footprint, placed at the start pose
    twist: np.ndarray  # (K, 3) the odometry's twist
    true_twist: np.ndarray  # (K, 3) the body's

    def position_errors(self) -> np.ndarray:
        return np.hypot(self.odom[:, 0] - self.truth[:, 0], self.odom[:, 1] - self.truth[:, 1])


def drive(world: Path, route: list[tuple[float, float]] = ROUTE, seed: int = 0) -> Run:
    """Pure pursuit on the true pose; the odometry sampled at every scan (10 Hz)."""
    w = World.from_file(world, seed=seed)
    rt = Runtime(w, seed=seed)
    start = w.robot_pose
    path = _dense(route)
    rows: list[tuple[float, ...]] = []
    i = 0
    while i < len(path) - 2:
        p = w.robot_pose
        i += int(np.argmin(np.hypot(path[i : i + 60, 0] - p.x, path[i : i + 60, 1] - p.y)))
        tx, ty = path[min(i + 16, len(path) - 1)]
        a = angle_diff(math.atan2(ty - p.y, tx - p.x), p.yaw)
        rt.set_cmd_vel(
            Twist(linear_x=0.4 if abs(a) < 0.6 else 0.05, angular_z=max(-1.2, min(1.2, 2 * a)))
        )
        for _ in range(5):
            rt.step()
            if round(rt.now * 1e9) % 100_000_000 == 0:  # a scan's time
                odom = rt.latest_odom
                est = start @ rt.lookup(ODOM, BASE_FOOTPRINT)
                t, v = w.robot_pose, w.robot_twist
                u = odom.twist
                rows.append(
                    (rt.now, *t.as_array(), *est.as_array(), u.linear_x, u.linear_y,
                     u.angular_z, v.linear_x, v.linear_y, v.angular_z)
                )  # fmt: skip
    a = np.array(rows)
    return Run(rt, a[:, 0], a[:, 1:4], a[:, 4:7], a[:, 7:10], a[:, 10:13])


@pytest.fixture(scope="module")
def runs(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Run]:
    tmp = tmp_path_factory.mktemp("laser_odometry")
    return {
        "wheels": drive(OFFICE),
        "laser": drive(office_world(tmp, "source: laser")),
    }


# -- the acceptance test -------------------------------------------------------------


def test_laser_odometry_alone_drifts_less_than_the_wheels(runs: dict[str, Run]) -> None:
    wheels, laser = runs["wheels"], runs["laser"]
    # the same route: steering on ground truth makes the two runs drive alike
    np.testing.assert_array_equal(wheels.truth, laser.truth)
    assert np.hypot(*np.diff(laser.truth[:, :2], axis=0).T).sum() > 18.0

    e_wheels, e_laser = wheels.position_errors(), laser.position_errors()
    rms_wheels = float(np.sqrt((e_wheels**2).mean()))
    rms_laser = float(np.sqrt((e_laser**2).mean()))
    # wheels: ~0.40 m final, 0.25 m RMS; laser: under 2 cm all the way
    assert e_laser[-1] < 0.05 and rms_laser < 0.03
    assert e_laser[-1] < e_wheels[-1] / 4 and rms_laser < rms_wheels / 4
    yaw_laser = np.abs(angle_diff(laser.odom[:, 2], laser.truth[:, 2]))
    assert yaw_laser.max() < 0.01


def test_laser_odometry_is_what_the_runtime_publishes(runs: dict[str, Run]) -> None:
    rt = runs["laser"].runtime
    assert isinstance(rt.odometry, LaserOdometry)
    odom = rt.latest_odom
    assert isinstance(odom, OdometryWithCovariance)
    assert odom is rt.odometry.last and odom is rt.latest["odom"]
    tf = rt.lookup(ODOM, BASE_FOOTPRINT)
    assert tf.as_array() == pytest.approx(odom.pose.as_array(), abs=1e-12)
    # one estimate per scan, stamped with the scan
    assert rt.latest_scan is not None and odom.stamp == rt.latest_scan.stamp
    # the pose covariance grows with the distance driven but stays small
    cov = odom.pose_covariance
    assert np.allclose(cov, cov.T) and (np.diag(cov) > 0).all()
    assert math.sqrt(cov[0, 0] + cov[1, 1]) < 1.0


def test_the_twist_is_sane(runs: dict[str, Run]) -> None:
    run = runs["laser"]
    est, true = run.twist[5:], run.true_twist[5:]
    # the body's velocity over the last scan interval, so it lags a little in turns
    assert np.abs(est[:, 0] - true[:, 0]).mean() < 0.02
    assert np.abs(est[:, 2] - true[:, 2]).mean() < 0.05
    assert np.abs(est[:, 0]).max() < 0.6 and np.abs(est[:, 2]).max() < 1.6
    assert np.abs(est[:, 1]).max() < 0.08  # a diff drive does not slide sideways
    cruising = true[:, 0] > 0.35
    assert cruising.sum() > 100 and (est[cruising, 0] > 0.3).all()


def test_same_seed_same_bits(tmp_path: Path) -> None:
    world = office_world(tmp_path, "source: laser")
    route = ROUTE[:4]
    a, b = drive(world, route, seed=3), drive(world, route, seed=3)
    assert a.odom.tobytes() == b.odom.tobytes()
    assert a.twist.tobytes() == b.twist.tobytes()
    assert len(a.odom) > 50


# -- standing still, seeing nothing ------------------------------------------------------


def test_standing_still_does_not_drift(tmp_path: Path) -> None:
    w = World.from_file(office_world(tmp_path, "source: laser"))
    rt = Runtime(w)
    rt.spin_for(5.0)
    pose = rt.latest_odom.pose
    assert rt.latest_odom.stamp == pytest.approx(5.0)
    assert math.hypot(pose.x, pose.y) < 0.002 and abs(pose.yaw) < 0.002
    assert rt.odometry.keyframes == 1  # every scan matched to the first


def blank_scan(stamp: float) -> LaserScan:
    n = 360
    inc = 2 * math.pi / n
    ranges = np.full(n, np.inf, np.float32)
    return LaserScan(stamp, "laser", -math.pi, -math.pi + inc * (n - 1), inc, 0.12, 8.0, ranges)


def test_a_blank_scan_coasts_on_the_last_velocity() -> None:
    lo = LaserOdometry(Pose2D(0.1, 0.0, 0.0))
    lo.scan_received(blank_scan(0.0))
    lo._velocity = (0.5, 0.0, 0.2)  # as if the last match had said so
    lo._stamp = 0.0
    odom = lo.scan_received(blank_scan(0.1))
    assert lo.response == 0.0
    assert odom.pose.x == pytest.approx(0.05, abs=1e-3)
    assert odom.pose.yaw == pytest.approx(0.02)
    assert odom.twist.linear_x == pytest.approx(0.5, abs=1e-6)


# -- the world file ------------------------------------------------------------------------


def test_a_misspelt_source_names_the_line_and_laser(tmp_path: Path) -> None:
    world = office_world(tmp_path, "source: lazer")
    line = next(n for n, text in enumerate(world.read_text().splitlines(), 1) if "lazer" in text)
    with pytest.raises(WorldError) as err:
        load_world_spec(world)
    assert err.value.line == line and err.value.file == str(world)
    assert "odometry.source" in str(err.value) and "'laser'" in str(err.value)


def test_the_default_source_is_wheels() -> None:
    assert load_world_spec(OFFICE).robot.odometry.source == "wheels"


def test_laser_odometry_needs_a_lidar(tmp_path: Path) -> None:
    text = office_world(tmp_path, "source: laser").read_text()
    cut = text.index("  sensors:")
    world = tmp_path / "blind.yaml"
    world.write_text(text[:cut])
    with pytest.raises(WorldError, match="needs a lidar") as err:
        Runtime(World.from_file(world))
    assert err.value.line is not None and "odometry.source" in str(err.value)
