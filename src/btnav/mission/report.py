"""`report.json`: what a run did, in the fields the brief fixes (and a few more)."""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

from ..core.error_codes import Outcome

EXIT_SUCCEEDED, EXIT_FAILED = 0, 1


@dataclass
class RunReport:
    mission: str
    seed: int
    status: str  # succeeded | failed | canceled
    error_code: int | None
    error_msg: str | None
    sim_time: float
    wall_time: float
    path_length: float
    collisions: int
    recoveries: int
    replans: int
    missed_waypoints: list[int]
    localization_error: dict[str, float]
    task: str = ""
    goals: int = 0
    outputs: list[str] = field(default_factory=list)
    #: One record per contact (`World.contacts`): time, pose [x, y, yaw], hit (wall or
    #: obstacle), index in the world file's list, kind and line; `collisions` counts them.
    contacts: list[dict[str, Any]] = field(default_factory=list)
    #: m^2 of free space on the SLAM map at the end (None: the run had a map, not SLAM).
    explored_area: float | None = None

    @property
    def succeeded(self) -> bool:
        return self.status == Outcome.SUCCEEDED.value

    @property
    def exit_code(self) -> int:
        """`btnav run`'s: 0 when the task succeeded, 1 when it failed or was canceled, or
        when waypoints were missed: Nav2's FollowWaypoints still succeeds then (the status
        stays `succeeded`), but a script or CI job asked for every waypoint."""
        return EXIT_SUCCEEDED if self.succeeded and not self.missed_waypoints else EXIT_FAILED

    @property
    def real_time_factor(self) -> float:
        return self.sim_time / self.wall_time if self.wall_time > 0 else float("inf")

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)

    def write(self, path: Path) -> None:
        path.write_text(json.dumps(self.to_dict(), indent=2) + "\n")

    def summary(self) -> str:
        """One line: the outcome, time, and what a user checks first."""
        head = f"{self.mission}: {self.status}"
        if self.succeeded and self.missed_waypoints:
            head += f" with {len(self.missed_waypoints)} of {self.goals} waypoints missed"
        if self.error_code is not None:
            head += f" (error {self.error_code}: {self.error_msg})"
        elif self.error_msg:
            head += f" ({self.error_msg})"
        parts = [
            f"{self.sim_time:.1f} s sim in {self.wall_time:.1f} s wall "
            f"({self.real_time_factor:.0f}x real time)",
            f"{self.path_length:.1f} m",
            f"{self.collisions} collision{'s' if self.collisions != 1 else ''}",
            f"{self.recoveries} recover{'ies' if self.recoveries != 1 else 'y'}",
        ]
        if self.explored_area is not None:
            parts.insert(1, f"{self.explored_area:.1f} m² explored")
        if self.task == "follow_waypoints" and self.succeeded:
            reached = self.goals - len(self.missed_waypoints)
            missed = f" (missed {self.missed_waypoints})" if self.missed_waypoints else ""
            parts.insert(1, f"{reached}/{self.goals} waypoints{missed}")
        elif self.missed_waypoints:
            parts.insert(1, f"missed waypoints {self.missed_waypoints}")
        return f"{head}: " + ", ".join(parts)
