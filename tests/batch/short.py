"""Short missions for batch tests: the small office, one goal a metre away (~1 s each)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from ..mission.missions import write_mission

INFLATION = "local_costmap.local_costmap.inflation_layer.inflation_radius"


def short_mission(folder: Path, name: str = "short", **fields: Any) -> Path:
    doc: dict[str, Any] = {
        "initial_pose": [1.0, 1.0, 0.0],
        "task": {"navigate_to_pose": [2.0, 1.2, 0.0]},
        "time_limit": 30,
        "seed": 0,
        "outputs": ["report", "trajectory"],
    }
    doc.update(fields)
    return write_mission(folder, name, **doc)
