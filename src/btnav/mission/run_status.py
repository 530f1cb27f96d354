"""What a run is doing now, in words: the sim time, the real-time factor, the RUNNING
action nodes (ComputePathToPose, FollowPath, Spin, BackUp, ...) and the waypoint.

    12.4 s sim | 7x real time | FollowPath | waypoint 2/4

`btnav run` draws it on a terminal (`cli.status_line`), run.gif stamps it on its
frames, the run recorder keeps the running actions; computing it only reads the run.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

from py_trees.common import Status

from ..bt.nav2_actions import BtActionNode
from ..navigators.basic_navigator import BasicNavigator


def format_status(
    sim_time: float,
    real_time_factor: float | None,
    actions: list[str],
    waypoint: tuple[int, int] | None = None,
    width: int | None = None,
) -> str:
    """`12.4 s sim | 7x real time | FollowPath | waypoint 2/4`, cut to `width` characters.

    `real_time_factor` None (no wall time yet) and an empty `actions` are left out;
    `waypoint` is (1-based index, count).
    """
    parts = [f"{sim_time:.1f} s sim"]
    if real_time_factor is not None:
        parts.append(f"{real_time_factor:.0f}x real time")
    if actions:
        parts.append(", ".join(actions))
    if waypoint is not None:
        parts.append(f"waypoint {waypoint[0]}/{waypoint[1]}")
    line = " | ".join(parts)
    if width is not None and len(line) > width:
        line = line[: max(width - 3, 0)] + "..." if width > 3 else line[:width]
    return line


def running_actions(nav: BasicNavigator) -> list[str]:
    """The node types of the RUNNING leaves of the tree that runs the current goal, action
    nodes first (ComputePathToPose, FollowPath, Spin, ...), each once, in tree order."""
    for navigator in nav.bt_navigator.navigators.values():
        current = navigator.current
        if current is None or not current.active or navigator.root is None:
            continue
        leaves = [n for n in _depth_first(navigator.root) if not n.children]
        running = [n for n in leaves if n.status == Status.RUNNING]
        actions = [n for n in running if isinstance(n, BtActionNode)] or running
        return list(dict.fromkeys(type(n).__name__ for n in actions))
    return []


def _depth_first(node: Any) -> Iterator[Any]:
    yield node
    for child in node.children:
        yield from _depth_first(child)


def current_waypoint(nav: BasicNavigator, task: str, goals: int) -> tuple[int, int] | None:
    """(1-based index of the pose being driven to, number of poses), from the task's feedback."""
    feedback = nav.get_feedback()
    if task == "follow_waypoints" and feedback is not None:
        index = getattr(feedback, "current_waypoint", None)
        if index is not None:
            return min(int(index) + 1, goals), goals
    if task == "navigate_through_poses" and feedback is not None:
        left = getattr(feedback, "number_of_poses_remaining", None)
        if left is not None:
            return min(max(goals - int(left) + 1, 1), goals), goals
    return None
