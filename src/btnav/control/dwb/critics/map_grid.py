"""dwb_critics::MapGridCritic: each cell's Manhattan distance (cells) to the nearest seed cell.

Nav2 floods the grid from the seed cells (the plan, or the goal) with a 4-connected
queue ordered by Manhattan distance: a breadth-first search, so every cell gets its
smallest Manhattan distance to any seed, through obstacles too (Nav2's MapGridQueue
queues every cell). `scipy.ndimage.distance_transform_cdt` with the taxicab metric is
that same distance field as one vectorised pass.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from pydantic import Field
from scipy.ndimage import distance_transform_cdt

from ....core import fmath
from ....costmap.cost_values import NO_INFORMATION
from ....costmap.costmap_2d import Costmap2D
from ....params.schema import one_of
from ..critic import Trajectories, TrajectoryCritic


def dense_plan(plan: NDArray[np.float64], resolution: float) -> NDArray[np.float64]:
    """nav_2d_utils::adjustPlanResolution: a gap wider than two cells gets
    `int((gap - 2 res) / res) - 2` evenly spaced points (so still gaps of about a cell)."""
    if len(plan) < 2:
        return plan[:, :2]
    seg = np.diff(plan[:, :2], axis=0)
    sq = seg[:, 0] * seg[:, 0] + seg[:, 1] * seg[:, 1]
    min_sq = resolution * resolution * 4.0
    steps = np.zeros(len(seg), np.int64)
    wide = sq > min_sq
    steps[wide] = ((np.sqrt(sq[wide]) - np.sqrt(min_sq)) / resolution).astype(np.int64) - 1
    # each segment: its start point, then points j = 1 .. steps-1 at start + j * seg / steps
    n = np.maximum(steps, 1)
    idx = np.repeat(np.arange(len(seg)), n)
    frac = (np.arange(n.sum()) - np.repeat(np.cumsum(n) - n, n)) / np.repeat(n, n)
    pts = plan[idx, :2] + seg[idx] * frac[:, None]
    return np.vstack([pts, plan[-1:, :2]])


def plan_cells_on_costmap(plan: NDArray[np.float64], costmap: Costmap2D) -> NDArray[np.int64]:
    """The first contiguous run of plan cells that are on the map and not unknown (M, 2) (mx, my)."""
    pts = dense_plan(plan, costmap.resolution)
    m, inside = costmap.world_to_map(pts)
    ok = inside.copy()
    ok[inside] = costmap.costs[m[inside, 1], m[inside, 0]] != NO_INFORMATION
    good = np.flatnonzero(ok)
    if good.size == 0:
        return np.zeros((0, 2), np.int64)
    first = good[0]
    bad_after = np.flatnonzero(~ok[first:])
    end = first + bad_after[0] if bad_after.size else len(ok)
    return m[first:end]


class MapGridCritic(TrajectoryCritic):
    class Params(TrajectoryCritic.Params):
        aggregation_type: one_of("last", "sum", "product") = "last"  # type: ignore[valid-type]
        forward_point_distance: float = Field(0.325, ge=0.0)

    #: PathDist/GoalDist reject trajectories leaving the grid; the Align critics do not.
    stop_on_failure = True
    forward_distance = 0.0

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        #: (ny, nx) Manhattan cells to the nearest seed (Nav2's cell_values_).
        self._cell_values: NDArray[np.int32] | None = None
        self._in_goal_window = False

    def near_goal(self, pose, goal) -> bool:
        """Within the goal window where only the final yaw matters (the align critics' off switch).

        Nav2's PathAlign switches off within its forward_point_distance; btnav also switches
        PathAlign and GoalAlign off within the planner's `xy_goal_tolerance`, the window in which
        RotateToGoal allows only rotations. There, "point the nose at the path / at the goal
        point" is a different heading from the goal's yaw, and their score moves in whole cells
        (24 per cell for GoalAlign against RotateToGoal's 32 per radian), so it would hold the
        robot short of the yaw tolerance, dithering as the plan's cells shift. Once entered,
        that window holds until a new plan, as RotateToGoal's does: a robot whose estimate
        drifts a centimetre out while it turns in place is still turning to the goal's yaw
        (with the switch per cycle, GoalAlign came back on then and turned it the wrong way).
        """
        d2 = (pose.x - goal.x) ** 2 + (pose.y - goal.y) ** 2
        tolerance = float(getattr(self.planner, "xy_goal_tolerance", 0.0))
        self._in_goal_window = self._in_goal_window or d2 <= tolerance * tolerance
        ahead = float(self.params.forward_point_distance)
        return self._in_goal_window or d2 <= ahead * ahead

    def reset(self) -> None:
        """A new plan: the goal window is left."""
        self._in_goal_window = False

    def set_seeds(self, cells: NDArray[np.int64], costmap: Costmap2D) -> bool:
        """Flood the costmap's grid from `cells` (mx, my); False (prepare fails) if none."""
        if len(cells) == 0:
            self._cell_values = None
            return False
        free = np.ones(costmap.costs.shape, bool)
        free[cells[:, 1], cells[:, 0]] = False
        self._cell_values = distance_transform_cdt(free, metric="taxicab")
        return True

    def _points(self, trajs: Trajectories) -> NDArray[np.float64]:
        poses = trajs.poses
        if self.params.aggregation_type == "last" and not self.stop_on_failure:
            poses = poses[:, -1:, :]
        d = self.forward_distance
        if d:
            s, c = fmath.sincos(poses[..., 2])
            xy = poses[..., :2] + d * np.stack([c, s], -1)
        else:
            xy = poses[..., :2]
        return xy

    def score(self, trajs: Trajectories, costmap: Costmap2D) -> NDArray[np.float64]:
        """Nav2's scoreTrajectory: every scored pose must be on the grid (else illegal)."""
        m, inside = costmap.world_to_map(self._points(trajs))
        assert self._cell_values is not None
        ny, nx = self._cell_values.shape
        values = self._cell_values[
            np.clip(m[..., 1], 0, ny - 1), np.clip(m[..., 0], 0, nx - 1)
        ].astype(float)
        agg = self.params.aggregation_type
        if agg == "last":
            score = values[:, -1]
        elif agg == "sum":
            score = values.sum(axis=1)
        else:
            score = np.prod(values, axis=1)
        return np.where(inside.all(axis=1), score, np.inf)
