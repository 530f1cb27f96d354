"""`outputs: [bag]` records the run as a ROS 2 bag (MCAP) that rosbags reads back."""

from __future__ import annotations

import json
import math
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest

pytest.importorskip("rosbags")
from rosbags.highlevel import AnyReader
from rosbags.interfaces import QosDurability, QosReliability
from rosbags.typesys import Stores, get_typestore

from btnav.core.errors import BtnavError
from btnav.mission import Mission, RunOutput, run_mission
from btnav.plugins import register, unregister
from btnav.viz.rosbag_output import BAG_DIR

from ..mission.missions import TOUR

GOAL = [2.2, 1.3, 0.0]  # a short drive from the tour's start (1, 1), with AMCL
LIDAR_HZ, ODOM_HZ, CONTROLLER_HZ = 10, 50, 20  # the small office's lidar and odometry; Nav2's
TOPICS = {
    "/scan": "sensor_msgs/msg/LaserScan",
    "/odom": "nav_msgs/msg/Odometry",
    "/tf": "tf2_msgs/msg/TFMessage",
    "/tf_static": "tf2_msgs/msg/TFMessage",
    "/map": "nav_msgs/msg/OccupancyGrid",
    "/plan": "nav_msgs/msg/Path",
    "/cmd_vel": "geometry_msgs/msg/Twist",
    "/amcl_pose": "geometry_msgs/msg/PoseWithCovarianceStamped",
    "/behavior_tree_log": "nav2_msgs/msg/BehaviorTreeLog",
}


@dataclass
class Bag:
    types: dict[str, str]
    qos: dict[str, Any]
    times: list[int]  # every record's time, in file order
    msgs: dict[str, list[tuple[int, Any]]]  # topic -> (record time, message)

    def count(self, topic: str) -> int:
        return len(self.msgs.get(topic, []))


def read_bag(path: Path) -> Bag:
    with AnyReader([path], default_typestore=get_typestore(Stores.ROS2_JAZZY)) as reader:
        types = {c.topic: c.msgtype for c in reader.connections}
        qos = {c.topic: c.ext.offered_qos_profiles[0] for c in reader.connections}
        times: list[int] = []
        msgs: dict[str, list[tuple[int, Any]]] = {}
        for conn, t, raw in reader.messages():
            times.append(t)
            msgs.setdefault(conn.topic, []).append((t, reader.deserialize(raw, conn.msgtype)))
    return Bag(types, qos, times, msgs)


def ns(stamp: Any) -> int:
    return stamp.sec * 1_000_000_000 + stamp.nanosec


def bt_events(bag: Bag) -> list[tuple[int, str, int, str, str]]:
    """Every status change in /behavior_tree_log, as bt_log.jsonl lists them."""
    return [
        (ns(e.timestamp), e.node_name, e.uid, e.previous_status, e.current_status)
        for _, msg in bag.msgs["/behavior_tree_log"]
        for e in msg.event_log
    ]


def yaw(q: Any) -> float:
    return 2.0 * math.atan2(q.z, q.w)


def tour(out: Path, outputs: list[str], **overrides: Any) -> Any:
    sets = {"mission.outputs": outputs, "mission.task": {"navigate_to_pose": GOAL}}
    sets["mission.time_limit"] = 20
    return run_mission(Mission.load(TOUR, overrides={**sets, **overrides}), out)


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """The short tour with and without the bag; the bag run's RunOutput kept to compare."""
    kept: list[RunOutput] = []

    @register("output", "keep_run")
    class Keep:
        files = ()

        def write(self, run: RunOutput) -> None:
            kept.append(run)

    root = tmp_path_factory.mktemp("bag")
    try:
        with_bag = tour(root / "with", ["report", "trajectory", "bt_log", "bag", "keep_run"])
    finally:
        unregister("output", "keep_run")
    without = tour(root / "without", ["report", "trajectory", "bt_log"])
    return root, with_bag, without, kept[0], read_bag(root / "with" / "bag")


def test_the_bag_has_nav2s_topics_at_the_runs_rates(runs):
    root, report, _, _, bag = runs
    assert report.status == "succeeded"
    assert report.outputs[-1] == BAG_DIR
    assert (root / "with" / "bag" / "metadata.yaml").is_file()
    assert bag.types == TOPICS
    end = round(report.sim_time * 1e9)

    # Every record is in time order, on sim time, within the run.
    assert bag.times == sorted(bag.times) and bag.times[0] >= 0 and bag.times[-1] <= end
    # A scan (and an odometry estimate) at the start and at each period after it.
    assert bag.count("/scan") == math.floor(report.sim_time * LIDAR_HZ + 1e-9) + 1
    assert bag.count("/odom") == math.floor(report.sim_time * ODOM_HZ + 1e-9) + 1
    for topic in ("/scan", "/odom"):
        assert all(ns(m.header.stamp) == t for t, m in bag.msgs[topic])  # stamped as recorded
    # AMCL stamps its pose with the time of the scan it weighed, never later than the record.
    assert all(ns(m.header.stamp) <= t for t, m in bag.msgs["/amcl_pose"])
    # One command per control cycle while the controller drives, no more.
    assert 0.5 * CONTROLLER_HZ * report.sim_time < bag.count("/cmd_vel")
    assert bag.count("/cmd_vel") <= CONTROLLER_HZ * report.sim_time + 1
    assert bag.count("/tf_static") == bag.count("/map") == 1

    # Latched topics as a recording shows them: transient local; the scan best effort.
    for topic in ("/tf_static", "/map", "/amcl_pose"):
        assert bag.qos[topic].durability == QosDurability.TRANSIENT_LOCAL
    assert bag.qos["/tf"].durability == QosDurability.VOLATILE
    assert bag.qos["/scan"].reliability == QosReliability.BEST_EFFORT


def test_messages_match_the_lidar_the_frames_and_the_map(runs):
    _, _, _, run, bag = runs
    rt = run.navigator.runtime
    lidar = rt.sensors[0]
    _, scan = bag.msgs["/scan"][-1]
    assert scan.header.frame_id == lidar.frame_id == "laser"
    assert scan.angle_min == pytest.approx(lidar.angle_min)
    assert scan.angle_increment == pytest.approx(lidar.angle_increment)
    assert len(scan.ranges) == len(lidar.angles) == 360
    assert scan.range_max == pytest.approx(lidar.range_max)

    # /tf_static: the mounts, once; /tf: map -> odom -> base_footprint, ending where the
    # run's frame tree ended.
    [(_, static)] = bag.msgs["/tf_static"]
    mounts = {(t.header.frame_id, t.child_frame_id) for t in static.transforms}
    assert mounts == {("base_footprint", "base_link"), ("base_link", "laser")}
    last: dict[str, Any] = {}
    for _, msg in bag.msgs["/tf"]:
        for t in msg.transforms:
            last[t.child_frame_id] = t
    assert last["odom"].header.frame_id == "map"
    assert last["base_footprint"].header.frame_id == "odom"
    x, y, th = 0.0, 0.0, 0.0
    for child in ("base_footprint", "odom"):  # compose map -> odom -> base_footprint
        tr = last[child].transform
        a = yaw(tr.rotation)
        x, y = (
            tr.translation.x + math.cos(a) * x - math.sin(a) * y,
            tr.translation.y + (math.sin(a) * x + math.cos(a) * y),
        )
        th += a
    end = rt.robot_pose("map", "base_footprint")
    assert (x, y) == pytest.approx((end.x, end.y), abs=1e-9)
    assert math.remainder(th - end.yaw, math.tau) == pytest.approx(0.0, abs=1e-9)

    [(_, grid)] = bag.msgs["/map"]
    served = run.navigator.stack.map_server.map
    assert (grid.info.width, grid.info.height) == (served.width, served.height)
    assert grid.header.frame_id == "map" and len(grid.data) == served.data.size

    # AMCL's pose, with its covariance on x, y and yaw.
    _, amcl = bag.msgs["/amcl_pose"][-1]
    assert amcl.header.frame_id == "map"
    cov = amcl.pose.covariance
    assert cov[0] > 0 and cov[7] > 0 and cov[35] > 0


def test_plans_and_the_bt_log_are_the_runs(runs):
    root, _, _, _, bag = runs
    log = [json.loads(line) for line in (root / "with" / "bt_log.jsonl").read_text().splitlines()]
    planned = [
        e for e in log if e["type"] == "ComputePathToPose" and e["current_status"] == "SUCCESS"
    ]
    assert bag.count("/plan") == len(planned) >= 1
    _, plan = bag.msgs["/plan"][-1]
    goal = plan.poses[-1].pose.position
    assert math.hypot(goal.x - GOAL[0], goal.y - GOAL[1]) < 0.05
    assert plan.header.frame_id == "map"

    expected = [
        (
            round(e["timestamp"] * 1e9),
            e["node_name"],
            e["uid"],
            e["previous_status"],
            e["current_status"],
        )
        for e in log
    ]
    assert bt_events(bag) == expected


def test_the_bag_only_reads_the_run(runs):
    root, with_bag, without, _, _ = runs
    a, b = with_bag.to_dict(), without.to_dict()
    for r in (a, b):
        del r["wall_time"]
    assert a.pop("outputs") == [*b.pop("outputs"), BAG_DIR]
    assert a == b
    for name in ("trajectory.csv", "bt_log.jsonl"):
        assert (root / "with" / name).read_bytes() == (root / "without" / name).read_bytes()


def test_a_rerun_replaces_the_bag_and_can_stamp_cmd_vel(runs):
    root, _, _, _, first = runs
    out = root / "with"
    (out / "bag" / "stale.txt").write_text("from an earlier run")
    tour(out, ["bag"], **{"controller_server.enable_stamped_cmd_vel": True})
    assert not (out / "bag" / "stale.txt").exists()
    bag = read_bag(out / "bag")
    assert bag.types["/cmd_vel"] == "geometry_msgs/msg/TwistStamped"
    assert bag.count("/cmd_vel") == first.count("/cmd_vel")
    _, cmd = bag.msgs["/cmd_vel"][0]
    assert cmd.header.frame_id == "base_link"
    # The tree's log is the same without the run's bt_log beside it.
    assert bt_events(bag) == bt_events(first)


def test_without_rosbags_the_run_does_not_start(tmp_path, monkeypatch):
    for name in [m for m in sys.modules if m == "rosbags" or m.startswith("rosbags.")]:
        monkeypatch.setitem(sys.modules, name, None)
    monkeypatch.setitem(sys.modules, "rosbags", None)
    with pytest.raises(BtnavError, match=r"pip install 'btnav\[logs\]'"):
        tour(tmp_path / "out", ["report", "bag"])
    assert not (tmp_path / "out" / "report.json").exists()
