"""The ends of a plan as Nav2's grid planners (Smac 2D, Theta*) set them.

Both planners reject a start or goal off the map with the same messages, answer a start
and goal in one cell with a one-pose plan, and give the last pose the goal's yaw, or
with `use_final_approach_orientation` the direction the plan arrives from (a one-pose
plan then keeps the start's yaw, so the controller does not turn on the spot).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ..core import fmath
from ..core.geometry import Pose2D
from ..core.messages import Path
from ..costmap.costmap_2d import Costmap2D
from .exceptions import GoalOutsideMapBounds, StartOutsideMapBounds


def start_and_goal_cells(
    costmap: Costmap2D, start: Pose2D, goal: Pose2D
) -> tuple[tuple[int, int], tuple[int, int]]:
    """The (mx, my) cells of start and goal; off the map raises Nav2's bounds errors."""
    (sx, sy), start_in = costmap.world_to_map([start.x, start.y])
    if not start_in:
        raise StartOutsideMapBounds(
            f"Start Coordinates of({start.x:.6f}, {start.y:.6f}) was outside bounds"
        )
    (gx, gy), goal_in = costmap.world_to_map([goal.x, goal.y])
    if not goal_in:
        raise GoalOutsideMapBounds(
            f"Goal Coordinates of({goal.x:.6f}, {goal.y:.6f}) was outside bounds"
        )
    return (int(sx), int(sy)), (int(gx), int(gy))


def one_pose_plan(
    x: float,
    y: float,
    start: Pose2D,
    goal: Pose2D,
    use_final_approach_orientation: bool,
    frame: str,
) -> Path:
    """The plan of a start and goal in one cell: one pose at (x, y)."""
    yaw = start.yaw if use_final_approach_orientation else goal.yaw
    return Path(0.0, np.array([[x, y, yaw]]), frame)


def set_final_orientation(
    poses: NDArray[np.float64], start: Pose2D, goal: Pose2D, use_final_approach_orientation: bool
) -> None:
    """The last pose's yaw, in place: the goal's, or the direction of the last segment."""
    if not use_final_approach_orientation:
        poses[-1, 2] = goal.yaw
    elif len(poses) == 1:
        poses[-1, 2] = start.yaw
    else:
        d = poses[-1, :2] - poses[-2, :2]
        poses[-1, 2] = fmath.arctan2(float(d[1]), float(d[0]))
