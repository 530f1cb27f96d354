"""`btnav run`'s live status on a terminal: one line, rewritten in place while the run goes.

    12.4 s sim | 7x real time | FollowPath | waypoint 2/4

A run of a few minutes of robot time takes seconds to a minute of wall time, silent
until its summary; on a terminal this line says it is alive and what the tree is
doing (the RUNNING action nodes: ComputePathToPose, FollowPath, Spin, BackUp, ...).
It is redrawn with `\\r` a few times a second of wall time and erased before the
summary. When stdout is not a terminal (a pipe, a CI log, a test) it prints nothing,
and the run does not even call it, so logs and outputs are unchanged.
"""

from __future__ import annotations

import shutil
import time
from collections.abc import Callable, Iterator
from typing import Any, TextIO

from py_trees.common import Status

from ..bt.nav2_actions import BtActionNode
from ..navigators.navigator import BasicNavigator

#: Wall seconds between redraws: often enough to look live, rarely enough to cost nothing.
REDRAW_INTERVAL = 0.25


def format_status(
    sim_time: float,
    real_time_factor: float | None,
    actions: list[str],
    waypoint: tuple[int, int] | None = None,
    width: int | None = None,
) -> str:
    """`12.4 s sim | 7x real time | FollowPath | waypoint 2/4`, cut to `width` characters.

    `real_time_factor` None (no wall time yet) and an empty `actions` are left out;
    `waypoint` is (1-based index, count).
    """
    parts = [f"{sim_time:.1f} s sim"]
    if real_time_factor is not None:
        parts.append(f"{real_time_factor:.0f}x real time")
    if actions:
        parts.append(", ".join(actions))
    if waypoint is not None:
        parts.append(f"waypoint {waypoint[0]}/{waypoint[1]}")
    line = " | ".join(parts)
    if width is not None and len(line) > width:
        line = line[: max(width - 3, 0)] + "..." if width > 3 else line[:width]
    return line


def running_actions(nav: BasicNavigator) -> list[str]:
    """The node types of the RUNNING leaves of the tree that runs the current goal, action
    nodes first (ComputePathToPose, FollowPath, Spin, ...), each once, in tree order."""
    for navigator in nav.bt_navigator.navigators.values():
        current = navigator.current
        if current is None or not current.active or navigator.root is None:
            continue
        leaves = [n for n in _depth_first(navigator.root) if not n.children]
        running = [n for n in leaves if n.status == Status.RUNNING]
        actions = [n for n in running if isinstance(n, BtActionNode)] or running
        return list(dict.fromkeys(type(n).__name__ for n in actions))
    return []


def _depth_first(node: Any) -> Iterator[Any]:
    yield node
    for child in node.children:
        yield from _depth_first(child)


def current_waypoint(nav: BasicNavigator, task: str, goals: int) -> tuple[int, int] | None:
    """(1-based index of the pose being driven to, number of poses), from the task's feedback."""
    feedback = nav.get_feedback()
    if task == "follow_waypoints" and feedback is not None:
        index = getattr(feedback, "current_waypoint", None)
        if index is not None:
            return min(int(index) + 1, goals), goals
    if task == "navigate_through_poses" and feedback is not None:
        left = getattr(feedback, "number_of_poses_remaining", None)
        if left is not None:
            return min(max(goals - int(left) + 1, 1), goals), goals
    return None


class StatusLine:
    """The `progress` callback of `run_mission` that keeps the status line up to date.

    `enabled` is whether `stream` is a terminal; when it is not, nothing is written.
    `wall_clock` is injectable for tests.
    """

    def __init__(
        self,
        stream: TextIO,
        *,
        task: str,
        goals: int,
        interval: float = REDRAW_INTERVAL,
        wall_clock: Callable[[], float] = time.monotonic,
    ) -> None:
        isatty = getattr(stream, "isatty", None)
        self.enabled = bool(isatty and isatty())
        self.stream = stream
        self.task = task
        self.goals = goals
        self.interval = interval
        self.wall_clock = wall_clock
        self._start: tuple[float, float] | None = None  # (wall, sim) at the first call
        self._next = 0.0
        self._shown = 0  # characters on the line now

    def __call__(self, nav: BasicNavigator) -> None:
        if not self.enabled:
            return
        wall = self.wall_clock()
        if self._start is None:
            self._start = (wall, nav.now)
            self._next = wall + self.interval
            return
        if wall < self._next:
            return
        self._next = wall + self.interval
        wall0, sim0 = self._start
        elapsed = wall - wall0
        rtf = (nav.now - sim0) / elapsed if elapsed > 0 else None
        width = shutil.get_terminal_size().columns - 1
        line = format_status(
            nav.now,
            rtf,
            running_actions(nav),
            current_waypoint(nav, self.task, self.goals),
            width,
        )
        self._write(line)

    def _write(self, line: str) -> None:
        pad = " " * max(self._shown - len(line), 0)  # cover what a longer line left
        self.stream.write(f"\r{line}{pad}")
        self.stream.flush()
        self._shown = len(line)

    def close(self) -> None:
        """Erase the line, so what is printed next starts on a clean one."""
        if self.enabled and self._shown:
            self.stream.write("\r" + " " * self._shown + "\r")
            self.stream.flush()
            self._shown = 0
