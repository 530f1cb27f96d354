"""`btnav run MISSION [--out DIR] [--seed N] [--set KEY=VALUE ...]`: the run, one line of result.

On a terminal a live status line (sim time, real-time factor, the running action,
the waypoint) is redrawn while the run goes and erased before the result; elsewhere
the output is only the result.
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

from ..mission.mission import Mission
from ..mission.runner import run_mission
from ..mission.status_line import StatusLine


def default_out_dir(mission: Mission) -> Path:
    return Path("out") / mission.name


def run_main(
    path: str,
    *,
    out: str | None = None,
    seed: int | None = None,
    overrides: dict[str, Any] | None = None,
    origins: dict[str, str] | None = None,
) -> int:
    """Exit 0 when the task succeeded, 1 when it failed, hit its time limit or missed
    waypoints. `origins` maps each override key to the `--set KEY=VALUE` that gave it."""
    mission = Mission.load(path, seed=seed, overrides=overrides, origins=origins)
    out_dir = Path(out) if out is not None else default_out_dir(mission)
    status = StatusLine(sys.stdout, task=mission.task, goals=len(mission.spec.task.poses))
    try:
        report = run_mission(mission, out_dir, progress=status if status.enabled else None)
    finally:
        status.close()
    print(report.summary())
    if report.outputs:
        print(f"outputs in {out_dir}/: {', '.join(report.outputs)}")
    return report.exit_code
