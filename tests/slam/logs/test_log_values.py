"""Values no log can hold, and damaged bags: one located error, exit 2, nothing written.

A NaN or infinite pose once reached the scan matcher and crashed it (OverflowError);
a damaged bag's error named no record. What a user sees is checked through the CLI.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from btnav.cli import main
from btnav.slam.logs import read_log

from .test_logs import Msgs, _ros2, ns, robot_topics

CARTOGRAPHER_LUA = Path(__file__).resolve().parents[3] / "params" / "cartographer_2d.lua"
SCAN = "FLASER 3 1.0 2.0 3.0 0 0 0 {odom} {t} host 0"
ODOM = "ODOM {pose} 0 0 0 {t} host 0"


def carmen(tmp_path: Path, bad_line: str | None = None) -> tuple[Path, int]:
    """A small driving log; `bad_line` replaces its sixth line. Returns (file, 1-based line)."""
    lines = []
    for k in range(10):
        t = 100.0 + k
        lines.append(ODOM.format(pose=f"{0.3 * k} 0 0", t=t))
        lines.append(SCAN.format(odom=f"{0.3 * k} 0 0", t=t + 0.5))
    if bad_line is not None:
        lines[5] = bad_line
    path = tmp_path / "run.clf"
    path.write_text("\n".join(lines) + "\n")
    return path, 6


def run(tmp_path: Path, log: Path, *extra: str) -> tuple[int, Path]:
    """`btnav slam LOG ... -o OUT`: the exit code and OUT."""
    out = tmp_path / "out"
    return main(["slam", str(log), *extra, "-o", str(out)]), out


@pytest.mark.parametrize(
    ("line", "words"),
    [
        (ODOM.format(pose="nan 0 0", t=102.0), "ODOM: field 2 (x) 'nan' is not a finite number"),
        (ODOM.format(pose="inf 0 0", t=102.0), "ODOM: field 2 (x) 'inf' is not a finite number"),
        (ODOM.format(pose="0 -inf 0", t=102.0), "ODOM: field 3 (y) '-inf'"),
        (ODOM.format(pose="1e300 0 0", t=102.0), "ODOM: field 2 (x) '1e300' is beyond +-1e+09 m"),
        (ODOM.format(pose="0 0 nan", t=102.0), "ODOM: field 4 (theta) 'nan'"),
        (ODOM.format(pose="0 0 0", t="nan"), "ODOM: field 8 (timestamp) 'nan'"),
        (SCAN.format(odom="nan 0 0", t=102.5), "FLASER: field 9 (odom_x) 'nan'"),
        (SCAN.format(odom="0 0 0", t="inf"), "FLASER: field 12 (ipc_timestamp) 'inf'"),
        ("FLASER 3 1 2 3 nan 0 0 0 0 0 102.5 host 0", "FLASER: field 6 (x) 'nan'"),
    ],
)
@pytest.mark.parametrize("engine", ["slam_toolbox", "cartographer"])
def test_a_non_finite_or_absurd_pose_or_stamp_names_its_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], line: str, words: str, engine: str
) -> None:
    log, at = carmen(tmp_path, line)
    extra = ["--lua", str(CARTOGRAPHER_LUA)] if engine == "cartographer" else []
    code, out = run(tmp_path, log, *extra)
    err = capsys.readouterr().err
    assert code == 2
    assert err.startswith(f"btnav: error: {log}:{at}: {words}")
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert not out.exists()


def test_a_robotlaser_pose_that_is_not_finite_names_its_line(tmp_path: Path) -> None:
    head = "ROBOTLASER1 0 -1.57 3.14 1.57 30 0.01 0 3 1 2 3 0"  # fields 1-13, no remissions
    poses = "0 0 0 {robot} 0 0 0 0 0"  # laser x y theta, robot x y theta, motion
    path = tmp_path / "rl.clf"
    lines = [f"{head} {poses.format(robot=r)} {t} h 0" for r, t in (("0 0 0", 10), ("0 0 nan", 11))]
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(Exception, match=r"rl.clf:2: ROBOTLASER1: field 19 \(robot_theta\) 'nan'"):
        read_log(path)


def test_invalid_readings_stay_valid_input(tmp_path: Path) -> None:
    """A range may be inf or NaN: a laser's "no return" and "invalid reading"."""
    log, _ = carmen(tmp_path, "FLASER 3 nan inf 3.0 0 0 0 0 0 0 102.5 host 0")
    scans = read_log(log).scans
    assert any(np.isnan(s.ranges[0]) and np.isinf(s.ranges[1]) for s in scans)


# ---------------------------------------------------------------- bags


@pytest.fixture(scope="module")
def msgs() -> Msgs:
    pytest.importorskip("rosbags")
    return Msgs()


def test_a_bag_odometry_pose_that_is_nan_names_topic_message_and_stamp(
    tmp_path: Path, msgs: Msgs, capsys: pytest.CaptureFixture[str]
) -> None:
    topics = robot_topics(msgs)
    topics["/odom"][6] = (ns(1.25), msgs.odom(1.25, float("nan"), 0.0, 0.0))
    bag = _ros2(tmp_path, "nanodom", "mcap", topics)
    code, out = run(tmp_path, bag)
    err = capsys.readouterr().err
    assert code == 2 and not out.exists()
    assert err.strip() == (
        f"btnav: error: {bag}: message 7 on /odom (stamp 1.250000 s): "
        "pose.pose.position.x 'nan' is not a finite number"
    )


def test_a_tf_odometry_that_is_infinite_names_its_message(tmp_path: Path, msgs: Msgs) -> None:
    topics = robot_topics(msgs, odometry="tf")
    topics["/tf"][3] = (ns(1.1), msgs.tf(1.1, "odom", "base_footprint", 0.1, float("inf"), 0.0))
    bag = _ros2(tmp_path, "inftf", "sqlite3", topics)
    with pytest.raises(Exception, match=r"message 4 on /tf \(stamp 1.100000 s\): "
                       r"transforms\[0\].transform.translation.y 'inf'"):  # fmt: skip
        read_log(bag)


def test_a_scan_with_a_nan_angle_names_its_message(tmp_path: Path, msgs: Msgs) -> None:
    topics = robot_topics(msgs)
    scan = topics["/scan"][2][1]
    scan.angle_increment = float("nan")
    bag = _ros2(tmp_path, "nanscan", "mcap", topics)
    with pytest.raises(Exception, match=r"message 3 on /scan .*angle_increment 'nan'"):
        read_log(bag)


def _ros1_bag(path: Path, minutes: int = 2) -> Any:
    """A bz2-compressed ROS 1 bag of 10 Hz scans and 50 Hz odometry, in small chunks."""
    from rosbags.rosbag1 import Writer

    m = Msgs("ROS1_NOETIC")
    writer = Writer(path)
    writer.set_compression(Writer.CompressionFormat.BZ2)
    writer.chunk_threshold = 20_000
    with writer:
        scan = writer.add_connection("/scan", "sensor_msgs/msg/LaserScan", typestore=m.ts)
        odom = writer.add_connection("/odom", "nav_msgs/msg/Odometry", typestore=m.ts)
        for k in range(minutes * 600):
            t = 1.0 + 0.1 * k
            msg = m.scan(t, [1.0 + 0.01 * (k % 50)] * 90)
            writer.write(scan, ns(t), m.ts.serialize_ros1(msg, msg.__msgtype__))
            o = m.odom(t, 0.01 * k, 0.0, 0.0)
            writer.write(odom, ns(t), m.ts.serialize_ros1(o, o.__msgtype__))
    return m


def _chunks(path: Path) -> list[tuple[int, int]]:
    """(chunk record position, data position) of each chunk of a ROS 1 bag."""
    from rosbags.rosbag1 import Reader

    with Reader(path) as reader:
        return sorted((pos, c.datapos) for pos, c in reader.chunks.items())


def test_a_bag_damaged_mid_file_names_the_message_and_its_chunk(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    pytest.importorskip("rosbags")
    bag = tmp_path / "damaged.bag"
    _ros1_bag(bag)
    chunks = _chunks(bag)
    pos, data = chunks[len(chunks) // 2]
    raw = bytearray(bag.read_bytes())
    raw[data + 10 : data + 60] = bytes(50)  # the compressed stream no longer decodes
    bag.write_bytes(bytes(raw))
    code, out = run(tmp_path, bag)
    err = capsys.readouterr().err.strip()
    assert code == 2 and not out.exists() and len(err.splitlines()) == 1
    found = re.fullmatch(
        rf"btnav: error: {re.escape(str(bag))}: cannot read message (\d+) on /(scan|odom) "
        rf"\(bag time ([0-9.]+) s, in the chunk at byte (\d+)\): .+",
        err,
    )
    assert found, err
    assert int(found[4]) == pos


def test_a_truncated_bag_says_it_is_cut_short_and_where(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    pytest.importorskip("rosbags")
    bag = tmp_path / "cut.bag"
    _ros1_bag(bag, minutes=1)
    size = bag.stat().st_size
    bag.write_bytes(bag.read_bytes()[: size // 2])
    code, out = run(tmp_path, bag)
    err = capsys.readouterr().err.strip()
    assert code == 2 and not out.exists()
    assert re.search(
        rf"the bag is cut short: its header puts the index at byte \d+, but the file ends at "
        rf"byte {size // 2}",
        err,
    ), err
