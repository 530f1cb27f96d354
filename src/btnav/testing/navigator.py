"""`btnav_navigator`'s navigator: `btnav.Navigator`, recording into the test's run folder.

As `btnav run` does, it writes `trajectory.csv` (a row per control cycle) and
`bt_log.jsonl` (every node's status changes) while it is driven, and at `close()`
`report.json` when a task has ended. The recorders only read the run, so the
navigator behaves exactly as `Navigator.from_mission` would.
"""

from __future__ import annotations

import time
from contextlib import ExitStack
from pathlib import Path
from typing import Any, TextIO

from ..mission.bt_log import BtLog
from ..mission.counters import NavigationCounters
from ..mission.navigator import Navigator
from ..mission.runner import build_report
from ..mission.trajectory import TrajectoryRecorder


class RecordedNavigator(Navigator):
    """A Navigator whose run is recorded in `out_dir` (see the module doc)."""

    out_dir: Path | None = None
    _files: ExitStack | None = None

    def record(self, out_dir: Path) -> None:
        """Start writing `trajectory.csv` and `bt_log.jsonl` into `out_dir`."""
        self.out_dir = out_dir
        self._files = files = ExitStack()  # closed by close()

        def sink(name: str) -> TextIO:
            return files.enter_context(open(out_dir / name, "w", newline="\n"))

        bt = self.bt_navigator
        self._recorder = TrajectoryRecorder(
            self.runtime,
            self.stack.controller_server.rate,
            sink("trajectory.csv"),
            global_frame=bt.params.global_frame,
        )
        self.runtime.add(self._recorder)
        self._counters = NavigationCounters()
        bt.tick_listeners.append(self._counters)
        self._bt_log_sink = sink("bt_log.jsonl")
        log = BtLog(
            self._bt_log_sink,
            lambda: self.runtime.now,
            idle_transitions=bt.params.bt_log_idle_transitions,
        )
        bt.tick_listeners.append(log)
        self._wall0 = time.perf_counter()

    @property
    def trajectory_file(self) -> Path | None:
        return self.out_dir / "trajectory.csv" if self.out_dir is not None else None

    @property
    def bt_log_file(self) -> Path | None:
        return self.out_dir / "bt_log.jsonl" if self.out_dir is not None else None

    def flush(self) -> None:
        """Write out what is buffered, so the files can be read mid-test."""
        if self._files is not None:
            for sink in (self._recorder.sink, self._bt_log_sink):
                if sink is not None and not sink.closed:
                    sink.flush()

    def close(self) -> None:
        """Close the files; write `report.json` if a task has ended."""
        if self._files is None:
            return
        files, self._files = self._files, None
        files.close()
        result = self.get_result()
        if result is None or self.mission is None or self.out_dir is None:
            return
        wall = time.perf_counter() - self._wall0
        outputs: list[Any] = []
        report = build_report(
            self.mission, self, result, self._recorder, self._counters, wall, False, outputs
        )
        report.write(self.out_dir / "report.json")
