"""`report.json`: what a run did, in the fields the brief fixes (and a few more).

`missed_waypoints` stays the list of indices scripts read; `missed_waypoint_statuses`
says why each was missed, as Nav2's WaypointStatus does (index, pose, error code and
message, FAILED), plus what Nav2's message leaves out: the code's name, the tree node
that failed last and the sim time. `btnav run` prints one line per missed waypoint.
"""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

from ..core.error_codes import ERROR_CODES, Outcome

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
    #: Why each waypoint of `missed_waypoints` was missed (`waypoint_status`), in order.
    missed_waypoint_statuses: list[dict[str, Any]] = field(default_factory=list)

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

    def missed_lines(self) -> list[str]:
        """One line per missed waypoint: where it was, Nav2's error, the node and the time."""
        return [missed_line(status) for status in self.missed_waypoint_statuses]


def error_code_name(code: int) -> str:
    """Nav2's name of a result code (`204` -> `GOAL_OUTSIDE_MAP`): each action has its own
    hundreds, and 0, 1, 2 mean the same in every action; the number if no action has it."""
    for table in ERROR_CODES.values():
        try:
            return table(code).name
        except ValueError:
            continue
    return str(code)


def waypoint_status(
    index: int,
    pose: Any,
    error_code: int,
    error_msg: str,
    sim_time: float | None,
    failed_node: dict[str, str] | None = None,
) -> dict[str, Any]:
    """A missed waypoint as report.json writes it: Nav2's WaypointStatus fields (FAILED)
    with the code's name, the tree node that failed last (`{name, type}`, its name as
    bt_log.jsonl writes it; None when no node failed, as when the task at the waypoint
    failed) and the sim time the waypoint was given up (None if the result has none)."""
    return {
        "waypoint_index": index,
        "waypoint_status": "FAILED",
        "waypoint_pose": [float(v) for v in pose],
        "error_code": int(error_code),
        "error_code_name": error_code_name(int(error_code)),
        "error_msg": error_msg,
        "failed_node": failed_node,
        "sim_time": None if sim_time is None else round(float(sim_time), 6),
    }


def missed_line(status: dict[str, Any]) -> str:
    """`missed waypoint 1 (20, 3, 0): error 204 GOAL_OUTSIDE_MAP "..."; ComputePathToPose
    failed last, at 12.3 s sim`."""
    pose = ", ".join(f"{v:g}" for v in status["waypoint_pose"])
    text = (
        f"missed waypoint {status['waypoint_index']} ({pose}): error {status['error_code']} "
        f"{status['error_code_name']}"
    )
    if status["error_msg"]:
        text += f' "{status["error_msg"]}"'
    node = status.get("failed_node")
    if node:  # its own name, without the names of the nodes above it
        name = node["name"].rsplit(".", 1)[-1]
        shown = node["type"] if name in (node["type"], "") else f"{name} ({node['type']})"
        text += f"; {shown} failed last"
    when = status.get("sim_time")
    return text if when is None else f"{text}, at {when:.1f} s sim"
