"""The Ray backend: the same jobs as Ray tasks, on a local Ray or a running cluster.

Ray is imported only here, and only when asked for (`pip install 'btnav[ray]'`).
Each task runs its job with `worker.run_isolated`, in a fresh process forked inside
the Ray worker, so a run on Ray is built exactly as a local one and gives the same
record. The Ray worker itself imports only the batch's light modules (a `Job`, a
`RunRecord`); the stack is imported once per worker, by its fork server. Without
`--address` a local Ray is started with `workers` CPUs and shut down at the end; with
one, the batch joins that cluster (its nodes must see `--out` and the mission files at
the same paths, e.g. on a shared file system).

A task whose node was lost (Ray gives up after its retries) gets no row, so running
the command again runs it again; Ctrl-C cancels the tasks still queued or running.
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from .jobs import BatchError, Job
from .record import RunRecord
from .worker import run_isolated

RAY_MISSING = "the ray backend needs Ray, which is not installed (pip install 'btnav[ray]')"


def _import_ray() -> Any:
    try:
        import ray
    except ImportError:
        raise BatchError(RAY_MISSING, key="--backend") from None
    return ray


def _ray_task(job: Job, out: str) -> RunRecord:
    return run_isolated(job, Path(out))


def run_ray(
    jobs: Sequence[Job],
    out: Path,
    workers: int,
    on_done: Callable[[RunRecord], None],
    address: str | None = None,
) -> list[Job]:
    """Run every job as a Ray task; `on_done(record)` as each ends. Returns the jobs that
    got no record (their node was lost), to be run by a later invocation."""
    ray = _import_ray()
    started = not ray.is_initialized()
    if started:
        quiet = {"log_to_driver": False, "logging_level": logging.ERROR}
        if address:
            ray.init(address=address, **quiet)
        else:
            ray.init(num_cpus=workers, include_dashboard=False, **quiet)
    task = ray.remote(num_cpus=1, max_retries=3)(_ray_task)
    refs = {task.remote(job, str(out.resolve())): job for job in jobs}
    pending = list(refs)
    lost: list[Job] = []
    try:
        while pending:
            done, pending = ray.wait(pending, num_returns=1)
            for ref in done:
                try:
                    record = ray.get(ref)
                except ray.exceptions.RayError:  # the node or worker died; no row
                    lost.append(refs[ref])
                    continue
                on_done(record)
    except BaseException:
        for ref in pending:
            ray.cancel(ref, force=True)
        raise
    finally:
        if started:
            ray.shutdown()
    return lost
