"""dwb_critics::MapGridCritic: the Manhattan cell distance to the nearest seed cell (path or goal).

Nav2 floods the whole grid from the seed cells; only the trajectory's scored
pose needs the value, so this looks up the nearest seed (Euclidean, as the
flood order) with a KD-tree and returns the Manhattan distance in cells to it.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from pydantic import Field
from scipy.spatial import cKDTree

from ....core import fmath
from ....costmap.cost_values import NO_INFORMATION
from ....costmap.costmap_2d import Costmap2D
from ....params.schema import one_of
from ..critic import Trajectories, TrajectoryCritic


def dense_plan(plan: NDArray[np.float64], resolution: float) -> NDArray[np.float64]:
    """nav_2d_utils::adjustPlanResolution: insert points so no gap exceeds the costmap resolution."""
    if len(plan) < 2:
        return plan[:, :2]
    seg = np.diff(plan[:, :2], axis=0)
    n = np.maximum(np.ceil(fmath.hypot(seg[:, 0], seg[:, 1]) / resolution).astype(int), 1)
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
        self._tree: cKDTree | None = None
        self._seeds = np.zeros((0, 2))

    def near_goal(self, pose, goal) -> bool:
        """Within the goal window where only the final yaw matters (the align critics' off switch).

        Nav2's PathAlign switches off within its forward_point_distance; btnav also switches
        PathAlign and GoalAlign off within the planner's `xy_goal_tolerance`, the window in which
        RotateToGoal allows only rotations. There, "point the nose at the path / at the goal
        point" is a different heading from the goal's yaw, and their score moves in whole cells
        (24 per cell for GoalAlign against RotateToGoal's 32 per radian), so it would hold the
        robot short of the yaw tolerance, dithering as the plan's cells shift.
        """
        radius = max(
            float(self.params.forward_point_distance),
            float(getattr(self.planner, "xy_goal_tolerance", 0.0)),
        )
        return (pose.x - goal.x) ** 2 + (pose.y - goal.y) ** 2 <= radius * radius

    def set_seeds(self, cells: NDArray[np.int64]) -> bool:
        if len(cells) == 0:
            self._tree = None
            return False
        self._seeds = np.unique(cells, axis=0).astype(float)
        self._tree = cKDTree(self._seeds)
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
        xy = self._points(trajs)
        S, T = xy.shape[:2]
        m, inside = costmap.world_to_map(xy)
        agg = self.params.aggregation_type
        query = m[:, -1] if agg == "last" else m.reshape(-1, 2)
        assert self._tree is not None
        _, nearest = self._tree.query(query.astype(float))
        manhattan = np.abs(self._seeds[nearest] - query).sum(axis=-1)
        if agg == "last":
            score = manhattan
        elif agg == "sum":
            score = manhattan.reshape(S, T).sum(axis=1)
        else:
            score = np.prod(manhattan.reshape(S, T), axis=1)
        off = ~inside.all(axis=1) if self.stop_on_failure else ~inside[:, -1]
        return np.where(off, np.inf, score.astype(float))
