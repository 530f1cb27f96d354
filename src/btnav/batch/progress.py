"""What a batch tells whoever shows its progress: `start`, a record as each run ends,
`close` (the `Progress` protocol `run_batch` takes), and a record in words (`describe`).

The command line draws it (`cli.batch_progress`: a rich bar on a terminal, a plain line
per run elsewhere); `run_batch` without one shows nothing.
"""

from __future__ import annotations

from typing import Protocol

from .record import RunRecord


class Progress(Protocol):
    def start(self, total: int, done: list[RunRecord]) -> None: ...
    def update(self, record: RunRecord) -> None: ...
    def close(self) -> None: ...


def describe(record: RunRecord) -> str:
    """`office seed=3 inflation_radius=0.4: succeeded, 8.2 s sim, 1.9 s wall`."""
    sweep = "".join(f" {k.split('.')[-1]}={v}" for k, v in record.sweep.items())
    head = f"{record.mission} seed={record.seed}{sweep}: {record.status}"
    if record.status == "error":
        return f"{head} ({record.error_msg}; see {record.folder}/traceback.txt)"
    if record.succeeded:
        detail = f"{record.sim_time:.1f} s sim"
    else:
        code = f"error {record.error_code}: " if record.error_code is not None else ""
        missed = f"{record.missed_waypoints} waypoints missed" if record.missed_waypoints else ""
        detail = f"{code}{record.error_msg or missed}"
    wall = f", {record.wall_time:.1f} s wall" if record.wall_time is not None else ""
    return f"{head} ({detail}{wall})"


class NoProgress:
    def start(self, total: int, done: list[RunRecord]) -> None:
        pass

    def update(self, record: RunRecord) -> None:
        pass

    def close(self) -> None:
        pass
