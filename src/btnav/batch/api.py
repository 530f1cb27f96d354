"""`run_batch`: a whole batch from Python, the machinery `btnav batch` drives.

Plan and check everything, open `results.csv` and skip the runs it already holds,
run the rest on the chosen backend (a row appended as each ends), then write the
summary. The records come back in the batch's order (mission, swept values, seed),
whichever order the runs ended in and whichever invocation ran them.
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from os import PathLike
from pathlib import Path
from typing import Any

from .jobs import BatchError, Job
from .local import run_local
from .plan import plan_batch
from .progress import NoProgress, Progress
from .record import RunRecord
from .results import RESULTS_FILE, ResultsFile, row_key
from .summary import summarize, write_summary

BACKENDS = ("local", "ray")
DEFAULT_OUT = "out/batch"


def default_workers() -> int:
    """Every core this process may use."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - not Linux
        return os.cpu_count() or 1


class BatchOutcome(list[RunRecord]):
    """The records, in batch order; `.lost` holds jobs a Ray node took down with it."""

    lost: list[Job]
    summary_files: list[str]


def run_batch(
    missions: Sequence[str | PathLike[str]],
    *,
    out: str | PathLike[str] = DEFAULT_OUT,
    seeds: Sequence[int] | None = None,
    sweep: Mapping[str, Sequence[Any]] | None = None,
    workers: int | None = None,
    backend: str = "local",
    address: str | None = None,
    overrides: Mapping[str, Any] | None = None,
    origins: Mapping[str, str] | None = None,
    progress: Progress | None = None,
) -> BatchOutcome:
    """Run missions x seeds x swept values into `out`, each run in a fresh process.

    Runs already in `out/results.csv` are not run again, so a second call finishes an
    interrupted batch. A user's mistake anywhere raises a `BtnavError` before any run
    starts; a run that fails is a record with its status, not an exception.

    Args:
        missions: mission YAML files (a staged mission is one job).
        out: the batch folder: `results.csv`, the summary, one folder per run.
        seeds: the seeds to run each mission with; None runs each mission's own seed.
        sweep: a `--set` key (a dotted params key or `mission.*`) mapped to its values;
            the batch runs their cartesian product.
        workers: processes at once (None: every core this process may use).
        backend: `local` (processes on this machine) or `ray` (the `ray` extra).
        address: the Ray cluster to join (None: start a local one).
        overrides: `--set` values applied to every run.
        origins: each override's `--set KEY=VALUE` as typed, for error messages.
        progress: told of each finished run (`btnav batch` draws its bar with it).

    Returns:
        One `RunRecord` per run in batch order (mission, swept values, seed), whichever
        order they ended in; `.lost` holds jobs a Ray node took down with it and
        `.summary_files` the summary files written.
    """
    if backend not in BACKENDS:
        raise BatchError(f"unknown backend '{backend}' (have: {', '.join(BACKENDS)})")
    if workers is not None and workers < 1:
        raise BatchError(f"--workers must be at least 1, got {workers}", key="--workers")
    jobs = plan_batch(missions, seeds=seeds, sweep=sweep, overrides=overrides, origins=origins)
    if backend == "ray":
        from .ray_backend import _import_ray

        _import_ray()  # a missing Ray is a user error before anything runs
    out_dir = Path(out)
    keys = list(sweep or {})
    results = ResultsFile(out_dir / RESULTS_FILE, keys)
    planned = {job.key for job in jobs}
    done: dict[tuple[str, ...], RunRecord] = {}
    for row in results.open():
        key = row_key(row, keys)
        if key in planned and key not in done:
            done[key] = RunRecord.from_row(row, keys)
    todo = [job for job in jobs if job.key not in done]
    shown = progress if progress is not None else NoProgress()

    def on_done(record: RunRecord) -> None:
        results.append(record.row())
        done[record.key] = record
        shown.update(record)

    lost: list[Job] = []
    shown.start(len(jobs), list(done.values()))
    try:
        if todo:
            count = min(workers or default_workers(), len(todo))
            if backend == "ray":
                from .ray_backend import run_ray

                lost = run_ray(todo, out_dir, count, on_done, address)
            else:
                run_local(todo, out_dir, count, on_done)
    finally:
        shown.close()
    outcome = BatchOutcome(done[job.key] for job in jobs if job.key in done)
    outcome.lost = lost
    outcome.summary_files = write_summary(summarize(outcome), out_dir)
    return outcome
