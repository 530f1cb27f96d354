"""The batch at a glance: per mission and swept value, how often and how well it worked.

A group is one mission with one set of swept values, over its seeds. For each:
the runs, how many succeeded (as `btnav run` exits 0: succeeded with no waypoint
missed) and the success rate with a 95% Wilson score interval (unlike the normal
approximation it stays inside [0, 1] and is honest at 0/10 and 10/10, the usual
outcomes of a handful of seeds); the median and 95th percentile of sim time and the
median path length of the runs that succeeded (a failed run's time is its time
limit, which says nothing about speed); the mean collisions and recoveries of every
run that finished (an `error` run has no numbers, and counts as not succeeded).
"""

from __future__ import annotations

import csv
import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .record import ERROR, RunRecord

Z95 = 1.959963984540054  # the standard normal's 97.5% quantile

COLUMNS = (
    "runs",
    "succeeded",
    "errors",
    "success_rate",
    "ci95_low",
    "ci95_high",
    "sim_time_median",
    "sim_time_p95",
    "path_length_median",
    "collisions_mean",
    "recoveries_mean",
)


def wilson_interval(successes: int, n: int, z: float = Z95) -> tuple[float, float]:
    """The Wilson score interval of a success rate: honest at 0 and 100 % and on few runs,
    where the normal approximation's interval leaves [0, 1].

    Args:
        successes: runs that succeeded.
        n: runs.
        z: the normal quantile (default 1.96, a 95 % interval).

    Returns:
        (low, high); (0, 1) when there are no runs.
    """
    if n == 0:
        return 0.0, 1.0
    p = successes / n
    denom = 1 + z * z / n
    centre = (p + z * z / (2 * n)) / denom
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / denom
    low = 0.0 if successes == 0 else max(0.0, centre - half)
    high = 1.0 if successes == n else min(1.0, centre + half)  # exact at the ends
    return low, high


@dataclass
class GroupSummary:
    mission: str
    sweep: dict[str, str]
    runs: int
    succeeded: int
    errors: int
    success_rate: float
    ci95_low: float
    ci95_high: float
    sim_time_median: float | None
    sim_time_p95: float | None
    path_length_median: float | None
    collisions_mean: float | None
    recoveries_mean: float | None

    def row(self) -> dict[str, object]:
        return {"mission": self.mission, **self.sweep, **{c: getattr(self, c) for c in COLUMNS}}


def _stat(values: list[float], q: float | None = None) -> float | None:
    if not values:
        return None
    if q is None:
        return float(np.mean(values))
    return float(np.percentile(values, q))


def summarize(records: Sequence[RunRecord]) -> list[GroupSummary]:
    """Group runs by mission and swept values, as `summary.md` shows them.

    Args:
        records: the batch's records (`run_batch`'s outcome, or `results.csv`'s rows).

    Returns:
        One `GroupSummary` per (mission, swept values), in the order the groups first
        appear: success rate with its Wilson interval, sim time median and p95 and path
        length median of the successful runs, collisions and recoveries per run.
    """
    groups: dict[tuple[str, ...], list[RunRecord]] = {}
    for r in records:
        groups.setdefault((r.mission, *r.sweep.values()), []).append(r)
    out = []
    for runs in groups.values():
        ok = [r for r in runs if r.succeeded]
        finished = [r for r in runs if r.status != ERROR]
        low, high = wilson_interval(len(ok), len(runs))
        out.append(
            GroupSummary(
                mission=runs[0].mission,
                sweep=dict(runs[0].sweep),
                runs=len(runs),
                succeeded=len(ok),
                errors=len(runs) - len(finished),
                success_rate=len(ok) / len(runs),
                ci95_low=low,
                ci95_high=high,
                sim_time_median=_stat([r.sim_time for r in ok if r.sim_time is not None], 50),
                sim_time_p95=_stat([r.sim_time for r in ok if r.sim_time is not None], 95),
                path_length_median=_stat(
                    [r.path_length for r in ok if r.path_length is not None], 50
                ),
                collisions_mean=_stat([r.collisions for r in finished if r.collisions is not None]),
                recoveries_mean=_stat([r.recoveries for r in finished if r.recoveries is not None]),
            )
        )
    return out


def _fmt(value: object, digits: int = 2) -> str:
    if value is None:
        return "-"
    if isinstance(value, float):
        return f"{value:.{digits}f}"
    return str(value)


def table_rows(summaries: Sequence[GroupSummary]) -> tuple[list[str], list[list[str]]]:
    """The table a user reads: success as `9/10 90% [60-98%]`, times in seconds."""
    keys = list(summaries[0].sweep) if summaries else []
    head = [
        "mission",
        *(k.split(".")[-1] for k in keys),
        "success",
        "95% CI",
        "sim time median",
        "p95",
        "path median",
        "collisions",
        "recoveries",
    ]
    rows = []
    for s in summaries:
        rows.append(
            [
                s.mission,
                *s.sweep.values(),
                f"{s.succeeded}/{s.runs} {100 * s.success_rate:.0f}%",
                f"{100 * s.ci95_low:.0f}-{100 * s.ci95_high:.0f}%",
                _fmt(s.sim_time_median, 1),
                _fmt(s.sim_time_p95, 1),
                _fmt(s.path_length_median, 2),
                _fmt(s.collisions_mean, 2),
                _fmt(s.recoveries_mean, 2),
            ]
        )
    return head, rows


def markdown(summaries: Sequence[GroupSummary]) -> str:
    """The summary as a Markdown table (summary.md, and what the command prints)."""
    head, rows = table_rows(summaries)
    widths = [max(len(r[i]) for r in [head, *rows]) for i in range(len(head))]

    def line(cells: list[str]) -> str:
        return "| " + " | ".join(c.ljust(w) for c, w in zip(cells, widths, strict=True)) + " |"

    rule = "|" + "|".join("-" * (w + 2) for w in widths) + "|"
    return "\n".join([line(head), rule, *(line(r) for r in rows)]) + "\n"


def write_summary(summaries: Sequence[GroupSummary], out: Path) -> list[str]:
    """summary.csv and summary.md in `out`, and summary.png when matplotlib is there;
    the names of the files written."""
    keys = list(summaries[0].sweep) if summaries else []
    with open(out / "summary.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, ["mission", *keys, *COLUMNS], lineterminator="\n")
        writer.writeheader()
        for s in summaries:
            writer.writerow({k: "" if v is None else v for k, v in s.row().items()})
    (out / "summary.md").write_text(markdown(summaries))
    written = ["summary.csv", "summary.md"]
    from .summary_plot import plot_summary

    if summaries and plot_summary(summaries, out / "summary.png"):
        written.append("summary.png")
    return written
