"""The runtime: physics, sensors and components on sim time, the frame tree, determinism."""

from __future__ import annotations

import numpy as np
import pytest

from btnav.core.errors import PluginError
from btnav.core.geometry import Pose2D
from btnav.core.messages import Twist
from btnav.core.resources import bundled_dir
from btnav.nav import Runtime, Stage
from btnav.sim.world import World

OFFICE = bundled_dir("worlds") / "small_office.yaml"


def make_runtime(seed: int = 0) -> Runtime:
    return Runtime(World.from_file(OFFICE, seed=seed), seed=seed)


class Counter:
    def __init__(self, rate: float, log: list | None = None, name: str = "", stage=None):
        self.rate = rate
        self.stamps: list[float] = []
        self.log = log
        self.name = name
        if stage is not None:
            self.stage = stage

    def update(self, now: float) -> None:
        self.stamps.append(now)
        if self.log is not None:
            self.log.append((now, self.name))


def test_physics_sensors_and_odometry_run_at_their_rates():
    rt = make_runtime()
    scans, odoms = [], []
    rt.subscribe("scan", scans.append)
    rt.subscribe("odom", odoms.append)
    assert rt.latest_scan is not None and rt.latest_scan.stamp == 0.0  # measured at start
    rt.spin_for(1.0)
    assert rt.now == 1.0 and rt.world.time == 1.0 and rt.step_count == 100
    assert len(scans) == 10  # the office lidar runs at 10 Hz
    assert [s.stamp for s in scans] == pytest.approx(np.arange(1, 11) / 10)
    assert len(odoms) == 50  # odometry at 50 Hz
    assert rt.latest_scan is scans[-1] and rt.latest["laser"] is scans[-1]
    assert rt.latest_odom is odoms[-1] and rt.latest_odom.stamp == 1.0


@pytest.mark.parametrize(("hz", "expected"), [(20.0, 20), (30.0, 30), (1.0, 1), (250.0, 100)])
def test_components_run_at_their_rate_on_sim_time(hz, expected):
    rt = make_runtime()
    c = rt.add(Counter(hz))
    rt.spin_for(1.0)
    assert len(c.stamps) == expected
    assert c.stamps[-1] == 1.0


def test_step_order_is_by_stage_then_by_add_order():
    rt = make_runtime()
    log: list = []
    rt.add(Counter(10, log, "navigator", Stage.NAVIGATOR))
    rt.add(Counter(10, log, "server_a"))  # default stage: SERVER
    rt.add(Counter(10, log, "costmap", Stage.COSTMAP))
    rt.add(Counter(10, log, "server_b"), stage=Stage.SERVER)
    rt.add(Counter(10, log, "localizer"), stage=Stage.LOCALIZATION)
    seen_scan = []
    probe = Counter(10, None, "probe", Stage.LOCALIZATION)
    probe.update = lambda now: seen_scan.append(rt.latest_scan.stamp == now)  # type: ignore[method-assign]
    rt.add(probe)
    rt.spin_for(0.1)
    assert [name for _, name in log] == [
        "localizer",
        "costmap",
        "server_a",
        "server_b",
        "navigator",
    ]
    assert seen_scan == [True]  # this step's scan is there before components run


def test_a_component_needs_a_rate_and_an_update():
    rt = make_runtime()
    with pytest.raises(ValueError, match="no rate"):
        rt.add(object())
    with pytest.raises(ValueError, match="positive"):
        rt.add(Counter(0.0))
    rt.add(Counter(5.0), rate=2.0)
    rt.spin_for(1.0)
    assert len(rt.components[0].stamps) == 2


def test_cmd_vel_moves_the_robot_from_the_next_step():
    rt = make_runtime()
    start = rt.world.robot_pose
    rt.set_cmd_vel(Twist(linear_x=0.4))
    rt.spin_for(2.0)
    moved = rt.world.robot_pose.x - start.x
    assert 0.5 < moved < 0.81
    assert rt.cmd_vel.linear_x == 0.4


def test_run_until_stops_when_the_predicate_holds_or_at_the_timeout():
    rt = make_runtime()
    rt.set_cmd_vel(Twist(linear_x=0.3))
    assert rt.run_until(lambda: rt.world.robot_pose.x > 1.3, timeout=5.0)
    assert rt.world.robot_pose.x > 1.3 and rt.now < 5.0
    t0 = rt.now
    assert not rt.run_until(lambda: False, timeout=0.5)
    assert rt.now == pytest.approx(t0 + 0.5, abs=1e-9)
    assert rt.run_until(lambda: True, timeout=0.0)


def test_frame_tree_is_rep105_with_the_sensor_mounts():
    rt = make_runtime()
    assert set(rt.frames.frames) == {"map", "odom", "base_footprint", "base_link", "laser"}
    assert rt.frames.parent("laser") == "base_link"
    # No localiser: map -> odom stays at the start pose, where odometry started.
    assert rt.robot_pose() == Pose2D(1.0, 1.0, 0.0)


def drive(rt: Runtime, seconds: float = 4.0) -> None:
    rt.set_cmd_vel(Twist(linear_x=0.35, angular_z=0.3))
    rt.spin_for(seconds / 2)
    rt.set_cmd_vel(Twist(linear_x=0.2, angular_z=-0.4))
    rt.spin_for(seconds / 2)


def test_after_driving_odom_is_odometry_and_map_is_ground_truth():
    rt = make_runtime()
    gt = rt.use_localizer("ground_truth")
    drive(rt)
    truth = rt.world.robot_pose
    est = rt.lookup("map", "base_footprint")
    assert (est.x, est.y, est.yaw) == pytest.approx((truth.x, truth.y, truth.yaw), abs=1e-9)
    assert gt.pose.pose == truth and gt.pose.stamp == rt.now
    assert rt.frames.edge("base_footprint").transform == rt.latest_odom.pose
    odom = rt.lookup("odom", "base_footprint")
    assert tuple(odom) == pytest.approx(tuple(rt.latest_odom.pose), abs=1e-12)
    # Odometry drifts (noise is on in the office world), so map -> odom has moved off the start.
    start = Pose2D(1.0, 1.0, 0.0)
    assert rt.lookup("map", "odom").distance_to(start) > 1e-4
    laser = rt.lookup("map", "laser")
    mounted = truth @ Pose2D(0.1, 0.0, 0.0)
    assert (laser.x, laser.y) == pytest.approx((mounted.x, mounted.y), abs=1e-9)


def test_without_a_localiser_map_to_base_drifts_with_odometry():
    rt = make_runtime()
    drive(rt)
    est = rt.robot_pose()
    assert tuple(est) == pytest.approx(tuple(Pose2D(1.0, 1.0, 0.0) @ rt.latest_odom.pose))
    assert est.distance_to(rt.world.robot_pose) > 1e-4


def test_an_unknown_localiser_lists_the_known_ones():
    rt = make_runtime()
    with pytest.raises(PluginError, match="ground_truth"):
        rt.use_localizer("ground_truht")


def trajectory(seed: int) -> dict[str, np.ndarray]:
    rt = make_runtime(seed)
    rt.use_localizer("ground_truth")
    truth, odom, scans = [], [], []
    rt.subscribe("scan", lambda s: scans.append(np.array(s.ranges)))
    for k in range(300):
        if k % 50 == 0:
            rt.set_cmd_vel(Twist(linear_x=0.1 + 0.05 * (k // 50), angular_z=0.4 - 0.15 * (k // 50)))
        rt.step()
        truth.append(rt.world.robot_pose.as_array())
        odom.append(rt.latest_odom.pose.as_array())
    return {"truth": np.array(truth), "odom": np.array(odom), "scans": np.array(scans)}


def test_same_seed_same_run_bit_for_bit():
    a, b = trajectory(7), trajectory(7)
    for key in a:
        assert np.array_equal(a[key], b[key]), key
    c = trajectory(8)
    assert not np.array_equal(a["odom"], c["odom"])
    assert not np.array_equal(a["scans"], c["scans"])


# -- the profiling hook ------------------------------------------------------------------


class Listener:
    name = "listener"

    def __init__(self) -> None:
        self.scans: list = []

    def on_scan(self, scan) -> None:
        self.scans.append(scan)


def test_profile_is_off_by_default_and_a_profiled_run_is_the_same_run():
    plain, profiled = make_runtime(), make_runtime()
    assert plain.profile is None
    plain.spin_for(1.0)
    assert plain.profile is None
    profiled.spin_for(1.0)
    profiled.profile = {}
    for rt in (plain, profiled):
        rt.set_cmd_vel(Twist(linear_x=0.2, angular_z=0.3))
        rt.spin_for(1.0)
    assert profiled.world.robot_pose == plain.world.robot_pose
    assert np.array_equal(profiled.latest_scan.ranges, plain.latest_scan.ranges)


def test_profile_has_a_share_for_each_part():
    # How much of a step's wall time the parts cover is in bench/sim_speed.py.
    from btnav.nav.runtime import profile_label

    rt = make_runtime()
    counter = rt.add(Counter(20.0, name="counter"))
    listener = Listener()
    rt.subscribe("scan", listener.on_scan)
    rt.spin_for(0.5)  # warm
    rt.profile = {}
    rt.spin_for(2.0)
    spent = rt.profile
    lidar = f"Lidar/{rt.sensors[0].frame_id}"
    assert {"physics", "odometry", lidar, "Counter/counter", "Listener/listener"} <= set(spent)
    assert profile_label(counter) == "Counter/counter"
    assert profile_label(listener.on_scan) == "Listener/listener"  # a subscriber: its owner
    assert all(v >= 0.0 for v in spent.values())
    assert len(listener.scans) == 25 and len(counter.stamps) == 50
