"""A dock in a world file (`docks:`): where it stands, its plugin type and its body.

```yaml
docks:
  - {name: home_dock, type: simple_charging_dock, pose: [10.6, 1.0, 0.0]}
```

`pose` is where the robot's base frame is when it is docked (Nav2's dock pose), facing
the dock; `type` names the dock plugin section of the docking server that docks there.
The body is a box `size: [depth, width]` whose front face is `face` metres ahead of the
pose along the dock's x axis (default: the robot footprint's front, so a docked robot
touches it), with the detector's marker at the middle of that face.
"""

from __future__ import annotations

import math
from typing import Annotated, Any

from pydantic import AfterValidator, Field, field_validator

from ..core.validation import StrictModel


def _finite(v: tuple[float, ...]) -> tuple[float, ...]:
    if not all(math.isfinite(c) and abs(c) <= 1.0e5 for c in v):
        raise ValueError("expected finite numbers (metres and radians)")
    return v


class DockSpec(StrictModel):
    name: str = Field(min_length=1, max_length=200)
    type: str = Field(min_length=1, description="the docking server's dock plugin name")
    pose: Annotated[tuple[float, float, float], AfterValidator(_finite)]
    size: Annotated[tuple[float, float], AfterValidator(_finite)] = (0.1, 0.4)
    face: float | None = Field(None, ge=0.0, le=100.0, allow_inf_nan=False)

    @field_validator("size")
    @classmethod
    def _positive(cls, v: tuple[float, float]) -> tuple[float, float]:
        if not (v[0] >= 1e-3 and v[1] >= 1e-3):
            raise ValueError("a dock's size is [depth, width], both > 0")
        return v


def _unique(docks: list[Any]) -> list[Any]:
    seen: set[str] = set()
    for dock in docks:
        if dock.name in seen:
            raise ValueError(f"two docks are named '{dock.name}'; each dock needs its own name")
        seen.add(dock.name)
    return docks


#: The world file's `docks:` list.
Docks = Annotated[list[DockSpec], AfterValidator(_unique)]
