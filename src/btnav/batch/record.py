"""One run's line of a batch: what `results.csv` holds and `run_batch` returns.

A record is built from the run's `RunReport` in the process that ran it, or read back
from `results.csv` for a run an earlier invocation finished, and the two give equal
records (floats are written with `repr`), so a resumed batch returns what a fresh
one would.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from ..mission.report import RunReport
from .jobs import Job, value_text
from .results import TAIL

#: The status of a run that raised (its traceback is `traceback.txt` in its folder).
ERROR = "error"
SUCCEEDED = "succeeded"
TRACEBACK_FILE = "traceback.txt"


@dataclass
class RunRecord:
    """A finished run: the brief's report fields, flattened to one row."""

    mission: str
    seed: int
    sweep: dict[str, str]  # key -> the value's text, as in results.csv
    status: str  # succeeded | failed | canceled | error
    error_code: int | None = None
    error_msg: str | None = None
    sim_time: float | None = None
    wall_time: float | None = None
    path_length: float | None = None
    collisions: int | None = None
    recoveries: int | None = None
    replans: int | None = None
    missed_waypoints: int | None = None
    loc_rms_xy: float | None = None
    loc_max_xy: float | None = None
    loc_rms_yaw: float | None = None
    explored_area: float | None = None  # m² of free space mapped (a SLAM run's map)
    folder: str = ""
    extra: dict[str, Any] = field(default_factory=dict, compare=False, repr=False)

    @property
    def succeeded(self) -> bool:
        """What `btnav run` exits 0 for: succeeded and no waypoint missed."""
        return self.status == SUCCEEDED and not self.missed_waypoints

    @property
    def key(self) -> tuple[str, ...]:
        return (self.mission, str(self.seed), *self.sweep.values())

    def row(self) -> dict[str, Any]:
        """The record by results.csv column."""
        out: dict[str, Any] = {"mission": self.mission, "seed": self.seed, **self.sweep}
        for name in TAIL:
            out[name] = getattr(self, name)
        return out

    @classmethod
    def from_report(cls, job: Job, report: RunReport, folder: str) -> RunRecord:
        loc = report.localization_error
        return cls(
            mission=job.mission,
            seed=job.seed,
            sweep=_sweep_text(job),
            status=report.status,
            error_code=report.error_code,
            error_msg=report.error_msg,
            sim_time=report.sim_time,
            wall_time=report.wall_time,
            path_length=report.path_length,
            collisions=report.collisions,
            recoveries=report.recoveries,
            replans=report.replans,
            missed_waypoints=len(report.missed_waypoints),
            loc_rms_xy=loc.get("rms_xy"),
            loc_max_xy=loc.get("max_xy"),
            loc_rms_yaw=loc.get("rms_yaw"),
            explored_area=report.explored_area,
            folder=folder,
        )

    @classmethod
    def error(cls, job: Job, message: str, folder: str, wall_time: float | None) -> RunRecord:
        return cls(
            mission=job.mission,
            seed=job.seed,
            sweep=_sweep_text(job),
            status=ERROR,
            error_msg=message,
            wall_time=wall_time,
            folder=folder,
        )

    @classmethod
    def from_row(cls, row: Mapping[str, str], sweep_keys: list[str]) -> RunRecord:
        """A record read back from results.csv (empty cells are None)."""

        def num(name: str, kind: type) -> Any:
            text = row.get(name) or ""
            return kind(text) if text else None

        return cls(
            mission=row["mission"],
            seed=int(row["seed"]),
            sweep={k: row[k] for k in sweep_keys},
            status=row["status"],
            error_code=num("error_code", int),
            error_msg=row.get("error_msg") or None,
            sim_time=num("sim_time", float),
            wall_time=num("wall_time", float),
            path_length=num("path_length", float),
            collisions=num("collisions", int),
            recoveries=num("recoveries", int),
            replans=num("replans", int),
            missed_waypoints=num("missed_waypoints", int),
            loc_rms_xy=num("loc_rms_xy", float),
            loc_max_xy=num("loc_max_xy", float),
            loc_rms_yaw=num("loc_rms_yaw", float),
            explored_area=num("explored_area", float),
            folder=row.get("folder", ""),
        )


def _sweep_text(job: Job) -> dict[str, str]:
    return {k: value_text(v) for k, v in job.sweep}
