"""The local backend: up to `workers` runs at once, each in a fresh process.

The parent only schedules: it starts a run's process (`worker.start`), waits for any
running one to report, hands the record to `on_done` (which appends its row) and
starts the next. Ctrl-C (KeyboardInterrupt in the parent) ends the running processes
with SIGTERM, waits for them, and re-raises: no orphan process, and no row for a run
that did not finish, since rows are written by this loop alone, one whole row per
write.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable, Sequence
from multiprocessing.connection import Connection, wait
from pathlib import Path
from typing import Any

from .jobs import Job
from .record import RunRecord
from .worker import collect, context, start, stop


def run_local(
    jobs: Sequence[Job], out: Path, workers: int, on_done: Callable[[RunRecord], None]
) -> None:
    """Run every job, `workers` at a time; `on_done(record)` as each ends (in end order)."""
    ctx = context()
    pending = deque(jobs)
    running: dict[Connection, tuple[Any, Job]] = {}
    try:
        while pending or running:
            while pending and len(running) < max(1, workers):
                job = pending.popleft()
                process, receive = start(ctx, job, out)
                running[receive] = (process, job)
            for ready in wait(list(running)):
                assert isinstance(ready, Connection)
                process, job = running.pop(ready)
                on_done(collect(process, ready, job, out))
    except BaseException:
        stop([process for process, _ in running.values()])
        for receive in running:
            receive.close()
        raise
