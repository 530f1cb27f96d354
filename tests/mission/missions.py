"""Writing missions for tests: the small office, Nav2's params, files by absolute path."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import yaml

REPO = Path(__file__).resolve().parents[2]
WORLD = REPO / "worlds" / "small_office.yaml"
MAP = REPO / "maps" / "small_office.yaml"
PARAMS = REPO / "params" / "nav2_params.yaml"
TOUR = REPO / "missions" / "office_tour.yaml"
TOLERANCE = 0.25 + 0.02  # Nav2's xy_goal_tolerance, and a margin for the last step


def write_mission(folder: Path, name: str = "mission", **fields: Any) -> Path:
    doc: dict[str, Any] = {
        "mission": name,
        "world": str(WORLD),
        "params": str(PARAMS),
        "map": str(MAP),
        "localization": "ground_truth",
    }
    doc.update(fields)
    path = folder / f"{name}.yaml"
    path.write_text(yaml.safe_dump(doc, sort_keys=False))
    return path


def world_with(folder: Path, *obstacles: dict[str, Any]) -> Path:
    """The small office with extra obstacles (not in the map)."""
    doc = yaml.safe_load(WORLD.read_text())
    doc["obstacles"] = [*doc.get("obstacles", []), *obstacles]
    out = folder / "world.yaml"
    out.write_text(yaml.safe_dump(doc, sort_keys=False))
    return out


def read_report(out: Path) -> dict[str, Any]:
    return json.loads((out / "report.json").read_text())
