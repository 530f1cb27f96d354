"""Missions in tests: `load_mission(path, **overrides)` and `run_mission(...)` -> `RunResult`.

Overrides are `btnav run --set`'s: a dotted params key
(`**{"local_costmap.local_costmap.inflation_layer.inflation_radius": 0.4}`) or a mission
key, spelt `mission.seed` or bare as a keyword (`seed=3`, `time_limit=20`,
`task={"navigate_to_pose": [3, 2, 1.57]}`); a path given this way is relative to the
current directory, as on a command line. A run always writes `report.json`,
`trajectory.csv` and `bt_log.jsonl` (and `run.png` with `--btnav-out` and matplotlib)
into the test's run folder, so the assertion helpers can read them; recording only
reads the run, so the report is the one `btnav run` gives.
"""

from __future__ import annotations

import dataclasses
import importlib.util
from collections.abc import Mapping
from dataclasses import dataclass, field
from os import PathLike
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..mission.report import RunReport
from .folders import claim_folder

if TYPE_CHECKING:
    from ..mission.mission import Mission

#: What every run in a test writes, so the assertion helpers have their files.
RECORDED = ("report", "trajectory", "bt_log")


def as_overrides(
    overrides: Mapping[str, Any] | None, keywords: Mapping[str, Any]
) -> dict[str, Any]:
    """`--set` keys from a mapping and keywords; a bare keyword is a mission key."""
    merged = {**(overrides or {}), **keywords}
    return {(key if "." in key else f"mission.{key}"): value for key, value in merged.items()}


def load_mission(
    path: str | PathLike[str],
    overrides: Mapping[str, Any] | None = None,
    **keywords: Any,
) -> Mission:
    """`Mission.load` with `--set`-style overrides; a mistake is the usual located error,
    blamed on the override that caused it."""
    from ..mission.mission import Mission

    over = as_overrides(overrides, keywords)
    origins = {key: f"override {key}={value!r}" for key, value in over.items()}
    return Mission.load(path, overrides=over, origins=origins)


@dataclass
class RunResult(RunReport):
    """A run's `RunReport`, plus where its files are and the task's poses (for messages)."""

    out_dir: Path | None = None
    task_poses: list[tuple[float, float, float]] = field(default_factory=list)
    world_file: str | None = None

    @property
    def trajectory_file(self) -> Path | None:
        return self._file("trajectory.csv")

    @property
    def bt_log_file(self) -> Path | None:
        return self._file("bt_log.jsonl")

    def _file(self, name: str) -> Path | None:
        if self.out_dir is None or not (self.out_dir / name).is_file():
            return None
        return self.out_dir / name

    def to_dict(self) -> dict[str, Any]:
        """`report.json`'s fields only."""
        data = super().to_dict()
        data.pop("out_dir", None)
        data.pop("task_poses", None)
        data.pop("world_file", None)
        return data


def with_recorded_outputs(mission: Mission, picture: bool) -> Mission:
    """The mission, asking also for the files the helpers read (and `png` if `picture`)."""
    from ..mission.outputs import is_output

    wanted = list(mission.spec.outputs)
    wanted += [name for name in RECORDED if name not in wanted]
    if picture and "png" not in wanted and _can_draw() and is_output("png"):
        wanted.append("png")
    if wanted == list(mission.spec.outputs):
        return mission
    return dataclasses.replace(mission, spec=mission.spec.model_copy(update={"outputs": wanted}))


def _can_draw() -> bool:
    return importlib.util.find_spec("matplotlib") is not None


def run_mission(
    mission: str | PathLike[str] | Mission,
    overrides: Mapping[str, Any] | None = None,
    *,
    out: str | PathLike[str] | None = None,
    **keywords: Any,
) -> RunResult:
    """Run a mission file, a bundled mission's name or a loaded `Mission` to its end.

    The files go to `out` if given, else to the test's run folder (kept with
    `--btnav-out` when the test fails). A navigation failure is a report, never an
    exception: check it with `assert_reached`.
    """
    from ..mission.mission import Mission
    from ..mission.runner import run_mission as run

    if isinstance(mission, Mission):
        if overrides or keywords:
            raise TypeError(
                "overrides apply when a mission is loaded: pass its path "
                "(run_mission(path, **overrides)) or load it with btnav_mission(path, **overrides)"
            )
        loaded = mission
    else:
        loaded = load_mission(mission, overrides, **keywords)
    if out is not None:
        folder, picture = Path(out), False
    else:
        folder, picture = claim_folder(loaded.name)
    report = run(with_recorded_outputs(loaded, picture), folder)
    return RunResult(
        **{f.name: getattr(report, f.name) for f in dataclasses.fields(RunReport)},
        out_dir=folder,
        task_poses=list(loaded.spec.task.poses),
        world_file=loaded.world.file,
    )
