"""CARMEN logs (.clf, .log): the text format of the classic 2D SLAM data sets
(Intel Research Lab, FR079, FR101, CSAIL, ACES, MIT Killian Court).

One message a line, its name first; FLASER and ROBOTLASER1 (lasers), ODOM and PARAM
(range limit, FLASER geometry and mount) are read, every other message is skipped. An
FLASER scan without a resolution PARAM is read at CARMEN's 1 degree default, not the
pi/179 the ROS bags of these logs declare (it bends Intel's corridors). Odometry is the
ODOM lines interpolated at each scan when there are any. Errors name the line and count
fields from 1 at the message name, as awk does. The fields in full, and why:
docs/decisions/0057.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from btnav.core import fmath
from btnav.core.files import read_bytes
from btnav.core.geometry import angle_diff, normalize_angle
from btnav.core.messages import LaserScan

from .recorded_log import (
    CARMEN_MESSAGES,
    LogError,
    Progress,
    RecordedLog,
    implausible,
    rep117_ranges,
    time_span,
    why_implausible,
)

#: The maximum range of a FLASER laser when no PARAM line gives it (SICK LMS: 81.9 m).
DEFAULT_MAX_RANGE = 80.0
FRAME_ID = "laser"

FORMATS = {
    "FLASER": "FLASER n r1..rn x y theta odom_x odom_y odom_theta ipc_timestamp host "
    "logger_timestamp",
    "ROBOTLASER1": "ROBOTLASER1 laser_type start_angle field_of_view angular_resolution "
    "maximum_range accuracy remission_mode n r1..rn m rem1..remm laser_x laser_y "
    "laser_theta robot_x robot_y robot_theta tv rv forward_safety_dist side_safety_dist "
    "turn_axis timestamp host logger_timestamp",
    "ODOM": "ODOM x y theta tv rv accel timestamp host logger_timestamp",
}


class _Lines:
    """The log's lines and how to point at one of them in an error."""

    def __init__(self, path: Path, text: str) -> None:
        self.path = path
        self.lines = text.replace("\r\n", "\n").split("\n")
        self.ends_in_newline = text.endswith("\n")
        if self.lines and self.lines[-1] == "":
            self.lines.pop()
        self.last = next(
            (i for i in range(len(self.lines) - 1, -1, -1) if self.lines[i].strip()), -1
        )

    def error(self, i: int, message: str, *, cut: bool = False) -> LogError:
        """A LogError at line index `i`; a line cut short at the end says "truncated"."""
        if cut and i == self.last:
            end = "" if self.ends_in_newline else " (the file ends mid-line)"
            message = f"truncated last line{end}: {message}"
        return LogError(message, file=self.path, line=i + 1)

    def group(self) -> dict[str, list[int]]:
        """Line indices by message name (comments and blank lines left out)."""
        out: dict[str, list[int]] = {}
        for i, line in enumerate(self.lines):
            words = line.split(None, 1)
            if words and not words[0].startswith("#"):
                out.setdefault(words[0], []).append(i)
        return out

    def field_counts(self, idx: list[int]) -> NDArray[np.int64]:
        """Whitespace-separated fields on each line; counting single spaces is 30x
        faster than splitting, so only lines with other whitespace are split."""
        lines = self.lines
        return np.fromiter(
            (
                len(s.split()) if ("  " in s or "\t" in s or s != s.strip()) else s.count(" ") + 1
                for s in (lines[i] for i in idx)
            ),
            dtype=np.int64,
            count=len(idx),
        )

    def field(self, i: int, k: int) -> str:
        return self.lines[i].split(None, k + 1)[k]

    def numbers(self, tag: str, idx: list[int], cols: NDArray[np.int64]) -> NDArray[np.float64]:
        """Fields `cols` of lines `idx` (all with at least max(cols)+1 fields) as a
        float array (len(idx), len(cols)); a field that is not a number is located."""
        if not idx:
            return np.zeros((0, len(cols)))
        try:
            return np.loadtxt(
                [self.lines[i] for i in idx],
                usecols=cols.tolist(),
                dtype=np.float64,
                comments=None,
                ndmin=2,
            )
        except ValueError:
            pass
        for i in idx:  # the error path only: find the first line, then the field
            try:
                np.loadtxt([self.lines[i]], usecols=cols.tolist(), comments=None)
                continue
            except ValueError:
                pass
            words = self.lines[i].split()
            bad = next((k for k in cols.tolist() if not _is_number(words[k])), None)
            if bad is None:
                raise self.error(i, f"{tag}: a field is not a number as CARMEN writes one")
            raise self.error(
                i,
                f"{tag}: field {bad + 1} '{words[bad]}' is not a number",
                cut=len(words) == bad + 1,
            )
        raise self.error(idx[0], f"{tag}: cannot read the numbers of these lines")

    def check_values(
        self,
        tag: str,
        idx: list[int],
        v: NDArray[np.float64],
        cols: NDArray[np.int64],
        checks: dict[int, tuple[str, str]],
    ) -> LogError | None:
        """The error for the first field, in file order, that `implausible` flags: `v` holds
        fields `cols` of lines `idx`, `checks` maps a column of `v` to (name, kind).
        Returned, not raised, so a reader of several blocks reports the earliest line."""
        first: tuple[int, int, str, str] | None = None
        for j, (name, kind) in checks.items():
            bad = np.flatnonzero(implausible(v[:, j], kind))
            if len(bad):
                here = (idx[int(bad[0])], int(cols[j]), name, kind)
                first = here if first is None or here[:2] < first[:2] else first
        if first is None:
            return None
        i, k, name, kind = first
        return self.error(
            i, f"{tag}: field {k + 1} ({name}) {why_implausible(self.field(i, k), kind)}"
        )

    def counts(
        self, tag: str, idx: list[int], k: int | NDArray[np.int64], what: str
    ) -> NDArray[np.int64]:
        """Field `k` (one for all lines, or one per line) of each line as a count of
        readings or remissions: a whole number >= 0."""
        ks = np.broadcast_to(np.asarray(k, dtype=np.int64), (len(idx),)).tolist()
        fields = [self.field(i, kk) for i, kk in zip(idx, ks, strict=True)]
        values = np.empty(len(idx))
        try:
            values[:] = np.array(fields, dtype=np.float64)
        except ValueError:
            values[:] = [float(f) if _is_number(f) else np.nan for f in fields]
        bad = np.flatnonzero(~((values >= 0) & (values == np.floor(values)) & (values < 1e6)))
        if len(bad):
            j = int(bad[0])
            raise self.error(
                idx[j],
                f"{tag}: the {what} count (field {ks[j] + 1}) '{fields[j]}' is not a whole number",
            )
        return values.astype(np.int64)

    def check_lengths(
        self,
        tag: str,
        idx: list[int],
        have: NDArray[np.int64],
        need: NDArray[np.int64],
        what: Callable[[int], str],
    ) -> None:
        """Each line has `need` fields up to its timestamp, then at most host and
        logger_timestamp; fewer is "too few fields", more (or a number where the host
        should be) means the announced count does not match the line."""
        short = have < need
        long = have > need + 2
        for j in np.flatnonzero((have > need) & ~long):
            extra = int(have[j] - need[j])  # the host is the first field after the timestamp
            long[j] = _is_number(self.lines[idx[j]].rsplit(None, extra)[1])
        bad = np.flatnonzero(short | long)
        if not len(bad):
            return
        j = int(bad[0])
        i, n, h = idx[j], int(need[j]), int(have[j])
        fmt = FORMATS[tag]
        if short[j]:
            raise self.error(
                i,
                f"{tag}: too few fields: {what(j)} needs {n} fields up to the timestamp, "
                f"the line has {h} (format: {fmt})",
                cut=True,
            )
        raise self.error(
            i,
            f"{tag}: the count does not match the values: {what(j)} has {n} fields up to "
            f"the timestamp, then at most a host name and a logger timestamp, but the line "
            f"has {h} fields (format: {fmt})",
        )


def _raise_first(errors: list[LogError | None]) -> None:
    """Raise the error of the earliest line, if any."""
    found = [e for e in errors if e is not None]
    if found:
        raise min(found, key=lambda e: e.line or 0)


def _pose_checks(at: int, prefix: str) -> dict[int, tuple[str, str]]:
    """Checks of a pose `x y theta` whose x is column `at`."""
    return {
        at: (f"{prefix}x", "position"),
        at + 1: (f"{prefix}y", "position"),
        at + 2: (f"{prefix}theta", "yaw"),
    }


def _is_number(s: str) -> bool:
    try:
        float(s)
    except ValueError:
        return False
    return True


def _flaser(log: _Lines, idx: list[int]) -> list[tuple[list[int], int, NDArray[np.float64]]]:
    """FLASER blocks of one beam count n: (line indices, n, rows of r1..rn, x y theta,
    odom x y theta, timestamp)."""
    have = log.field_counts(idx)
    short = np.flatnonzero(have < 2)
    if len(short):
        i = idx[short[0]]
        raise log.error(i, "FLASER: too few fields: no reading count", cut=True)
    n = log.counts("FLASER", idx, 1, "reading")
    log.check_lengths("FLASER", idx, have, n + 9, lambda j: f"FLASER with {n[j]} readings")
    blocks, errors = [], []
    for beams in np.unique(n).tolist():
        sel = [idx[j] for j in np.flatnonzero(n == beams)]
        cols = np.arange(2, beams + 9)
        v = log.numbers("FLASER", sel, cols)
        checks = _pose_checks(beams, "") | _pose_checks(beams + 3, "odom_")
        checks[beams + 6] = ("ipc_timestamp", "stamp")
        errors.append(log.check_values("FLASER", sel, v, cols, checks))
        blocks.append((sel, beams, v))
    _raise_first(errors)
    return blocks


def _robotlaser(
    log: _Lines, idx: list[int]
) -> list[tuple[list[int], int, int, NDArray[np.float64]]]:
    """ROBOTLASER1 blocks of one (n, m): (line indices, n, m, rows of the 7 config
    fields, r1..rn, rem1..remm, laser pose, robot pose, 5 motion fields, timestamp)."""
    tag = "ROBOTLASER1"
    have = log.field_counts(idx)
    short = np.flatnonzero(have < 10)
    if len(short):
        i = idx[short[0]]
        raise log.error(i, f"{tag}: too few fields: the line has {have[short[0]]}", cut=True)
    n = log.counts(tag, idx, 8, "reading")
    short = np.flatnonzero(have < n + 10)
    if len(short):
        j = short[0]
        raise log.error(
            idx[j], f"{tag}: too few fields for {n[j]} readings and a remission count", cut=True
        )
    m = log.counts(tag, idx, 9 + n, "remission")
    log.check_lengths(
        tag, idx, have, n + m + 22, lambda j: f"{tag} with {n[j]} readings and {m[j]} remissions"
    )
    blocks, errors = [], []
    for beams, rems in sorted({(int(a), int(b)) for a, b in zip(n, m, strict=True)}):
        sel = [idx[j] for j in np.flatnonzero((n == beams) & (m == rems))]
        cols = np.concatenate(
            [np.arange(1, 8), np.arange(9, 9 + beams), np.arange(10 + beams, 22 + beams + rems)]
        )
        v = log.numbers(tag, sel, cols)
        tail = 7 + beams + rems  # laser_x: the fields after the remissions
        checks = {1: ("start_angle", "yaw"), 2: ("field_of_view", "yaw")}
        checks |= {3: ("angular_resolution", "yaw"), tail + 11: ("timestamp", "stamp")}
        checks |= _pose_checks(tail, "laser_") | _pose_checks(tail + 3, "robot_")
        errors.append(log.check_values(tag, sel, v, cols, checks))
        blocks.append((sel, beams, rems, v))
    _raise_first(errors)
    return blocks


def _params(log: _Lines, idx: list[int]) -> dict[str, float]:
    """The PARAM values this reader uses, as numbers."""
    used = {
        "robot_front_laser_max",
        "laser_front_laser_fov",
        "laser_front_laser_resolution",
        "robot_frontlaser_offset",
        "robot_frontlaser_side_offset",
        "robot_frontlaser_angular_offset",
    }
    out: dict[str, float] = {}
    for i in idx:
        words = log.lines[i].split()
        if len(words) >= 2 and words[1] in used:
            if len(words) < 3 or not _is_number(words[2]):
                shown = f"'{words[2]}'" if len(words) >= 3 else "nothing"
                raise log.error(i, f"PARAM {words[1]}: expected a number, got {shown}", cut=True)
            out[words[1]] = float(words[2])
    return out


def _flaser_spacing(fov: float, n: int) -> float:
    """CARMEN's beam spacing when no PARAM gives it: a laser resolution (1, 0.5 or 0.25
    degrees) when the beams are the field of view at that resolution with the last beam
    left out (180 beams on 180 degrees: -90 to +89, as CARMEN and GMapping read them),
    else the beams span the whole field of view."""
    if n > 1 and any(math.isclose(math.degrees(fov) / n, r) for r in (1.0, 0.5, 0.25)):
        return fov / n
    return fov / (n - 1) if n > 1 else 0.0


def _scans_from_flaser(
    blocks: list[tuple[list[int], int, NDArray[np.float64]]], params: dict[str, float]
) -> tuple[list[tuple[int, LaserScan]], NDArray[np.float64], NDArray[np.float64]]:
    """(line, scan) pairs, the odometry poses and stamps of the FLASER lines."""
    max_range = params.get("robot_front_laser_max", DEFAULT_MAX_RANGE)
    fov = math.radians(params.get("laser_front_laser_fov", 180.0))
    res = params.get("laser_front_laser_resolution")
    scans: list[tuple[int, LaserScan]] = []
    odom, stamps = [], []
    for lines, n, v in blocks:
        inc = math.radians(res) if res is not None else _flaser_spacing(fov, n)
        a_min = -0.5 * fov
        ranges = rep117_ranges(v[:, :n], 0.0, max_range)
        odom.append(v[:, n + 3 : n + 6])
        stamps.append(v[:, n + 6])
        for j, line in enumerate(lines):
            scan = LaserScan(
                stamp=float(v[j, n + 6]),
                frame_id=FRAME_ID,
                angle_min=a_min,
                angle_max=a_min + (n - 1) * inc,
                angle_increment=inc,
                range_min=0.0,
                range_max=max_range,
                ranges=ranges[j],
            )
            scans.append((line, scan))
    return scans, np.concatenate(odom), np.concatenate(stamps)


def _scans_from_robotlaser(
    blocks: list[tuple[list[int], int, int, NDArray[np.float64]]],
) -> tuple[
    list[tuple[int, LaserScan]], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]
]:
    """(line, scan) pairs, the robot poses, stamps and laser offsets of the ROBOTLASER1 lines."""
    scans: list[tuple[int, LaserScan]] = []
    robot, stamps, offsets = [], [], []
    for lines, n, m, v in blocks:
        start, _fov, res, max_range = v[:, 1], v[:, 2], v[:, 3], v[:, 4]
        ranges = rep117_ranges(v[:, 7 : 7 + n], 0.0, max_range[:, None])
        rem = v[:, 7 + n : 7 + n + m].astype(np.float32)
        tail = v[:, 7 + n + m :]
        laser, pose = tail[:, 0:3], tail[:, 3:6]
        robot.append(pose)
        stamps.append(tail[:, 11])
        offsets.append(_offsets(pose, laser))
        for j, line in enumerate(lines):
            scan = LaserScan(
                stamp=float(tail[j, 11]),
                frame_id=FRAME_ID,
                angle_min=float(start[j]),
                angle_max=float(start[j] + (n - 1) * res[j]),
                angle_increment=float(res[j]),
                range_min=0.0,
                range_max=float(max_range[j]),
                ranges=ranges[j],
                intensities=rem[j] if m == n else np.zeros(0, np.float32),
            )
            scans.append((line, scan))
    return scans, np.concatenate(robot), np.concatenate(stamps), np.concatenate(offsets)


def _offsets(robot: NDArray[np.float64], laser: NDArray[np.float64]) -> NDArray[np.float64]:
    """The laser's pose in the robot frame, robot⁻¹ ⊕ laser, row by row."""
    s, c = fmath.sincos(robot[:, 2])
    dx, dy = laser[:, 0] - robot[:, 0], laser[:, 1] - robot[:, 1]
    return np.stack([c * dx + s * dy, c * dy - s * dx, angle_diff(laser[:, 2], robot[:, 2])], 1)


def _median_offset(offsets: NDArray[np.float64]) -> NDArray[np.float64]:
    """One offset for the log: the median, the yaw taken around the first line's."""
    yaw0 = offsets[0, 2]
    yaw = yaw0 + np.median(angle_diff(offsets[:, 2], yaw0))
    return np.array([np.median(offsets[:, 0]), np.median(offsets[:, 1]), normalize_angle(yaw)])


def read_carmen(path: str | Path, *, progress: Progress | None = None) -> RecordedLog:
    """Read a CARMEN log: its FLASER or ROBOTLASER1 scans and its odometry."""
    p = Path(path)
    log = _Lines(p, read_bytes(p, error_cls=LogError, what="log").decode("latin-1"))
    groups = log.group()
    total = sum(len(groups.get(t, [])) for t in ("FLASER", "ROBOTLASER1", "ODOM"))
    if progress:
        progress(0, total)
    params = _params(log, groups.get("PARAM", []))
    if groups.get("ROBOTLASER1"):
        idx = groups["ROBOTLASER1"]
        pairs, odom, scan_stamps, offsets = _scans_from_robotlaser(_robotlaser(log, idx))
        laser_offset, source = _median_offset(offsets), "ROBOTLASER1"
    elif groups.get("FLASER"):
        idx = groups["FLASER"]
        pairs, odom, scan_stamps = _scans_from_flaser(_flaser(log, idx), params)
        laser_offset = np.array(
            [
                params.get("robot_frontlaser_offset", 0.0),
                params.get("robot_frontlaser_side_offset", 0.0),
                normalize_angle(params.get("robot_frontlaser_angular_offset", 0.0)),
            ]
        )
        source = "FLASER"
    else:
        names = sorted(groups, key=lambda t: (t not in CARMEN_MESSAGES, -len(groups[t])))
        found = ", ".join(f"{t} {len(groups[t])}" for t in names[:6]) or "nothing"
        found += ", ..." if len(names) > 6 else ""
        raise LogError(
            f"no scans: a CARMEN log needs FLASER or ROBOTLASER1 lines (found: {found})", file=p
        )
    if progress:
        progress(len(idx), total)
    pairs.sort(key=lambda ls: ls[0])  # file order; RecordedLog then sorts by stamp
    if groups.get("ODOM"):
        odom_idx = groups["ODOM"]
        have = log.field_counts(odom_idx)
        log.check_lengths("ODOM", odom_idx, have, np.full(len(odom_idx), 8), lambda j: "ODOM")
        cols = np.arange(1, 8)
        v = log.numbers("ODOM", odom_idx, cols)
        checks = _pose_checks(0, "") | {6: ("timestamp", "stamp")}
        _raise_first([log.check_values("ODOM", odom_idx, v, cols, checks)])
        odom_stamps, odom_poses, odom_source = v[:, 6], v[:, 0:3], "ODOM lines"
    else:
        odom_stamps, odom_poses = scan_stamps, odom
        odom_source = f"{source} odometry fields"
    if progress:
        progress(total, total)
    return RecordedLog(
        path=p,
        scans=[s for _, s in pairs],
        odom_stamps=odom_stamps,
        odom_poses=odom_poses,
        laser_offset=laser_offset,
        duration=time_span(scan_stamps, odom_stamps),
        scan_source=source,
        odom_source=odom_source,
    )
