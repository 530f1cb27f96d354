"""A mission in stages: the seeds' closed loop (map with SLAM, then navigate the map with
AMCL) as one file and one command.

```yaml
mission: office_closed_loop
world: ../worlds/small_office.yaml
params: ../params/nav2_params.yaml
initial_pose: [1.0, 1.0, 0.0]
stages:
  - name: map                # explore with SLAM; its map is saved
    localization: slam
    task: explore
  - name: tour               # the stack restarted on that map, with AMCL
    localization: amcl
    map: map                 # the map the `map` stage saved
    task: {follow_waypoints: [[3, 2, 1.57], [6, 3, 0]]}
```

Stages run in order, each on a fresh bring-up (a new world with the robot at the
mission's start, new servers: a relaunch), and each writes its outputs into its own
folder, `<out>/<stage>/`. A stage whose map a later stage uses saves it whatever its
`outputs` say. Every stage is checked before the first one runs; a stage that fails
ends the run, and the later ones are not run. `report.json` at the top holds each
stage's report.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from os import PathLike
from pathlib import Path
from typing import Any

from ..core.yaml_io import load_yaml
from .mission import Mission, find_mission, split_overrides
from .report import EXIT_SUCCEEDED, RunReport
from .runner import run_mission
from .spec import load_mission_spec
from .stage_doc import map_stages, mission_name, stage_names


@dataclass
class StagedReport:
    """What a staged mission did: one report per stage that ran, in order."""

    mission: str
    stages: list[tuple[str, RunReport]] = field(default_factory=list)
    planned: list[str] = field(default_factory=list)

    @property
    def succeeded(self) -> bool:
        return len(self.stages) == len(self.planned) and all(
            r.exit_code == EXIT_SUCCEEDED for _, r in self.stages
        )

    @property
    def exit_code(self) -> int:
        for _, report in self.stages:
            if report.exit_code != EXIT_SUCCEEDED:
                return report.exit_code
        return EXIT_SUCCEEDED

    def to_dict(self) -> dict[str, Any]:
        return {
            "mission": self.mission,
            "status": "succeeded" if self.succeeded else "failed",
            "stages": [{"stage": name, **r.to_dict()} for name, r in self.stages],
            "not_run": self.planned[len(self.stages) :],
        }

    def write(self, path: Path) -> None:
        path.write_text(json.dumps(self.to_dict(), indent=2) + "\n")


def is_staged(path: str | PathLike[str]) -> bool:
    file = find_mission(path)
    return bool(stage_names(load_yaml(file), str(file)))


def staged_mission_name(path: str | PathLike[str]) -> str:
    file = find_mission(path)
    return mission_name(load_yaml(file), str(file))


def run_stages(
    path: str | PathLike[str],
    out_dir: str | PathLike[str],
    *,
    seed: int | None = None,
    overrides: Mapping[str, Any] | None = None,
    origins: Mapping[str, str] | None = None,
    progress: Callable[[Mission], Callable[[Any], None] | None] | None = None,
    on_stage: Callable[[str, RunReport], None] | None = None,
    extra_outputs: set[str] | frozenset[str] = frozenset(),
) -> StagedReport:
    """Run every stage into `out_dir/<stage>/`; `progress(mission)` gives each stage's live
    status callback, `on_stage(stage, report)` hears each stage's end; `extra_outputs` are
    written by every stage (`btnav run --gif`)."""
    file = find_mission(path)
    doc = load_yaml(file)
    names = stage_names(doc, str(file))
    keep_map = map_stages(doc, str(file))
    mission_over, _ = split_overrides(overrides or {})
    for name in names:  # every stage's keys checked before anything runs
        load_mission_spec(file, mission_over, origins, stage=name)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    report = StagedReport(mission_name(doc, str(file)), planned=names)
    maps: dict[str, Path] = {}
    for name in names:
        mission = Mission.load(
            file, seed=seed, overrides=overrides, origins=origins, stage=name, stage_maps=maps
        )
        wanted = {"map"} if name in keep_map else set()
        for output in sorted((wanted | set(extra_outputs)) - set(mission.spec.outputs)):
            mission.spec.outputs.append(output)
        stage_out = out / name
        result = run_mission(mission, stage_out, None if progress is None else progress(mission))
        report.stages.append((name, result))
        maps[name] = stage_out / "map.yaml"
        if on_stage is not None:
            on_stage(name, result)
        if result.exit_code != EXIT_SUCCEEDED:
            break
    report.write(out / "report.json")
    return report
