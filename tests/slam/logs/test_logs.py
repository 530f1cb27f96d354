"""Reading recorded laser logs: CARMEN text logs and ROS 1 / ROS 2 bags."""

from __future__ import annotations

import math
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from btnav.slam.logs import LogError, RecordedLog, read_log

SLAM_LOGS = Path(__file__).resolve().parents[4] / "shared" / "slam_logs"

# ---------------------------------------------------------------- CARMEN

FLASER_LOG = """\
# a hand-written CARMEN log
PARAM robot_front_laser_max 5.0 nohost 0
ODOM 0.0 0.0 0.0 0.0 0.0 0 100.0 nohost 0
SYNC ignored 1 2 3
FLASER 5 1.0 2.0 5.0 7.5 0.5 9 9 9 9 9 9 100.5 nohost 0
ODOM 1.0 0.0 0.5 0.0 0.0 0 101.0 nohost 0
RAWLASER1 0 -1.57 3.14 0.0175 80 0.01 0 2 1.0 1.0 0 101.2 nohost 0
FLASER 5 1.5 2.5 3.5 4.5 0.0 9 9 9 9 9 9 101.5 nohost 0
ODOM 2.0 1.0 1.0 0.0 0.0 0 102.0 nohost 0
"""


def write(tmp_path: Path, text: str, name: str = "run.clf") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def test_flaser_scans_with_odometry_from_odom_lines(tmp_path: Path) -> None:
    log = read_log(write(tmp_path, FLASER_LOG))
    assert isinstance(log, RecordedLog)
    assert [s.stamp for s in log.scans] == [100.5, 101.5]
    scan = log.scans[0]
    assert scan.frame_id == "laser"
    assert scan.angle_min == pytest.approx(-math.pi / 2)
    assert scan.angle_max == pytest.approx(math.pi / 2)
    assert scan.angle_increment == pytest.approx(math.pi / 4)
    # PARAM robot_front_laser_max 5: 5.0 and 7.5 are no return, 0.5 is a reading
    np.testing.assert_array_equal(scan.ranges, np.float32([1.0, 2.0, np.inf, np.inf, 0.5]))
    assert np.isnan(log.scans[1].ranges[4])  # a zero reading is invalid
    assert scan.range_max == 5.0
    # the ODOM lines, not the FLASER odometry fields (all 9s), place the scans
    assert log.odom_source == "ODOM lines"
    np.testing.assert_allclose(log.odom_at(100.5), [0.5, 0.0, 0.25])
    np.testing.assert_allclose(
        log.odom_at([101.5, 99.0, 200.0]), [[1.5, 0.5, 0.75], [0, 0, 0], [2, 1, 1]]
    )
    np.testing.assert_array_equal(log.laser_offset, [0.0, 0.0, 0.0])
    assert log.duration == pytest.approx(2.0)
    assert log.scan_source == "FLASER"


def test_flaser_without_odom_lines_uses_its_odometry_fields(tmp_path: Path) -> None:
    text = (
        "FLASER 3 1 2 3 0.1 0.2 0.3 1.0 2.0 0.5 10.0 host 10.0\n"
        "FLASER 3 1 2 3 0.1 0.2 0.3 2.0 2.0 1.5 11.0 host 11.0\n"
    )
    log = read_log(write(tmp_path, text))
    assert log.odom_source == "FLASER odometry fields"
    np.testing.assert_allclose(log.odom_at(10.5), [1.5, 2.0, 1.0])


def test_180_flaser_beams_without_params_are_one_degree_apart(tmp_path: Path) -> None:
    log = read_log(
        write(tmp_path, "FLASER 180 " + " ".join(["3.0"] * 180) + " 0 0 0 0 0 0 5.0 h 5.0\n")
    )
    scan = log.scans[0]
    assert scan.angle_min == pytest.approx(-math.pi / 2)
    assert scan.angle_increment == pytest.approx(math.radians(1.0))
    assert scan.angle_max == pytest.approx(math.radians(89.0))


@pytest.mark.parametrize(("beams", "last_deg"), [(360, 89.5), (361, 90.0)])
def test_half_degree_flaser_scans_as_fr079_and_mit_csail_log_them(
    tmp_path: Path, beams: int, last_deg: float
) -> None:
    """FR079 logs 360 beams a scan, MIT CSAIL 361: both are 0.5 degrees apart."""
    line = f"FLASER {beams} " + " ".join(["3.0"] * beams) + " 0 0 0 0 0 0 5.0 h 5.0\n"
    scan = read_log(write(tmp_path, line)).scans[0]
    assert scan.angle_min == pytest.approx(-math.pi / 2)
    assert scan.angle_increment == pytest.approx(math.radians(0.5))
    assert scan.angle_max == pytest.approx(math.radians(last_deg))


def test_flaser_geometry_and_mount_from_params(tmp_path: Path) -> None:
    text = (
        "PARAM laser_front_laser_resolution 1.0\n"
        "PARAM robot_frontlaser_offset 0.25\n"
        "FLASER 180 " + " ".join(["3.0"] * 180) + " 0 0 0 0 0 0 5.0 host 5.0\n"
    )
    log = read_log(write(tmp_path, text))
    scan = log.scans[0]
    assert scan.angle_increment == pytest.approx(math.radians(1.0))
    assert scan.angle_max == pytest.approx(math.radians(89.0))  # GMapping's reading of 180 beams
    np.testing.assert_allclose(log.laser_offset, [0.25, 0.0, 0.0])


# The laser 0.2 m ahead of the robot, which faces about -x (yaw +-3.1).
ROBOTLASER_LOG = """\
ROBOTLASER1 0 -1.0 2.0 0.5 30.0 0.01 0 5 1.0 2.0 30.0 40.0 3.0 5 10 20 30 40 50 \
-0.199827 0.008316 3.1 0.0 0.0 3.1 0.1 0.0 0.5 0.5 0.0 50.0 host 50.0
ROBOTLASER1 0 -1.0 2.0 0.5 30.0 0.01 0 5 1.0 2.0 3.0 4.0 3.0 0 \
-0.199827 0.991684 -3.1 0.0 1.0 -3.1 0.1 0.0 0.5 0.5 0.0 51.0 host 51.0
"""


def test_robotlaser1_geometry_offset_and_odometry(tmp_path: Path) -> None:
    log = read_log(write(tmp_path, ROBOTLASER_LOG, "run.log"))
    assert log.scan_source == "ROBOTLASER1"
    first, second = log.scans
    assert (first.angle_min, first.angle_increment, first.range_max) == (-1.0, 0.5, 30.0)
    assert first.angle_max == pytest.approx(1.0)
    np.testing.assert_array_equal(first.ranges, np.float32([1, 2, np.inf, np.inf, 3]))
    np.testing.assert_array_equal(first.intensities, np.float32([10, 20, 30, 40, 50]))
    assert second.intensities.size == 0
    np.testing.assert_allclose(log.laser_offset, [0.2, 0.0, 0.0], atol=1e-5)
    assert log.odom_source == "ROBOTLASER1 odometry fields"
    # yaw interpolates along the shorter arc, through pi, not through 0
    mid = log.odom_at(50.5)
    np.testing.assert_allclose(mid[:2], [0.0, 0.5])
    assert abs(mid[2]) == pytest.approx(math.pi)


def test_a_carmen_log_is_recognised_by_its_content(tmp_path: Path) -> None:
    log = read_log(write(tmp_path, FLASER_LOG, "run.txt"))
    assert len(log.scans) == 2


def test_progress_is_reported(tmp_path: Path) -> None:
    calls: list[tuple[int, int]] = []
    read_log(write(tmp_path, FLASER_LOG), progress=lambda done, total: calls.append((done, total)))
    assert calls[0] == (0, 5) and calls[-1] == (5, 5)


POSE_AND_TIME = "0 0 0 0 0 0 12.0 host 12.0"


@pytest.mark.parametrize(
    ("text", "line", "words"),
    [
        (
            f"FLASER 3 1 2 3 {POSE_AND_TIME}\nFLASER 3 1 2\nFLASER 3 1 2 3 {POSE_AND_TIME}\n",
            2,
            "too few fields",
        ),
        (f"# c\nFLASER 3 1.0 x 2.0 {POSE_AND_TIME}\n", 2, "field 4 'x' is not a number"),
        (f"FLASER 3 1 2 3 4 {POSE_AND_TIME}\n", 1, "does not match"),
        (f"FLASER 3 1 2 {POSE_AND_TIME}\n", 1, "does not match"),
        (f"FLASER three 1 2 3 {POSE_AND_TIME}\n", 1, "'three' is not a whole number"),
        (f"FLASER 3 1 2 3 {POSE_AND_TIME}\nFLASER 3 1 2 3 0 0 0 0", 2, "truncated"),
        (
            f"FLASER 3 1 2 3 {POSE_AND_TIME}\nODOM 1 2 x 0 0 0 13.0 host 0\n",
            2,
            "'x' is not a number",
        ),
        (f"FLASER 3 1 2 3 {POSE_AND_TIME}\nODOM 1 2 3\n", 2, "too few fields"),
        (
            f"PARAM robot_front_laser_max far\nFLASER 3 1 2 3 {POSE_AND_TIME}\n",
            1,
            "expected a number",
        ),
        ("ROBOTLASER1 0 -1 2 0.5 30 0.01 0 2 1.0\n", 1, "too few fields"),
    ],
)
def test_carmen_errors_name_the_file_and_line(
    tmp_path: Path, text: str, line: int, words: str
) -> None:
    path = write(tmp_path, text)
    with pytest.raises(LogError) as err:
        read_log(path)
    assert str(err.value).startswith(f"{path}:{line}: ")
    assert words in str(err.value)


def test_a_log_without_scans_is_an_error(tmp_path: Path) -> None:
    path = write(tmp_path, "ODOM 0 0 0 0 0 0 1.0 host 0\nRAWLASER1 0 0 0 0 0 0 0 0 0 1.0 h 0\n")
    with pytest.raises(LogError, match=r"no scans.*RAWLASER1 1") as err:
        read_log(path)
    assert err.value.file == str(path)


def test_unknown_and_missing_files(tmp_path: Path) -> None:
    with pytest.raises(LogError, match="not a log btnav can read"):
        read_log(write(tmp_path, "hello world\n", "notes.txt"))
    with pytest.raises(LogError, match="log not found"):
        read_log(tmp_path / "missing.clf")
    with pytest.raises(LogError, match="--scan-topic names a bag topic"):
        read_log(write(tmp_path, FLASER_LOG), scan_topic="/scan")


# ---------------------------------------------------------------- ROS bags


def _ros2(
    tmp_path: Path, name: str, storage: str, topics: dict[str, list[tuple[int, Any]]]
) -> Path:
    """A rosbag2 folder with the given (timestamp ns, message) lists per topic."""
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore

    ts = get_typestore(Stores.ROS2_HUMBLE)
    path = tmp_path / name
    plugin = StoragePlugin.MCAP if storage == "mcap" else StoragePlugin.SQLITE3
    with Writer(path, version=8, storage_plugin=plugin) as writer:
        for topic, msgs in topics.items():
            conn = writer.add_connection(topic, msgs[0][1].__msgtype__, typestore=ts)
            for t, msg in msgs:
                writer.write(conn, t, ts.serialize_cdr(msg, msg.__msgtype__))
    return path


class Msgs:
    """Message builders for the tests' bags (ROS 2 Humble types)."""

    def __init__(self, store: str = "ROS2_HUMBLE") -> None:
        from rosbags.typesys import Stores, get_types_from_msg, get_typestore

        self.ts = get_typestore(getattr(Stores, store))
        if "tf2_msgs/msg/TFMessage" not in self.ts.types:  # ROS 1's store lacks it
            self.ts.register(
                get_types_from_msg(
                    "geometry_msgs/TransformStamped[] transforms", "tf2_msgs/msg/TFMessage"
                )
            )
        self.t = self.ts.types

    def header(self, t: float, frame: str) -> Any:
        sec = math.floor(t)
        stamp = self.t["builtin_interfaces/msg/Time"](sec=sec, nanosec=round((t - sec) * 1e9))
        cls = self.t["std_msgs/msg/Header"]
        if "seq" in cls.__dataclass_fields__:
            return cls(seq=0, stamp=stamp, frame_id=frame)
        return cls(stamp=stamp, frame_id=frame)

    def quat(self, yaw: float) -> Any:
        return self.t["geometry_msgs/msg/Quaternion"](
            x=0.0, y=0.0, z=math.sin(yaw / 2), w=math.cos(yaw / 2)
        )

    def scan(self, t: float, ranges: Sequence[float], frame: str = "laser") -> Any:
        return self.t["sensor_msgs/msg/LaserScan"](
            header=self.header(t, frame),
            angle_min=-1.0,
            angle_max=1.0,
            angle_increment=2.0 / (len(ranges) - 1),
            time_increment=0.0,
            scan_time=0.1,
            range_min=0.1,
            range_max=10.0,
            ranges=np.array(ranges, dtype=np.float32),
            intensities=np.zeros(0, dtype=np.float32),
        )

    def odom(self, t: float, x: float, y: float, yaw: float) -> Any:
        g = self.t
        pose = g["geometry_msgs/msg/Pose"](
            position=g["geometry_msgs/msg/Point"](x=x, y=y, z=0.0), orientation=self.quat(yaw)
        )
        vec = g["geometry_msgs/msg/Vector3"](x=0.0, y=0.0, z=0.0)
        return g["nav_msgs/msg/Odometry"](
            header=self.header(t, "odom"),
            child_frame_id="base_footprint",
            pose=g["geometry_msgs/msg/PoseWithCovariance"](pose=pose, covariance=np.zeros(36)),
            twist=g["geometry_msgs/msg/TwistWithCovariance"](
                twist=g["geometry_msgs/msg/Twist"](linear=vec, angular=vec),
                covariance=np.zeros(36),
            ),
        )

    def tf(self, t: float, parent: str, child: str, x: float, y: float, yaw: float) -> Any:
        g = self.t
        transform = g["geometry_msgs/msg/Transform"](
            translation=g["geometry_msgs/msg/Vector3"](x=x, y=y, z=0.0), rotation=self.quat(yaw)
        )
        stamped = g["geometry_msgs/msg/TransformStamped"](
            header=self.header(t, parent), child_frame_id=child, transform=transform
        )
        return g["tf2_msgs/msg/TFMessage"](transforms=[stamped])


def ns(t: float) -> int:
    return round(t * 1e9)


def robot_topics(m: Msgs, *, odometry: str = "odom") -> dict[str, list[tuple[int, Any]]]:
    """Five scans at 10 Hz, the robot driving along x at 1 m/s and turning at 0.5 rad/s;
    the laser 0.1 m ahead of base_link, which is 0.05 m left of base_footprint."""
    scans = [
        (ns(1.0 + 0.1 * k), m.scan(1.0 + 0.1 * k, [0.05, 1.0 + k, 10.0, 2.0])) for k in range(5)
    ]
    poses = [(0.95 + 0.05 * k, 0.05 * k, 0.0, 0.025 * k) for k in range(13)]
    topics = {"/scan": scans}
    if odometry == "odom":
        topics["/odom"] = [(ns(t), m.odom(t, x, y, yaw)) for t, x, y, yaw in poses]
    else:
        topics["/tf"] = [
            (ns(t), m.tf(t, "odom", "base_footprint", x, y, yaw)) for t, x, y, yaw in poses
        ]
    topics["/tf_static"] = [
        (ns(0.9), m.tf(0.9, "base_footprint", "base_link", 0.0, 0.05, 0.0)),
        (ns(0.9), m.tf(0.9, "base_link", "laser", 0.1, 0.0, 0.0)),
    ]
    return topics


@pytest.fixture(scope="module")
def msgs() -> Msgs:
    pytest.importorskip("rosbags")
    return Msgs()


def check_robot_log(log: RecordedLog) -> None:
    assert len(log.scans) == 5
    np.testing.assert_allclose([s.stamp for s in log.scans], 1.0 + 0.1 * np.arange(5), atol=1e-9)
    scan = log.scans[2]
    assert (scan.frame_id, scan.angle_min, scan.range_max) == ("laser", -1.0, 10.0)
    # REP-117: below range_min invalid (NaN), at range_max no return (+inf)
    assert np.isnan(scan.ranges[0]) and scan.ranges[2] == np.inf
    np.testing.assert_array_equal(scan.ranges[[1, 3]], np.float32([3.0, 2.0]))
    np.testing.assert_allclose(log.odom_at(1.2), [0.25, 0.0, 0.125], atol=1e-9)
    np.testing.assert_allclose(log.laser_offset, [0.1, 0.05, 0.0], atol=1e-12)


@pytest.mark.parametrize("storage", ["sqlite3", "mcap"])
def test_ros2_bag_with_odometry(tmp_path: Path, msgs: Msgs, storage: str) -> None:
    bag = _ros2(tmp_path, "run", storage, robot_topics(msgs))
    calls: list[tuple[int, int]] = []
    log = read_log(bag, progress=lambda done, total: calls.append((done, total)))
    check_robot_log(log)
    assert calls[-1] == (20, 20)  # 5 scans, 13 odometry messages, 2 static transforms
    assert (log.scan_source, log.odom_source) == ("/scan", "/odom (nav_msgs/msg/Odometry)")
    storage_file = next(bag.glob("*.mcap" if storage == "mcap" else "*.db3"))
    check_robot_log(read_log(storage_file))  # the storage file itself reads too


def test_ros2_bag_with_tf_odometry(tmp_path: Path, msgs: Msgs) -> None:
    log = read_log(_ros2(tmp_path, "run", "mcap", robot_topics(msgs, odometry="tf")))
    check_robot_log(log)
    assert log.odom_source == "/tf odom -> base_footprint"


def test_ros1_bag(tmp_path: Path) -> None:
    pytest.importorskip("rosbags")
    from rosbags.rosbag1 import Writer

    m = Msgs("ROS1_NOETIC")
    path = tmp_path / "run.bag"
    with Writer(path) as writer:
        for topic, items in robot_topics(m).items():
            conn = writer.add_connection(topic, items[0][1].__msgtype__, typestore=m.ts)
            for t, msg in items:
                writer.write(conn, t, m.ts.serialize_ros1(msg, msg.__msgtype__))
    check_robot_log(read_log(path))


def test_topic_choice(tmp_path: Path, msgs: Msgs) -> None:
    topics = robot_topics(msgs)
    topics["/scan_rear"] = topics["/scan"]
    topics["/wheel_odom"] = topics["/odom"]
    bag = _ros2(tmp_path, "two", "sqlite3", topics)
    with pytest.raises(
        LogError,
        match=r"2 LaserScan topics in the bag: /scan, /scan_rear; choose one with --scan-topic",
    ):
        read_log(bag)
    with pytest.raises(LogError, match=r"2 Odometry topics.*/odom, /wheel_odom.*--odom-topic"):
        read_log(bag, scan_topic="/scan")
    check_robot_log(read_log(bag, scan_topic="/scan_rear", odom_topic="/wheel_odom"))
    with pytest.raises(LogError) as err:
        read_log(bag, scan_topic="/scna", odom_topic="/odom")
    assert str(err.value).startswith(f"{bag}: --scan-topic /scna: no such topic")
    assert "(did you mean '/scan'?)" in str(err.value)
    with pytest.raises(LogError, match="carries nav_msgs/msg/Odometry, not sensor_msgs"):
        read_log(bag, scan_topic="/odom", odom_topic="/odom")


def test_bag_without_scans_or_unreadable(tmp_path: Path, msgs: Msgs) -> None:
    topics = robot_topics(msgs)
    del topics["/scan"]
    bag = _ros2(tmp_path, "noscan", "mcap", topics)
    with pytest.raises(
        LogError, match=r"no sensor_msgs/msg/LaserScan topic in the bag \(topics: /odom"
    ):
        read_log(bag)
    junk = tmp_path / "junk.bag"
    junk.write_bytes(b"#ROSBAG V2.0\n" + bytes(range(256)) * 4)
    with pytest.raises(LogError, match="cannot read this bag") as err:
        read_log(junk)
    assert err.value.file == str(junk)


def test_reading_a_bag_without_rosbags_says_what_to_install(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setitem(sys.modules, "rosbags.highlevel", None)  # import fails
    bag = tmp_path / "run.bag"
    bag.write_bytes(b"#ROSBAG V2.0\n")
    with pytest.raises(LogError, match=r"needs the 'rosbags' package: pip install 'btnav\[logs\]'"):
        read_log(bag)


def test_bag_without_laser_mount_warns(tmp_path: Path, msgs: Msgs) -> None:
    topics = robot_topics(msgs)
    del topics["/tf_static"]
    with pytest.warns(
        UserWarning, match="no transform from base_footprint to the scans' frame laser"
    ):
        log = read_log(_ros2(tmp_path, "nomount", "mcap", topics))
    np.testing.assert_array_equal(log.laser_offset, [0.0, 0.0, 0.0])


# ---------------------------------------------------------------- the Intel lab log


@pytest.mark.slow
def test_intel_clf_and_bag_read_to_the_same_log() -> None:
    pytest.importorskip("rosbags")
    clf = read_log(SLAM_LOGS / "intel.clf")
    bag = read_log(SLAM_LOGS / "intel.bag")
    assert len(clf.scans) == len(bag.scans) == 13631
    assert clf.duration == pytest.approx(2691.3, abs=0.1)
    np.testing.assert_allclose(clf.scan_stamps, bag.scan_stamps, rtol=0, atol=1e-6)
    a, b = clf.scans[100], bag.scans[100]
    # the same first beam; CARMEN's 1-degree spacing for the .clf, the pi/179 the bag declares
    assert a.angle_min == pytest.approx(b.angle_min, abs=1e-6)
    assert a.angle_increment == pytest.approx(math.radians(1.0))
    assert b.angle_increment == pytest.approx(math.pi / 179, abs=1e-6)
    r_clf = np.stack([s.ranges for s in clf.scans])
    r_bag = np.stack([s.ranges for s in bag.scans])
    assert r_clf.shape == (13631, 180)
    np.testing.assert_array_equal(r_clf, r_bag)  # both float32, no-returns both +inf
    assert np.isinf(r_clf).any() and not np.isnan(r_clf).any()
    np.testing.assert_allclose(
        clf.odom_at(clf.scan_stamps), bag.odom_at(bag.scan_stamps), atol=1e-6
    )
    np.testing.assert_array_equal(clf.laser_offset, bag.laser_offset)
