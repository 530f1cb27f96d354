"""ROS 1 bags and ROS 2 bags (sqlite3 or MCAP storage), without ROS.

Read with the pure-Python `rosbags` library (the optional extra `btnav[logs]`): the
LaserScan messages of one topic and the Odometry of one topic or, without one, the
`odom -> base_footprint` transform on `/tf`, as slam_toolbox takes it, each at its header
stamp. A topic is chosen for the user when it is the only one of its kind; the laser's
offset comes from the transforms. A bad message is a `LogError` naming its topic, number
and time. Details: docs/decisions/0057.
"""

from __future__ import annotations

import heapq
import itertools
import struct
import warnings
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from btnav.core import fmath
from btnav.core.errors import BtnavWarning
from btnav.core.geometry import Pose2D
from btnav.core.messages import LaserScan
from btnav.core.suggest import best_match

from .recorded_log import (
    LogError,
    Progress,
    RecordedLog,
    implausible,
    rep117_ranges,
    time_span,
    why_implausible,
)

SCAN_TYPE = "sensor_msgs/msg/LaserScan"
ODOM_TYPE = "nav_msgs/msg/Odometry"
TF_TYPE = "tf2_msgs/msg/TFMessage"
TF_TOPIC, TF_STATIC_TOPIC = "/tf", "/tf_static"
#: Children of `odom` that are the robot's base, best first (REP-105).
BASE_FRAMES = ("base_footprint", "base_link")
_PROGRESS_EVERY = 1000


def _stamp(header: Any) -> float:
    return float(header.stamp.sec) + float(header.stamp.nanosec) * 1e-9


def _frame(name: str) -> str:
    """ROS 1 frame ids may start with '/'; tf2 dropped it."""
    return name.lstrip("/")


def _yaw(q: NDArray[np.float64]) -> NDArray[np.float64]:
    """Yaw of (M, 4) quaternions x, y, z, w (the rotation about z of a planar robot)."""
    x, y, z, w = q[:, 0], q[:, 1], q[:, 2], q[:, 3]
    return fmath.arctan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def _bag_target(path: Path) -> Path:
    """What `rosbags` opens: a ROS 1 .bag, a rosbag2 folder, or a bare .db3/.mcap
    (its folder when the folder has the bag's metadata.yaml)."""
    if path.is_dir() and not (path / "metadata.yaml").exists():
        files = sorted(path.glob("*.mcap")) + sorted(path.glob("*.db3"))
        if len(files) != 1:
            raise LogError(
                "not a rosbag2 folder: no metadata.yaml"
                + (f" and {len(files)} storage files" if files else " and no .db3 or .mcap file"),
                file=path,
            )
        return files[0]
    if path.suffix in (".db3", ".mcap") and (path.parent / "metadata.yaml").exists():
        return path.parent
    if path.is_file() and path.suffix != ".bag":
        with path.open("rb") as fh:
            if fh.read(7) == b"#ROSBAG":
                raise LogError("a ROS 1 bag: rename it to end in .bag to read it", file=path)
    return path


def _open(path: Path) -> Any:
    try:
        from rosbags.highlevel import AnyReader
        from rosbags.typesys import Stores, get_typestore
    except ImportError:
        raise LogError(
            "reading ROS bags needs the 'rosbags' package: pip install 'btnav[logs]'", file=path
        ) from None
    target = _bag_target(path)
    try:
        reader = AnyReader([target], default_typestore=get_typestore(Stores.ROS2_HUMBLE))
        reader.open()
    except Exception as exc:  # rosbags raises many kinds for a damaged or foreign file
        cut = _ros1_index_place(target)
        raise LogError(
            f"cannot read this bag: {exc}" + (f"; {cut}" if cut else ""), file=path
        ) from None
    return reader


def _ros1_index_place(path: Path) -> str | None:
    """For a ROS 1 bag whose index cannot be read: where its header says the index is,
    and whether the file reaches it (a recording stopped before the bag was closed
    does not). None for any other file."""
    try:
        with path.open("rb") as fh:
            if fh.readline() != b"#ROSBAG V2.0\n":
                return None
            (size,) = struct.unpack("<I", fh.read(4))
            header = fh.read(size)
        end = path.stat().st_size
    except (OSError, struct.error):
        return None
    fields, i = {}, 0
    while i + 4 <= len(header):
        (n,) = struct.unpack_from("<I", header, i)
        name, _, value = header[i + 4 : i + 4 + n].partition(b"=")
        fields[name], i = value, i + 4 + n
    if len(fields.get(b"index_pos", b"")) != 8:
        return None
    (index_pos,) = struct.unpack("<Q", fields[b"index_pos"])
    if index_pos >= end:
        return (
            f"the bag is cut short: its header puts the index at byte {index_pos}, "
            f"but the file ends at byte {end} (`rosbag reindex` rebuilds the index)"
        )
    return f"the index starts at byte {index_pos} of {end}"


def _topics(reader: Any) -> dict[str, str]:
    """Topic -> message type."""
    return {c.topic: c.msgtype for c in reader.connections}


def _choose(
    path: Path, topics: dict[str, str], wanted: str | None, msgtype: str, flag: str, what: str
) -> str | None:
    """The topic to read: the one named, or the only one of `msgtype` (None if there is none)."""
    of_type = sorted(t for t, m in topics.items() if m == msgtype)
    if wanted is not None:
        if wanted not in topics:
            listed = ", ".join(of_type) or "none"
            raise LogError(
                f"{flag} {wanted}: no such topic in the bag ({what} topics: {listed})",
                file=path,
                suggestion=best_match(wanted, of_type or list(topics)),
            )
        if topics[wanted] != msgtype:
            raise LogError(
                f"{flag} {wanted}: the topic carries {topics[wanted]}, not {msgtype}", file=path
            )
        return wanted
    if len(of_type) > 1:
        raise LogError(
            f"{len(of_type)} {what} topics in the bag: {', '.join(of_type)}; "
            f"choose one with {flag}",
            file=path,
        )
    return of_type[0] if of_type else None


def _messages(reader: Any, path: Path, topics: list[str]) -> Iterator[tuple[str, int, Any]]:
    """(topic, number on the topic from 1, message) of the given topics in bag order; a
    damaged message is a LogError naming its topic, its number there and its bag time."""
    conns = [c for c in reader.connections if c.topic in topics]
    counts = dict.fromkeys(topics, 0)
    it = reader.messages(connections=conns)
    done = 0
    last = "before the first message"
    while True:
        try:
            conn, t, raw = next(it)
        except StopIteration:
            return
        except Exception as exc:  # a chunk that does not decompress or parse
            where = _ros1_failed_record(conns, done, counts) or f"the message {last}"
            raise LogError(f"cannot read {where}: {exc}", file=path) from None
        topic, number = conn.topic, counts[conn.topic] + 1
        try:
            msg = reader.deserialize(raw, conn.msgtype)
        except Exception as exc:
            where = f"message {number} on {topic} (bag time {t * 1e-9:.3f} s)"
            raise LogError(f"cannot read {where}: {exc}", file=path) from None
        counts[topic], done = number, done + 1
        last = f"after message {number} on {topic} (bag time {t * 1e-9:.3f} s)"
        yield topic, number, msg


def _ros1_failed_record(conns: list[Any], done: int, counts: dict[str, int]) -> str | None:
    """The message a ROS 1 bag failed on, by its index: the one after the `done` read
    (the order the rosbags reader merges the topics' indexes in), with the byte offset
    of its chunk. None when the bag is not a ROS 1 one read from one file."""
    owners = {id(c.owner) for c in conns}
    indexes = getattr(conns[0].owner, "indexes", None) if conns else None
    if len(owners) != 1 or not isinstance(indexes, dict):
        return None
    merged = heapq.merge(
        *[[(e, c.topic) for e in indexes.get(c.id, [])] for c in conns], key=lambda x: x[0].time
    )
    failed = next(itertools.islice(merged, done, None), None)
    if failed is None:
        return None
    entry, topic = failed
    return (
        f"message {counts.get(topic, 0) + 1} on {topic} (bag time {entry.time * 1e-9:.3f} s, "
        f"in the chunk at byte {entry.chunk_pos})"
    )


def _check_values(
    path: Path, topic: str, number: int, stamp: float, values: list[tuple[str, float, str]]
) -> None:
    """A LogError for the first of `values` (name, value, kind) that `implausible` flags
    (one array check a message: a bag has tens of thousands)."""
    names, numbers, kinds = zip(*values, strict=True)
    bad = np.flatnonzero(implausible(numbers, kinds))
    if len(bad):
        j = int(bad[0])
        why = why_implausible(repr(float(numbers[j])), kinds[j])
        raise LogError(
            f"message {number} on {topic} (stamp {stamp:.6f} s): {names[j]} {why}", file=path
        )


def _scan(msg: Any, path: Path, topic: str, number: int) -> LaserScan:
    r_min, r_max = float(msg.range_min), float(msg.range_max)
    stamp = _stamp(msg.header)
    checks = [("header.stamp", stamp, "stamp")]
    checks += [(f"angle_{k}", float(getattr(msg, f"angle_{k}")), "yaw") for k in ("min", "max", "increment")]  # fmt: skip
    _check_values(path, topic, number, stamp, checks)
    return LaserScan(
        stamp=stamp,
        frame_id=_frame(msg.header.frame_id),
        angle_min=float(msg.angle_min),
        angle_max=float(msg.angle_max),
        angle_increment=float(msg.angle_increment),
        range_min=r_min,
        range_max=r_max,
        ranges=rep117_ranges(msg.ranges, r_min, r_max),
        scan_time=float(msg.scan_time),
        time_increment=float(msg.time_increment),
        intensities=np.array(msg.intensities, dtype=np.float32),
    )


class _Transforms:
    """What /tf and /tf_static said: the odom -> base stream and the fixed mounts."""

    def __init__(self) -> None:
        self.odom: dict[
            tuple[str, str], list[tuple[float, float, float, float, float, float, float]]
        ] = {}
        self.fixed: dict[str, tuple[str, Pose2D]] = {}  # child -> (parent, pose in parent)

    def add(self, msg: Any, where: tuple[Path, str, int], *, static: bool) -> None:
        """The transforms of one message; `where` (file, topic, number) places an error."""
        for k, tf in enumerate(msg.transforms):
            parent, child = _frame(tf.header.frame_id), _frame(tf.child_frame_id)
            t, q = tf.transform.translation, tf.transform.rotation
            is_odom = parent.endswith("odom") and child.endswith(BASE_FRAMES)
            if not (is_odom or static or child not in self.fixed):
                continue
            stamp = _stamp(tf.header)
            _check_values(*where, stamp, _pose_values(f"transforms[{k}].", stamp, t, q, "transform.translation", "transform.rotation"))  # fmt: skip
            if is_odom:
                rows = self.odom.setdefault((parent, child), [])
                rows.append((stamp, t.x, t.y, q.x, q.y, q.z, q.w))
            else:
                yaw = float(_yaw(np.array([[q.x, q.y, q.z, q.w]]))[0])
                self.fixed[child] = (parent, Pose2D(float(t.x), float(t.y), yaw))

    def odometry(self) -> tuple[str, NDArray[np.float64], NDArray[np.float64]] | None:
        """(source, stamps, poses) of the odom -> base transform, base_footprint first."""
        for base in BASE_FRAMES:
            for (parent, child), rows in sorted(self.odom.items()):
                if child.endswith(base):
                    a = np.array(rows, dtype=np.float64)
                    poses = np.stack([a[:, 1], a[:, 2], _yaw(a[:, 3:7])], axis=1)
                    return f"{TF_TOPIC} {parent} -> {child}", a[:, 0], poses
        return None

    def mount(self, base: str, frame: str) -> Pose2D | None:
        """`frame`'s pose in `base` from the fixed transforms, or None without a chain."""
        pose, here, seen = Pose2D(), frame, set()
        while here != base:
            if here in seen or here not in self.fixed:
                return None
            seen.add(here)
            parent, in_parent = self.fixed[here]
            pose, here = in_parent @ pose, parent
        return pose


def _pose_values(
    prefix: str, stamp: float, t: Any, q: Any, position: str, orientation: str
) -> list[tuple[str, float, str]]:
    """(name, value, kind) of a stamped pose's fields as `_check_values` takes them."""
    out = [(f"{prefix}header.stamp", stamp, "stamp")]
    out += [(f"{prefix}{position}.{a}", float(getattr(t, a)), "position") for a in "xy"]
    out += [(f"{prefix}{orientation}.{a}", float(getattr(q, a)), "quaternion") for a in "xyzw"]
    return out


def read_rosbag(
    path: str | Path,
    *,
    scan_topic: str | None = None,
    odom_topic: str | None = None,
    progress: Progress | None = None,
) -> RecordedLog:
    """Read the scans and the odometry of a ROS 1 or ROS 2 bag."""
    p = Path(path)
    reader = _open(p)
    try:
        return _read(reader, p, scan_topic, odom_topic, progress)
    finally:
        reader.close()


def _read(
    reader: Any, p: Path, scan_topic: str | None, odom_topic: str | None, progress: Progress | None
) -> RecordedLog:
    topics = _topics(reader)
    use_tf = odom_topic == TF_TOPIC
    scan = _choose(p, topics, scan_topic, SCAN_TYPE, "--scan-topic", "LaserScan")
    if scan is None:
        listed = ", ".join(f"{t} ({m})" for t, m in sorted(topics.items())) or "none"
        raise LogError(f"no {SCAN_TYPE} topic in the bag (topics: {listed})", file=p)
    odom = None if use_tf else _choose(p, topics, odom_topic, ODOM_TYPE, "--odom-topic", "Odometry")
    if use_tf and topics.get(TF_TOPIC) != TF_TYPE:
        raise LogError(
            f"--odom-topic {TF_TOPIC}: the bag has no {TF_TYPE} topic {TF_TOPIC}", file=p
        )
    read_tf = (use_tf or odom is None) and topics.get(TF_TOPIC) == TF_TYPE
    wanted = [scan] + ([odom] if odom else []) + ([TF_TOPIC] if read_tf else [])
    if topics.get(TF_STATIC_TOPIC) == TF_TYPE:
        wanted.append(TF_STATIC_TOPIC)
    total = sum(c.msgcount for c in reader.connections if c.topic in wanted)
    scans: list[LaserScan] = []
    odom_rows: list[tuple[float, float, float, float, float, float, float]] = []
    base_frame = ""
    tfs = _Transforms()
    for done, (topic, number, msg) in enumerate(_messages(reader, p, wanted), 1):
        if topic == scan:
            scans.append(_scan(msg, p, topic, number))
        elif topic == odom:
            pp, stamp = msg.pose.pose, _stamp(msg.header)
            q = pp.orientation
            fields = _pose_values("", stamp, pp.position, q, "pose.pose.position", "pose.pose.orientation")  # fmt: skip
            _check_values(p, topic, number, stamp, fields)
            odom_rows.append((stamp, pp.position.x, pp.position.y, q.x, q.y, q.z, q.w))
            base_frame = base_frame or _frame(msg.child_frame_id)
        else:
            tfs.add(msg, (p, topic, number), static=topic == TF_STATIC_TOPIC)
        if progress and done % _PROGRESS_EVERY == 0:
            progress(done, total)
    if not scans:
        raise LogError(f"no scans: the topic {scan} has no messages", file=p)
    if odom is not None:
        a = np.array(odom_rows, dtype=np.float64).reshape(-1, 7)
        odom_stamps = a[:, 0]
        odom_poses = np.stack([a[:, 1], a[:, 2], _yaw(a[:, 3:7])], axis=1)
        odom_source = f"{odom} ({ODOM_TYPE})"
    elif (found := tfs.odometry()) is not None:
        odom_source, odom_stamps, odom_poses = found
        base_frame = odom_source.rsplit(" ", 1)[-1]
    elif use_tf:
        raise LogError(
            f"--odom-topic {TF_TOPIC}: no odom -> {' or '.join(BASE_FRAMES)} transform on {TF_TOPIC}",
            file=p,
        )
    else:
        odom_stamps, odom_poses, odom_source = np.zeros(0), np.zeros((0, 3)), ""
    laser_offset = _laser_offset(reader, p, topics, tfs, base_frame, scans[0].frame_id, read_tf)
    if progress:
        progress(total, total)
    return RecordedLog(
        path=p,
        scans=scans,
        odom_stamps=odom_stamps,
        odom_poses=odom_poses,
        laser_offset=laser_offset,
        duration=time_span(np.array([s.stamp for s in scans]), odom_stamps),
        scan_source=scan,
        odom_source=odom_source,
    )


def _laser_offset(
    reader: Any,
    p: Path,
    topics: dict[str, str],
    tfs: _Transforms,
    base: str,
    laser: str,
    tf_read: bool,
) -> NDArray[np.float64]:
    """The scan frame's pose in the base frame; /tf is read (until the chain is found)
    only when /tf_static does not give it."""
    bases = [base] if base else list(BASE_FRAMES)
    if not laser or laser in bases:
        return np.zeros(3)

    def lookup() -> Pose2D | None:
        return next((m for b in bases if (m := tfs.mount(b, laser)) is not None), None)

    mount = lookup()
    if mount is None and not tf_read and topics.get(TF_TOPIC) == TF_TYPE:
        for _topic, number, msg in _messages(reader, p, [TF_TOPIC]):
            tfs.add(msg, (p, TF_TOPIC, number), static=False)
            if (mount := lookup()) is not None:
                break
    if mount is None and not base:
        return np.zeros(3)  # no odometry, no base frame: nothing to warn about
    if mount is None:
        warnings.warn(
            BtnavWarning(
                f"no transform from {base} to the scans' frame {laser} on {TF_STATIC_TOPIC} "
                f"or {TF_TOPIC}; the laser is taken at the robot's origin",
                file=p,
            ),
            stacklevel=4,
        )
        return np.zeros(3)
    return mount.as_array()
