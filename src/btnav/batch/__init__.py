"""Batch runs: many missions x seeds x swept params, on all cores or on Ray, resumable.

`btnav batch` and `run_batch` plan the cartesian product, check every mission and
swept key before anything runs, run each job in a fresh process, append a row to
`results.csv` as each run ends (a second invocation runs only what is missing), and
summarise the batch per swept value.

Importing the package is cheap (names load their modules on first use): a Ray worker
that unpickles a `Job` should not import the navigation stack its run's process will
import anyway.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..core.lazy_names import lazy_names

if TYPE_CHECKING:
    from .api import BatchOutcome, run_batch
    from .jobs import BatchError, Job, parse_seeds, parse_sweep, parse_values
    from .record import RunRecord
    from .summary import GroupSummary, summarize, wilson_interval

#: Each public name and the module that holds it.
_LAZY = {
    "BatchError": "jobs",
    "BatchOutcome": "api",
    "GroupSummary": "summary",
    "Job": "jobs",
    "RunRecord": "record",
    "parse_seeds": "jobs",
    "parse_sweep": "jobs",
    "parse_values": "jobs",
    "run_batch": "api",
    "summarize": "summary",
    "wilson_interval": "summary",
}

__all__ = [
    "BatchError",
    "BatchOutcome",
    "GroupSummary",
    "Job",
    "RunRecord",
    "parse_seeds",
    "parse_sweep",
    "parse_values",
    "run_batch",
    "summarize",
    "wilson_interval",
]


__getattr__ = lazy_names(__name__, _LAZY)
