"""One run of a batch, in a process of its own.

`execute` is the run itself: load the mission with the job's seed and swept values,
run it into its folder, and turn the report into a `RunRecord`; anything it raises
becomes an `error` record with the traceback saved as `traceback.txt` beside the
run's other files, so one broken run never stops the batch.

`run_isolated` starts `execute` in a fresh process and returns its record. Fresh,
because py_trees keeps its blackboard (and btnav keeps Nav2's recovery count on it)
process-wide: a run after another in the same process could see what the first
left. The process is forked from a fork server that imported btnav once and never
ran a mission (`multiprocessing`'s "forkserver", preloading `btnav.batch.preload`),
so a run starts in milliseconds with nothing of an earlier run in it. Where there is
no fork server (Windows), it is spawned.
"""

from __future__ import annotations

import multiprocessing
import os
import signal
import sys
import time
import traceback
import warnings
from collections.abc import Iterator
from contextlib import contextmanager
from multiprocessing.connection import Connection
from multiprocessing.context import BaseContext
from pathlib import Path
from typing import Any

from ..core.errors import BtnavWarning
from .jobs import Job
from .record import TRACEBACK_FILE, RunRecord

#: Imported once by the fork server, so a run's process starts with btnav loaded.
PRELOAD = ["btnav.batch.preload"]


def execute(job: Job, out: Path) -> RunRecord:
    """Run `job` here and now; a run that raises is an `error` record, never an exception
    (KeyboardInterrupt and SystemExit still stop it)."""
    folder = job.folder(out)
    shown = str(folder.relative_to(out)) if folder.is_relative_to(out) else str(folder)
    (folder / TRACEBACK_FILE).unlink(missing_ok=True)
    wall0 = time.perf_counter()
    try:
        # here, not at the top: a Ray worker imports this module only to start runs
        from ..mission.mission import Mission
        from ..mission.runner import run_mission

        with warnings.catch_warnings():
            # the batch showed each mission's warnings once, when it checked them
            warnings.simplefilter("ignore", BtnavWarning)
            mission = Mission.load(
                job.mission_file,
                seed=job.seed,
                overrides=job.all_overrides(),
                origins=dict(job.origins),
            )
            report = run_mission(mission, folder)
    except Exception as err:
        folder.mkdir(parents=True, exist_ok=True)
        (folder / TRACEBACK_FILE).write_text(traceback.format_exc())
        message = f"{type(err).__name__}: {err}".splitlines()[0]
        return RunRecord.error(job, message, shown, time.perf_counter() - wall0)
    return RunRecord.from_report(job, report, shown)


def context() -> BaseContext:
    """The fork server where the platform has one (preloading btnav), else spawn."""
    if "forkserver" in multiprocessing.get_all_start_methods():
        ctx = multiprocessing.get_context("forkserver")
        ctx.set_forkserver_preload(PRELOAD)
        return ctx
    return multiprocessing.get_context("spawn")


def _die_with_parent() -> None:
    """Linux: the kernel kills this process when its parent (the fork server, which exits
    when the batch does) dies, so a batch killed with SIGKILL leaves no orphan run."""
    if not sys.platform.startswith("linux"):
        return
    try:
        import ctypes

        libc = ctypes.CDLL(None, use_errno=True)
        pr_set_pdeathsig = 1
        libc.prctl(pr_set_pdeathsig, signal.SIGKILL, 0, 0, 0)
    except (OSError, AttributeError):  # pragma: no cover - best effort
        pass


def child_main(job: Job, out: str, conn: Connection) -> None:
    """The body of a run's process: the batch's parent alone decides about Ctrl-C (it ends
    this process with SIGTERM), so a terminal's SIGINT to the whole group is ignored here."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    _die_with_parent()
    if os.path.isdir(job.cwd):  # on a Ray node, where the batch started (if it is there)
        os.chdir(job.cwd)
    record = execute(job, Path(out))
    try:
        conn.send(record)
    except (BrokenPipeError, ConnectionResetError):
        # the batch stopped listening (Ctrl-C while this run was ending): it will run
        # this job again next time, so the record goes nowhere, and no traceback
        return
    conn.close()


@contextmanager
def _main_script_hidden() -> Iterator[None]:
    """While a run's process starts, the parent's `__main__` names no script.

    multiprocessing runs the parent's main script again in every child it starts by
    spawn or fork server (as `__mp_main__`), so that pickled functions of `__main__`
    resolve. A run needs nothing from it (its target lives in this module), and in a
    Ray worker that script is Ray's worker, about 0.5 s to run in every run's process.
    """
    main = sys.modules.get("__main__")
    if main is None:
        yield
        return
    saved = {key: main.__dict__[key] for key in ("__file__", "__spec__") if key in main.__dict__}
    main.__dict__.pop("__file__", None)
    main.__dict__["__spec__"] = None
    try:
        yield
    finally:
        main.__dict__.pop("__spec__", None)
        main.__dict__.update(saved)


def start(ctx: BaseContext, job: Job, out: Path) -> tuple[Any, Connection]:
    """A run's process, started; its record arrives on the returned connection."""
    receive, send = ctx.Pipe(duplex=False)
    process = ctx.Process(  # type: ignore[attr-defined]
        target=child_main, args=(job, str(out), send), daemon=True, name=f"btnav-run-{job.seed}"
    )
    with _main_script_hidden():
        process.start()
    send.close()
    return process, receive


def collect(process: Any, receive: Connection, job: Job, out: Path) -> RunRecord:
    """The record a finished run's process sent; an `error` record if it died first."""
    try:
        record: RunRecord = receive.recv()
    except (EOFError, OSError):
        process.join()
        folder = job.folder(out)
        code = process.exitcode
        why = f"signal {-code}" if code is not None and code < 0 else f"exit code {code}"
        return RunRecord.error(
            job,
            f"the run's process died ({why}) before it reported",
            str(folder.relative_to(out)) if folder.is_relative_to(out) else str(folder),
            None,
        )
    finally:
        receive.close()
    process.join()
    return record


def stop(processes: list[Any], grace: float = 5.0) -> None:
    """End runs that are still going: SIGTERM, then SIGKILL after `grace` seconds."""
    for process in processes:
        if process.is_alive():
            process.terminate()
    deadline = time.monotonic() + grace
    for process in processes:
        process.join(max(0.0, deadline - time.monotonic()))
        if process.is_alive():
            process.kill()
            process.join()


def run_isolated(job: Job, out: Path) -> RunRecord:
    """`execute(job)` in a fresh process (what a Ray task calls)."""
    process, receive = start(context(), job, out)
    try:
        return collect(process, receive, job, out)
    except BaseException:
        stop([process])
        raise
