"""Keys of Nav2's collision_detector: the monitor's zones and sources, checked at `frequency`.

The detector only reports (`collision_detector_state`), so every polygon's
`action_type` must be "none", as Nav2 refuses any other at configure.
"""

from __future__ import annotations

from pydantic import Field, model_validator

from .collision_monitor import ZonesAndSourcesParams
from .schema import FieldProblem


class CollisionDetectorParams(ZonesAndSourcesParams):
    """collision_detector: which zones hold sensed points, published each timer tick."""

    frequency: float = Field(10.0, gt=0.0)

    @model_validator(mode="after")
    def _report_only(self) -> CollisionDetectorParams:
        for name, polygon in self.polygon_sections.items():
            if polygon.action_type != "none":
                raise FieldProblem(
                    ("polygon_sections", name, "action_type"),
                    f'the collision detector only reports: action_type must be "none", '
                    f'not "{polygon.action_type}"',
                )
        return self
