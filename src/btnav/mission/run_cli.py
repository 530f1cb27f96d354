"""`btnav run MISSION [--out DIR] [--seed N] [--set KEY=VALUE ...]`: the run, one line of result."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from .mission import Mission
from .runner import run_mission


def default_out_dir(mission: Mission) -> Path:
    return Path("out") / mission.name


def run_main(
    path: str,
    *,
    out: str | None = None,
    seed: int | None = None,
    overrides: dict[str, Any] | None = None,
) -> int:
    """Exit 0 when the task succeeded, 1 when it failed or hit its time limit."""
    mission = Mission.load(path, seed=seed, overrides=overrides)
    out_dir = Path(out) if out is not None else default_out_dir(mission)
    report = run_mission(mission, out_dir)
    print(report.summary())
    if report.outputs:
        print(f"outputs in {out_dir}/: {', '.join(report.outputs)}")
    return report.exit_code
