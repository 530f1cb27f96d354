"""One stage of a staged mission, as the mission document it stands for.

A stage is the mission's top-level keys with the stage's own on top, so a stage says
only what changes (`localization`, `map`, `task`, `outputs`, ...). Its name is the
mission's name and the stage's (`office_closed_loop/map`), and every key keeps the line
it was written on, so a mistake in a stage is named at its line. A stage's `map:` may
name an earlier stage: the map that stage saved is used (`stage_maps`).
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

from ..core.suggest import best_match
from ..core.yaml_io import YamlMap, YamlSeq
from ..params.tree import copy_tree
from .errors import MissionError

STAGES = "stages"


def mission_name(doc: Any, file: str) -> str:
    """The mission's name: its `mission:` key, else the file's stem."""
    name = doc.get("mission") if isinstance(doc, YamlMap) else None
    return str(name or Path(file).stem)


def stage_names(doc: Any, file: str) -> list[str]:
    """The stages' names in order (none: not a staged mission); a malformed list is located."""
    if not isinstance(doc, YamlMap) or STAGES not in doc:
        return []
    stages = doc[STAGES]
    where = dict(file=file, line=doc.line_of(STAGES), key=STAGES)
    if not isinstance(stages, YamlSeq) or not stages:
        raise MissionError("stages is a list of stages, each a mapping with a name", **where)
    if "task" in doc:
        raise MissionError(
            "a mission with stages gives each stage its task, not one at the top",
            file=file,
            line=doc.line_of("task"),
            key="task",
        )
    names: list[str] = []
    for i, stage in enumerate(stages):
        line = stages.item_lines[i] if i < len(stages.item_lines) else where["line"]
        name = stage.get("name") if isinstance(stage, YamlMap) else None
        if not isinstance(name, str) or not name or "/" in name:
            raise MissionError(
                "each stage is a mapping with a `name:` (a word: it names its outputs folder)",
                file=file,
                line=line,
                key=f"stages[{i}]",
            )
        if name in names:
            raise MissionError(
                f"two stages are named '{name}'", file=file, line=line, key=f"stages[{i}].name"
            )
        if STAGES in stage:
            raise MissionError(
                "a stage has no stages of its own",
                file=file,
                line=stage.line_of(STAGES),
                key=f"stages[{i}].stages",
            )
        names.append(name)
    return names


def stage_doc(
    doc: YamlMap, stage: str, file: str, stage_maps: Mapping[str, Path] | None = None
) -> YamlMap:
    """The mission document of `stage`; `stage_maps` holds the maps earlier stages saved."""
    names = stage_names(doc, file)
    if stage not in names:
        raise MissionError(
            f"no stage '{stage}'; stages: {', '.join(names)}",
            file=file,
            line=doc.line_of(STAGES),
            key=STAGES,
            suggestion=best_match(stage, names),
        )
    i = names.index(stage)
    own: YamlMap = doc[STAGES][i]
    merged: YamlMap = copy_tree(doc)
    del merged[STAGES]
    merged.key_lines.pop(STAGES, None)
    merged.line = own.line  # a key the stage lacks is missed at the stage
    for key, value in own.items():
        if key == "name":
            continue
        merged[key] = copy_tree(value)
        if key in own.key_lines:
            merged.key_lines[key] = own.key_lines[key]
    merged["mission"] = f"{mission_name(doc, file)}/{stage}"
    wanted = merged.get("map")
    if isinstance(wanted, str) and wanted in names:
        if names.index(wanted) >= i:
            raise MissionError(
                f"stage '{stage}' uses the map of stage '{wanted}', which runs "
                f"{'later' if names.index(wanted) > i else 'as this very stage'}",
                file=file,
                line=merged.line_of("map"),
                key=f"stages[{i}].map",
            )
        if stage_maps is not None and wanted in stage_maps:
            merged["map"] = str(stage_maps[wanted])
    return merged


def map_stages(doc: YamlMap, file: str) -> set[str]:
    """The stages whose saved map a later stage uses (they must save it)."""
    names = stage_names(doc, file)
    used = set()
    for stage in doc.get(STAGES, []) if names else []:
        wanted = stage.get("map")
        if isinstance(wanted, str) and wanted in names:
            used.add(wanted)
    return used
