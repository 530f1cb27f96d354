"""Assertions on a run whose failure message says what happened, so a user can act on it.

- `assert_reached(report)`: the task succeeded and no waypoint was missed; else the
  status, Nav2's error code (with its name) and message, each missed waypoint and its
  pose, where the robot ended, and the run folder.
- `assert_no_collisions(report)`: no contact; else each one: when, where the robot was,
  and what it hit (the world file's item and line).
- `assert_node_status(bt_log, "ComputePathToPose", "SUCCESS")`: the node (by name or
  type) had that status at least once (or exactly `times` times, or `last`); else the
  statuses it did have, with their times, or the nodes the log has.
- `assert_within(trajectory, pose, tol)`: the robot came within `tol` m of `pose` (and
  `yaw_tol` of its yaw); else the closest approach, when, and the pose then.

Each takes what a test has in hand (see `records`).
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Sequence
from typing import Any

from ..core import fmath
from .records import (
    TASK_ACTION,
    ReportView,
    matches,
    read_bt_log,
    read_report,
    read_trajectory,
    short_names,
)

NODE_STATUSES = ("IDLE", "RUNNING", "SUCCESS", "FAILURE")


def _pose_text(pose: Sequence[float]) -> str:
    return "(" + ", ".join(f"{v:.2f}" for v in pose) + ")"


def _folder_line(view: ReportView) -> str:
    return f"\n  run folder: {view.out_dir}" if view.out_dir is not None else ""


def error_code_text(code: int | None, task: str = "") -> str:
    """`104 (FollowPath PATIENCE_EXCEEDED)`: the code, and the action and name it stands for."""
    if code is None:
        return "none"
    from ..core.error_codes import ERROR_CODES

    tables = list(ERROR_CODES.items())
    action = TASK_ACTION.get(task)
    if action in ERROR_CODES:  # the task's own table first (its 9xx codes)
        tables.insert(0, (action, ERROR_CODES[action]))
    for name, table in tables:
        for member in table:
            if member.value == code and (code >= 100 or name == action):
                return f"{code} ({name} {member.name})"
    return str(code)


def _last_pose(view: ReportView) -> str | None:
    if view.out_dir is None:
        return None
    try:
        track = read_trajectory(view.out_dir)
    except (FileNotFoundError, TypeError, ValueError):
        return None
    if len(track.x) == 0:
        return None
    return _pose_text((track.x[-1], track.y[-1], track.yaw[-1]))


def assert_reached(report: Any) -> None:
    """The task succeeded and every waypoint was reached."""
    view = read_report(report)
    f = view.fields
    missed = list(f.get("missed_waypoints") or [])
    if f.get("status") == "succeeded" and not missed:
        return
    lines = [f"{f.get('mission', 'the run')} did not reach its goal: status {f.get('status')}"]
    if f.get("error_code") is not None:
        lines.append(
            f"  error code {error_code_text(f['error_code'], f.get('task', ''))}: "
            f"{f.get('error_msg') or '(no message)'}"
        )
    elif f.get("error_msg"):
        lines.append(f"  {f['error_msg']}")
    poses = list(view.task_poses)
    if poses and not missed:
        shown = ", ".join(_pose_text(p) for p in poses)
        lines.append(f"  task: {f.get('task') or 'goal'} {shown}")
    if missed:
        shown = [f"{i} {_pose_text(poses[i])}" if i < len(poses) else str(i) for i in missed]
        of = f" of {f['goals']}" if f.get("goals") else ""
        lines.append(f"  missed waypoints{of}: {', '.join(shown)}")
    where = f"after {f.get('sim_time', 0.0):.1f} s of sim time"
    last = _last_pose(view)
    if last is not None:
        where += f", the robot last at {last}"
    lines.append(f"  {where}")
    extras = [
        f"{f[k]} {k}" for k in ("collisions", "recoveries", "replans") if f.get(k) is not None
    ]
    if extras:
        lines.append("  " + ", ".join(extras))
    raise AssertionError("\n".join(lines) + _folder_line(view))


def assert_no_collisions(report: Any) -> None:
    """The robot touched nothing (the report's `contacts`, or a navigator's world's)."""
    view = read_report(report)
    contacts = list(view.fields.get("contacts") or [])
    count = int(view.fields.get("collisions") or len(contacts))
    if count == 0 and not contacts:
        return
    name = view.fields.get("mission", "the run")
    lines = [f"{name}: the robot touched something {count} time{'s' if count != 1 else ''}:"]
    for c in contacts:
        what = f"{c['hit']}s[{c['index']}]"
        if c.get("hit") == "obstacle" and c.get("kind"):
            what += f" ({c['kind']})"
        place = ""
        if c.get("line") is not None:
            place = f", line {c['line']}" + (f" of {view.world_file}" if view.world_file else "")
        lines.append(f"  t={c['time']:.2f} s, robot at {_pose_text(c['pose'])}: hit {what}{place}")
    raise AssertionError("\n".join(lines) + _folder_line(view))


def assert_node_status(
    bt_log: Any, node: str, status: str, *, times: int | None = None, last: bool = False
) -> None:
    """The node (by name or type) had `status`: at least once, exactly `times` times, or
    (with `last`) as its final status in the log."""
    from ..core.errors import UnknownNameError
    from ..core.suggest import best_match

    if status not in NODE_STATUSES:
        raise UnknownNameError(
            f"unknown status '{status}'; statuses: {', '.join(NODE_STATUSES)}",
            suggestion=best_match(status, NODE_STATUSES),
        )
    records, where = read_bt_log(bt_log)
    mine = [r for r in records if matches(node, r["node_name"], r["type"])]
    if not mine:
        names = short_names((r["node_name"], r["type"]) for r in records)
        near = best_match(node, names)
        hint = f" (did you mean '{near}'?)" if near else ""
        raise AssertionError(
            f"no node '{node}' in the tick log{hint} (a node that never ticked is not there); "
            f"it has: {', '.join(names) or 'nothing'}"
            f"\n  tick log: {where}"
        )
    by_uid: dict[int, list[dict[str, Any]]] = {}
    for r in mine:
        by_uid.setdefault(int(r["uid"]), []).append(r)
    if any(_holds(rs, status, times, last) for rs in by_uid.values()):
        return
    if last:
        want = f"did not end {status}"
    elif times is not None:
        want = f"was not {status} exactly {times} time{'s' if times != 1 else ''}"
    else:
        want = f"was never {status}"
    lines = [f"'{node}' {want}; its statuses:"]
    for uid, rs in sorted(by_uid.items()):
        counts = Counter(r["current_status"] for r in rs)
        summary = ", ".join(f"{s} x{n}" for s, n in counts.items())
        end = rs[-1]
        lines.append(
            f"  {rs[0]['node_name']} ({rs[0]['type']}, uid {uid}): {summary}; "
            f"last {end['current_status']} at t={end['timestamp']:.2f} s"
        )
        firsts = [
            f"first {s} at t={next(r['timestamp'] for r in rs if r['current_status'] == s):.2f} s"
            for s in counts
            if s != "IDLE"
        ]
        if firsts:
            lines.append("    " + ", ".join(firsts))
    lines.append(f"  tick log: {where}")
    raise AssertionError("\n".join(lines))


def _holds(records: list[dict[str, Any]], status: str, times: int | None, last: bool) -> bool:
    statuses = [r["current_status"] for r in records]
    if last:
        non_idle = [s for s in statuses if s != "IDLE"] or statuses
        return bool(non_idle) and non_idle[-1] == status
    count = statuses.count(status)
    return count == times if times is not None else count > 0


def assert_within(
    trajectory: Any,
    pose: Sequence[float],
    tol: float = 0.25,
    *,
    yaw_tol: float | None = None,
    which: str = "gt",
) -> None:
    """The robot came within `tol` m of `pose` (x, y[, yaw]); with `yaw_tol` and a yaw,
    also heading within `yaw_tol` rad there. `which` picks trajectory.csv's poses:
    gt (ground truth), est (the localiser's) or odom."""
    import numpy as np

    track = read_trajectory(trajectory, which)
    if len(track.x) == 0:
        raise AssertionError(f"the trajectory is empty ({track.source})")
    d = fmath.hypot(track.x - pose[0], track.y - pose[1])
    near = d <= tol
    check_yaw = yaw_tol is not None and len(pose) >= 3 and track.yaw is not None
    if check_yaw:
        dyaw = np.abs((track.yaw - pose[2] + math.pi) % (2 * math.pi) - math.pi)
        if np.any(near & (dyaw <= yaw_tol)):
            return
    elif np.any(near):
        return
    i = int(np.argmin(d))
    when = f"at t={track.t[i]:.2f} s" if track.t is not None else f"at row {i}"
    at = (track.x[i], track.y[i]) + ((track.yaw[i],) if track.yaw is not None else ())
    target = _pose_text(pose[:2])
    if check_yaw and near.any():
        j = int(np.flatnonzero(near)[np.argmin(dyaw[near])])
        when_j = f"t={track.t[j]:.2f} s" if track.t is not None else f"row {j}"
        message = (
            f"the robot came within {tol:g} m of {target} but never within {yaw_tol:g} rad "
            f"of yaw {pose[2]:.2f}: best heading {track.yaw[j]:.2f} "
            f"(off by {dyaw[j]:.2f} rad) at {when_j}"
        )
    else:
        message = (
            f"the robot never came within {tol:g} m of {target}: closest approach "
            f"{d[i]:.2f} m {when}, at {_pose_text(at)}"
        )
    raise AssertionError(f"{message}\n  trajectory: {track.source} ({which} poses)")
