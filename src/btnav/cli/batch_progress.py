"""What `btnav batch` shows while it runs.

On a terminal (and with rich installed), a live bar: runs done / total, the ETA, the
running success rate and the failures so far. Anywhere else (a CI log, a pipe), one
plain line per finished run, so a log says what ran without control characters. Each
is a `batch.progress.Progress`, fed by `run_batch` as runs end.
"""

from __future__ import annotations

import sys
from typing import Any, TextIO

from ..batch.progress import Progress, describe
from ..batch.record import RunRecord


class _Tally:
    def __init__(self) -> None:
        self.total = self.done = self.ok = 0

    def start(self, total: int, done: list[RunRecord]) -> None:
        self.total = total
        self.done = len(done)
        self.ok = sum(r.succeeded for r in done)

    def add(self, record: RunRecord) -> None:
        self.done += 1
        self.ok += record.succeeded

    @property
    def failed(self) -> int:
        return self.done - self.ok

    def rate(self) -> str:
        return f"{100 * self.ok / self.done:.0f}% ok" if self.done else "-"


class LineProgress:
    """One line per finished run: `[3/12] office seed=2 ...: succeeded (8.2 s sim, ...)`."""

    def __init__(self, stream: TextIO) -> None:
        self.stream = stream
        self.tally = _Tally()

    def start(self, total: int, done: list[RunRecord]) -> None:
        self.tally.start(total, done)
        skipped = f", {len(done)} already in results.csv" if done else ""
        print(f"batch: {total} runs{skipped}", file=self.stream, flush=True)

    def update(self, record: RunRecord) -> None:
        self.tally.add(record)
        width = len(str(self.tally.total))
        count = f"[{self.tally.done:>{width}}/{self.tally.total}]"
        print(f"{count} {describe(record)}", file=self.stream, flush=True)

    def close(self) -> None:
        pass


class RichProgress:
    """rich's live bar, with the success rate and failures so far beside it."""

    def __init__(self, stream: TextIO) -> None:
        from rich.console import Console
        from rich.progress import (
            BarColumn,
            MofNCompleteColumn,
            Progress,
            TextColumn,
            TimeElapsedColumn,
            TimeRemainingColumn,
        )

        self.console = Console(file=stream)
        self.tally = _Tally()
        self.bar = Progress(
            TextColumn("batch"),
            BarColumn(),
            MofNCompleteColumn(),
            TextColumn("eta"),
            TimeRemainingColumn(),
            TimeElapsedColumn(),
            TextColumn("{task.fields[rate]}  {task.fields[failed]}"),
            console=self.console,
            transient=False,
        )
        self.task: Any = None

    def _fields(self) -> dict[str, str]:
        failed = self.tally.failed
        return {"rate": self.tally.rate(), "failed": f"{failed} failed" if failed else ""}

    def start(self, total: int, done: list[RunRecord]) -> None:
        self.tally.start(total, done)
        self.bar.start()
        self.task = self.bar.add_task("batch", total=total, completed=len(done), **self._fields())

    def update(self, record: RunRecord) -> None:
        self.tally.add(record)
        if not record.succeeded:  # a failure is worth a line that stays above the bar
            self.console.print(describe(record), markup=False, highlight=False)
        self.bar.update(self.task, advance=1, **self._fields())

    def close(self) -> None:
        self.bar.stop()


def default_progress(stream: TextIO | None = None) -> Progress:
    """rich's bar on a terminal when rich is there; one line per run otherwise."""
    stream = stream if stream is not None else sys.stdout
    if stream.isatty():
        try:
            return RichProgress(stream)
        except ImportError:
            pass
    return LineProgress(stream)
