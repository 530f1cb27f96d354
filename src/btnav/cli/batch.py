"""`btnav batch MISSION... --out DIR`: the batch, its progress, then the summary table.

Exit 0 when every run succeeded (as `btnav run` would exit 0), 1 when any failed,
raised or was lost with a Ray node, 2 on a user error found before anything ran
(raised as a `BtnavError` for the CLI to print). Ctrl-C stops the runs, keeps every
finished row, says how to resume and exits 130.
"""

from __future__ import annotations

import sys
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from ..batch.api import run_batch
from ..batch.jobs import parse_seeds, parse_sweep
from ..batch.results import RESULTS_FILE
from ..batch.summary import markdown, summarize
from . import EXIT_FAILED, EXIT_INTERRUPTED, EXIT_OK
from .batch_progress import default_progress


def batch_main(
    missions: Sequence[str],
    *,
    out: str,
    seeds: str | None = None,
    sweep: Sequence[str] = (),
    workers: int | None = None,
    backend: str = "local",
    address: str | None = None,
    overrides: Mapping[str, Any] | None = None,
    origins: Mapping[str, str] | None = None,
) -> int:
    seed_list = parse_seeds(seeds) if seeds is not None else None
    values, sweep_origins = parse_sweep(sweep)
    progress = default_progress(sys.stdout)
    try:
        records = run_batch(
            missions,
            out=out,
            seeds=seed_list,
            sweep=values,
            workers=workers,
            backend=backend,
            address=address,
            overrides=overrides,
            origins={**(origins or {}), **sweep_origins},
            progress=progress,
        )
    except KeyboardInterrupt:
        print(
            f"btnav: interrupted; finished runs are in {Path(out) / RESULTS_FILE}: "
            "run the same command again to run the rest",
            file=sys.stderr,
        )
        return EXIT_INTERRUPTED
    print()
    print(markdown(summarize(records)), end="")
    failed = sum(not r.succeeded for r in records)
    line = f"{len(records)} runs, {len(records) - failed} succeeded, {failed} failed"
    if records.lost:
        line += f"; {len(records.lost)} lost with their Ray node (run the command again)"
    print(line)
    print(f"results in {out}/: {RESULTS_FILE}, {', '.join(records.summary_files)}, runs/")
    return EXIT_FAILED if failed or records.lost else EXIT_OK
