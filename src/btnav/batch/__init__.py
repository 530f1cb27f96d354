"""Batch runs: many missions x seeds x swept params, on all cores or on Ray, resumable.

`btnav batch` and `run_batch` plan the cartesian product, check every mission and
swept key before anything runs, run each job in a fresh process, append a row to
`results.csv` as each run ends (a second invocation runs only what is missing), and
summarise the batch per swept value.
"""

from .api import BatchOutcome, run_batch
from .jobs import BatchError, Job, parse_seeds, parse_sweep, parse_values
from .record import RunRecord
from .summary import GroupSummary, summarize, wilson_interval

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
