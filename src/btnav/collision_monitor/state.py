"""The monitor's and detector's reports (nav2_msgs CollisionMonitorState,
CollisionDetectorState) and the toggle service's answer (nav2_msgs/srv/Toggle)."""

from __future__ import annotations

from dataclasses import dataclass

from .action import ActionType


@dataclass(frozen=True)
class CollisionMonitorState:
    """The action now in force and the polygon that set it, from `stamp` on."""

    stamp: float
    action_type: ActionType
    polygon_name: str


@dataclass(frozen=True)
class CollisionDetectorState:
    """Per enabled polygon (in order), whether it holds at least `min_points` points."""

    stamp: float
    polygons: tuple[str, ...]
    detections: tuple[bool, ...]

    def detected(self, polygon: str) -> bool:
        return dict(zip(self.polygons, self.detections, strict=True)).get(polygon, False)


@dataclass(frozen=True)
class ToggleResponse:
    success: bool
    message: str
