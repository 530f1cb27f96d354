"""What the assertion helpers read, from whatever a test has in hand.

A report is a `RunReport` (or `run_mission`'s `RunResult`), its dict, `report.json` or
the run folder holding it, or a navigator (its task's result and its world's contacts).
A tick log is a list of `bt_log.jsonl` records, the file, a run folder, a run's result,
or anything with a `bt_log` (a tree under test, a navigator from `btnav_navigator`).
A trajectory is `trajectory.csv`, a run folder, a run's result, a navigator from
`btnav_navigator`, or an array: (N, 2) or (N, 3) of x, y[, yaw], or trajectory.csv's
columns (t, gt_x, gt_y, gt_yaw, ...).
"""

from __future__ import annotations

import csv
import json
from collections.abc import Sequence
from dataclasses import dataclass
from os import PathLike
from pathlib import Path
from typing import Any

REPORT_FILE, BT_LOG_FILE, TRAJECTORY_FILE = "report.json", "bt_log.jsonl", "trajectory.csv"
#: The task of a report -> the action whose error codes it carries.
TASK_ACTION = {
    "navigate_to_pose": "NavigateToPose",
    "navigate_through_poses": "NavigateThroughPoses",
    "follow_waypoints": "FollowWaypoints",
}


def matches(key: str, node_name: str, node_type: str) -> bool:
    """Whether `key` names a node: its type, its name, or its name's last part (py_trees
    names a node by its parents' names too: `NavigateRecovery.NavigateWithReplanning`)."""
    return key in (node_type, node_name) or node_name.endswith("." + key)


def short_names(pairs: Any) -> list[str]:
    """The names a user would type for (node_name, type) pairs: last name parts and types."""
    return sorted({n.rsplit(".", 1)[-1] for n, _ in pairs} | {t for _, t in pairs})


def _file_in(source: str | PathLike[str], name: str) -> Path:
    path = Path(source)
    if path.is_dir():
        path = path / name
    if not path.is_file():
        raise FileNotFoundError(f"no {name} at {path}")
    return path


def _flush(source: Any) -> None:
    flush = getattr(source, "flush", None)
    if callable(flush):
        flush()


def _is_path(source: Any) -> bool:
    return isinstance(source, str | PathLike)


@dataclass
class ReportView:
    """A report's fields as a dict, and where its run's files are (None if unknown)."""

    fields: dict[str, Any]
    out_dir: Path | None = None
    task_poses: Sequence[Sequence[float]] = ()
    world_file: str | None = None


def read_report(source: Any) -> ReportView:
    """A report from a `RunReport`, a dict, `report.json`, a run folder or a navigator."""
    if _is_path(source):
        path = _file_in(source, REPORT_FILE)
        return ReportView(json.loads(path.read_text()), path.parent)
    if isinstance(source, dict):
        return ReportView(dict(source))
    if hasattr(source, "to_dict"):
        return ReportView(
            source.to_dict(),
            getattr(source, "out_dir", None),
            getattr(source, "task_poses", ()),
            getattr(source, "world_file", None),
        )
    if hasattr(source, "bt_navigator") and hasattr(source, "world"):
        return _navigator_report(source)
    raise TypeError(f"not a report, report.json or run folder: {source!r}")


def _navigator_report(nav: Any) -> ReportView:
    """What a report would say about a navigator's task so far."""
    result = nav.get_result()
    handle = nav.handle
    if handle is None:
        status, code, msg = "not started", None, "no task was sent"
    elif result is None:
        status, code, msg = "running", None, "the task has not ended"
    else:
        status = str(result.outcome)
        code = result.error_code if result.failed else None
        msg = result.error_msg if result.failed else None
    value = result.value if result is not None else None
    goal = handle.goal if handle is not None else None
    poses = getattr(goal, "poses", None) or ([goal.pose] if hasattr(goal, "pose") else [])
    fields = {
        "mission": getattr(getattr(nav, "mission", None), "name", "navigator"),
        "status": status,
        "error_code": code,
        "error_msg": msg,
        "sim_time": nav.now,
        "missed_waypoints": list(getattr(value, "missed_indices", [])),
        "goals": len(poses),
        "task": handle.action if handle is not None else "",
        "collisions": nav.world.collisions,
        "contacts": [c.to_dict() for c in nav.world.contacts],
    }
    poses = [(p.x, p.y, p.yaw) if hasattr(p, "x") else tuple(p) for p in poses]
    return ReportView(fields, getattr(nav, "out_dir", None), poses, nav.world.file)


def read_bt_log(source: Any) -> tuple[list[dict[str, Any]], str]:
    """Tick-log records, and where they came from (for messages)."""
    if isinstance(source, list):
        return source, "the given records"
    if _is_path(source):
        path = _file_in(source, BT_LOG_FILE)
        return _jsonl(path), str(path)
    log = getattr(source, "bt_log_file", None) or getattr(source, "bt_log", None)
    if log is None:
        raise TypeError(f"no tick log in {source!r}")
    _flush(source)
    if isinstance(log, list):
        return log, repr(source)
    return _jsonl(Path(log)), str(log)


def _jsonl(path: Path) -> list[dict[str, Any]]:
    return [json.loads(line) for line in path.read_text().splitlines() if line.strip()]


@dataclass
class Track:
    """Poses over time: t (None when unknown), x, y, yaw (None when unknown), and the source."""

    t: Any
    x: Any
    y: Any
    yaw: Any
    source: str


def read_trajectory(source: Any, which: str = "gt") -> Track:
    """A track from trajectory.csv (its `which` poses: gt, est or odom), a run, or an array."""
    import numpy as np

    if not _is_path(source) and not hasattr(source, "shape") and not isinstance(source, list):
        found = getattr(source, "trajectory_file", None) or getattr(source, "out_dir", None)
        if found is None:
            raise TypeError(f"no trajectory in {source!r}")
        _flush(source)
        source = found
    if _is_path(source):
        path = _file_in(source, TRAJECTORY_FILE)
        with open(path, newline="") as f:
            rows = list(csv.reader(f))
        header, data = rows[0], np.array(rows[1:], dtype=float).reshape(-1, len(rows[0]))
        col = {name: data[:, i] for i, name in enumerate(header)}
        return Track(col["t"], col[f"{which}_x"], col[f"{which}_y"], col[f"{which}_yaw"], str(path))
    arr = np.asarray(source, dtype=float)
    if arr.ndim != 2 or arr.shape[1] < 2:
        raise ValueError(f"a trajectory array is (N, 2+) of x, y[, yaw], got shape {arr.shape}")
    if arr.shape[1] >= 4:  # trajectory.csv's columns: t, gt_x, gt_y, gt_yaw, ...
        return Track(arr[:, 0], arr[:, 1], arr[:, 2], arr[:, 3], "the given array")
    yaw = arr[:, 2] if arr.shape[1] == 3 else None
    return Track(None, arr[:, 0], arr[:, 1], yaw, "the given array")
