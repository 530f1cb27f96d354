"""`btnav run`'s live status on a terminal: one line, rewritten in place while the run goes.

    12.4 s sim | 7x real time | FollowPath | waypoint 2/4

A run of a few minutes of robot time takes seconds to a minute of wall time, silent
until its summary; on a terminal this line (`mission.run_status`'s words) says it is
alive and what the tree is doing. It is redrawn with `\\r` a few times a second of wall
time and erased before the summary. When stdout is not a terminal (a pipe, a CI log, a
test) it prints nothing, and the run does not even call it, so logs and outputs are
unchanged.
"""

from __future__ import annotations

import shutil
import time
from collections.abc import Callable
from typing import TextIO

from ..mission.run_status import current_waypoint, format_status, running_actions
from ..navigators.basic_navigator import BasicNavigator

#: Wall seconds between redraws: often enough to look live, rarely enough to cost nothing.
REDRAW_INTERVAL = 0.25


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
