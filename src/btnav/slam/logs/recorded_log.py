"""A recorded 2D laser log, whatever it was recorded with: scans plus odometry.

Offline SLAM (`btnav slam LOG`) replays a robot's past the way slam_toolbox replays a
bag: each scan, with the odometry pose at the scan's time as the motion prior. The
readers (`carmen`, `rosbag`) differ only in how they find those two streams, so they
all return this one `RecordedLog`, and every problem with the file is a `LogError`
that names the file and the line (text logs) or the topic and message (bags).

Ranges follow btnav's `LaserScan` contract (REP-117) whatever the log wrote: a
reading at or above the sensor's maximum range is `+inf` (no return), one below its
minimum range (or zero, CARMEN's and many drivers' "no reading") is NaN (invalid).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from os import PathLike
from pathlib import Path
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from btnav.core.errors import BtnavError
from btnav.core.geometry import angle_diff, normalize_angle
from btnav.core.messages import LaserScan

#: What `progress(done, total)` is called with while a log is read.
Progress = Callable[[int, int], None]

#: Message names that start a CARMEN log line (to recognise a CARMEN log by content).
CARMEN_MESSAGES = frozenset(
    {"PARAM", "SYNC", "ODOM", "TRUEPOS", "FLASER", "RLASER", "LASER3", "LASER4", "LASER5"}
    | {f"{kind}{i}" for kind in ("RAWLASER", "ROBOTLASER") for i in range(1, 6)}
    | {"NMEAGGA", "NMEARMC", "SONAR", "BUMPER", "SCANMARK", "POSITIONLASER", "GPSNMEA"}
)

CARMEN_SUFFIXES = frozenset({".clf", ".log", ".carmen", ".gfs"})
BAG_SUFFIXES = frozenset({".bag", ".db3", ".mcap"})


class LogError(BtnavError):
    """A recorded log that cannot be read: the message names the file and the line
    (CARMEN) or the topic and message (bags)."""


#: The largest |x|, |y| (m) a log's pose may hold: a million kilometres, beyond the
#: Moon, past any UTM easting or northing (< 10,000 km); float64 still resolves 0.1 um
#: there. A larger value is a corrupt field, and the maps overflow their int64 cells.
MAX_POSITION = 1e9
#: The largest |yaw| (rad): 160,000 turns of unwrapped odometry yaw, resolved to 1e-10 rad.
MAX_YAW = 1e6
#: The largest |stamp| (s): 3,000 years from 1970 either way, still resolved to 15 us.
MAX_STAMP = 1e11
#: Each kind of value a reader checks: (largest magnitude, unit).
LIMITS = {
    "position": (MAX_POSITION, "m"),
    "yaw": (MAX_YAW, "rad"),
    "stamp": (MAX_STAMP, "s"),
    "quaternion": (MAX_POSITION, ""),  # any finite component: the yaw is normalised
}


def implausible(values: ArrayLike, kind: str | Sequence[str]) -> NDArray[np.bool_]:
    """Which `values` no log can hold as a `kind` (see `LIMITS`; one kind for all, or one
    per value): not finite, or beyond the limit. A range reading is never checked here:
    inf and NaN are valid ones."""
    limit = LIMITS[kind][0] if isinstance(kind, str) else [LIMITS[k][0] for k in kind]
    return ~(np.abs(np.asarray(values, dtype=np.float64)) <= limit)


def why_implausible(text: str, kind: str) -> str:
    """Why the value written `text` is not a `kind` (for a value `implausible` flagged)."""
    limit, unit = LIMITS[kind]
    try:
        finite = np.isfinite(float(text))
    except ValueError:
        finite = False
    if not finite:
        return f"'{text}' is not a finite number"
    unit = f" {unit}" if unit else ""
    return f"'{text}' is beyond +-{limit:g}{unit}, more than any log holds (a corrupt field?)"


@dataclass
class RecordedLog:
    """The scans of a recorded log and the odometry to place them.

    `odom_stamps` is sorted with one pose per stamp (the readers drop repeated and
    out-of-order duplicates); scans are sorted by stamp. A log may have no odometry
    (`has_odometry` is False, e.g. a laser-only bag): `odom_at` then raises.
    """

    path: Path
    scans: list[LaserScan]
    odom_stamps: NDArray[np.float64]
    odom_poses: NDArray[np.float64]
    laser_offset: NDArray[np.float64] = field(default_factory=lambda: np.zeros(3))
    duration: float = 0.0
    #: Where the scans came from: `FLASER`, `ROBOTLASER1`, or the bag topic.
    scan_source: str = ""
    #: Where the odometry came from: `ODOM lines`, a topic, or `/tf odom -> base_link`.
    odom_source: str = ""

    def __post_init__(self) -> None:
        self.path = Path(self.path)
        stamps = np.asarray(self.odom_stamps, dtype=np.float64).reshape(-1)
        poses = np.asarray(self.odom_poses, dtype=np.float64).reshape(-1, 3)
        if len(stamps) != len(poses):
            raise ValueError(f"{len(stamps)} odometry stamps but {len(poses)} poses")
        self.odom_stamps, self.odom_poses = _clean_odometry(stamps, poses)
        self.laser_offset = np.asarray(self.laser_offset, dtype=np.float64).reshape(3)
        order = np.argsort(self.scan_stamps, kind="stable")
        if np.any(order != np.arange(len(order))):
            self.scans = [self.scans[i] for i in order]

    @property
    def scan_stamps(self) -> NDArray[np.float64]:
        return np.array([s.stamp for s in self.scans], dtype=np.float64)

    @property
    def has_odometry(self) -> bool:
        return len(self.odom_stamps) > 0

    def odom_at(self, t: float | ArrayLike) -> NDArray[np.float64]:
        """The odometry pose at time(s) `t`: (3,) for a number, (M, 3) for an array.

        Linear in x, y and along the shorter arc in yaw between the two poses around
        `t`, as a TF lookup interpolates; before the first or after the last pose the
        end pose (a log's first scan often comes a few ms before its first odometry).
        """
        stamps, poses = self.odom_stamps, self.odom_poses
        if not len(stamps):
            raise LogError("this log has no odometry to place its scans", file=self.path)
        tt = np.asarray(t, dtype=np.float64)
        scalar = tt.ndim == 0
        tt = tt.reshape(-1)
        if len(stamps) == 1:
            out = np.repeat(poses, len(tt), axis=0)
        else:
            i = np.clip(np.searchsorted(stamps, tt, side="right") - 1, 0, len(stamps) - 2)
            t0, t1 = stamps[i], stamps[i + 1]
            f = np.clip((tt - t0) / (t1 - t0), 0.0, 1.0)
            p0, p1 = poses[i], poses[i + 1]
            out = np.empty((len(tt), 3))
            out[:, 0] = p0[:, 0] + f * (p1[:, 0] - p0[:, 0])
            out[:, 1] = p0[:, 1] + f * (p1[:, 1] - p0[:, 1])
            out[:, 2] = normalize_angle(p0[:, 2] + f * angle_diff(p1[:, 2], p0[:, 2]))
            out[tt >= stamps[-1]] = poses[-1]  # exact at the end, not p0 + 1 * (p1 - p0)
        return out[0] if scalar else out


def _clean_odometry(
    stamps: NDArray[np.float64], poses: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Sorted by time, the first pose of each stamp kept, yaws in (-pi, pi]:
    interpolation needs strictly increasing stamps, and real logs repeat some."""
    if not len(stamps):
        return np.zeros(0), np.zeros((0, 3))
    order = np.argsort(stamps, kind="stable")
    stamps, poses = stamps[order], poses[order]
    keep = np.ones(len(stamps), dtype=bool)
    keep[1:] = stamps[1:] > stamps[:-1]
    poses = poses[keep].copy()
    poses[:, 2] = normalize_angle(poses[:, 2])
    return stamps[keep].copy(), poses


def rep117_ranges(
    ranges: ArrayLike, range_min: ArrayLike, range_max: ArrayLike
) -> NDArray[np.float32]:
    """Ranges as btnav's `LaserScan` wants them: >= range_max is +inf (no return),
    below range_min or not above zero NaN (invalid); infinities and NaN as given.
    The limits broadcast against the ranges (one per row of a (scans, beams) array)."""
    r = np.array(ranges, dtype=np.float32)
    finite = np.isfinite(r)
    lo = np.asarray(range_min, dtype=np.float32)
    hi = np.asarray(range_max, dtype=np.float32)
    r[finite & (r >= hi)] = np.inf
    r[finite & ((r < lo) | (r <= 0.0))] = np.nan
    return r


def time_span(*stamps: NDArray[np.float64]) -> float:
    """Seconds from the first to the last of all the given stamps (0 when there are none)."""
    full = [s for s in stamps if len(s)]
    if not full:
        return 0.0
    return float(max(s.max() for s in full) - min(s.min() for s in full))


def log_kind(path: Path) -> Literal["carmen", "rosbag"]:
    """Which reader a path needs: by its magic bytes, then its suffix, then its first line."""
    if path.is_dir():
        return "rosbag"
    try:
        with path.open("rb") as fh:
            head = fh.read(4096)
    except FileNotFoundError:
        raise LogError("log not found", file=path) from None
    except OSError as exc:
        raise LogError(f"cannot read: {exc.strerror or exc}", file=path) from None
    if head.startswith((b"#ROSBAG", b"SQLite format 3\x00", b"\x89MCAP")):
        return "rosbag"
    suffix = path.suffix.lower()
    if suffix in BAG_SUFFIXES:
        return "rosbag"
    if suffix in CARMEN_SUFFIXES:
        return "carmen"
    for line in head.decode("latin-1").splitlines():
        words = line.split(None, 1)
        if not words or words[0].startswith("#"):
            continue
        if words[0] in CARMEN_MESSAGES:
            return "carmen"
        break
    raise LogError(
        "not a log btnav can read: expected a CARMEN log (.clf, .log: lines starting "
        "FLASER, ROBOTLASER1, ODOM, ...) or a ROS bag (.bag, a rosbag2 folder, .db3, .mcap)",
        file=path,
    )


def read_log(
    path: str | PathLike[str],
    *,
    scan_topic: str | None = None,
    odom_topic: str | None = None,
    progress: Progress | None = None,
) -> RecordedLog:
    """Read a CARMEN log or a ROS 1 / ROS 2 bag (see `log_kind`) into a `RecordedLog`.

    `scan_topic` and `odom_topic` choose among a bag's topics (`--scan-topic`,
    `--odom-topic`); a CARMEN log has one laser and one odometry, so naming a topic
    for it is an error. `progress(done, total)` is called now and then while reading.
    """
    p = Path(path)
    if log_kind(p) == "rosbag":
        from .rosbag import read_rosbag

        return read_rosbag(p, scan_topic=scan_topic, odom_topic=odom_topic, progress=progress)
    if scan_topic is not None or odom_topic is not None:
        flag = "--scan-topic" if scan_topic is not None else "--odom-topic"
        raise LogError(f"{flag} names a bag topic, but this is a CARMEN log", file=p)
    from .carmen import read_carmen

    return read_carmen(p, progress=progress)
