"""`btnav_example::AStarPlanner`: a plain 8-connected A* on the global costmap.

The planner a student writes first, and a fair one to compare NavFn with: the same
costmap, the same start and goal, a different search. A step between two cells costs
its length times the mean of the two cells' penalties, `1 + cost_weight * cost / 252`,
so `cost_weight: 0` gives the shortest path that keeps the robot's centre out of
inscribed cells, and larger weights trade length for distance from obstacles (the
inflation layer's costs). The octile distance never overestimates such a cost, so the
path is optimal for it.

The numpy arrays that matter (penalties, the heuristic of every cell) are made at
once; only the search itself is a Python loop over a `heapq`, as in a textbook.
"""

from __future__ import annotations

import heapq
import math
from collections.abc import Callable

import numpy as np
from btnav.core.geometry import Pose2D
from btnav.core.messages import Path
from btnav.costmap.cost_values import (
    INSCRIBED_INFLATED_OBSTACLE,
    LETHAL_OBSTACLE,
    MAX_NON_OBSTACLE,
    NO_INFORMATION,
)
from btnav.costmap.costmap_2d import Costmap2D
from btnav.planning.exceptions import (
    GoalOccupied,
    GoalOutsideMapBounds,
    NoValidPathCouldBeFound,
    PlannerCancelled,
    StartOccupied,
    StartOutsideMapBounds,
)
from btnav.planning.global_planner import GlobalPlanner
from btnav.plugins import register
from numpy.typing import NDArray
from pydantic import Field

SQRT2 = math.sqrt(2.0)
#: Expansions between two calls of the planner server's `cancel_checker` (the first
#: expansion calls it too).
CANCEL_CHECK_EVERY = 1024


def step_penalties(
    costs: NDArray[np.uint8], cost_weight: float, allow_unknown: bool
) -> NDArray[np.float64]:
    """Each cell's penalty per cell length: `1 + cost_weight * cost / 252`; inf where blocked.

    Inscribed and lethal cells are blocked; unknown cells cost as free space when
    `allow_unknown`, and are blocked otherwise (Nav2's `allow_unknown`).
    """
    c = np.asarray(costs)
    penalty = 1.0 + cost_weight * np.minimum(c, MAX_NON_OBSTACLE) / MAX_NON_OBSTACLE
    penalty[c >= INSCRIBED_INFLATED_OBSTACLE] = np.inf
    if allow_unknown:
        penalty[c == NO_INFORMATION] = 1.0
    return penalty


def octile(shape: tuple[int, int], goal: tuple[int, int]) -> NDArray[np.float64]:
    """The octile distance (in cells) from every cell of a `shape` grid to `goal` (x, y)."""
    ys, xs = np.indices(shape)
    dx, dy = np.abs(xs - goal[0]), np.abs(ys - goal[1])
    return (dx + dy) + (SQRT2 - 2.0) * np.minimum(dx, dy)


def astar(
    penalty: NDArray[np.float64],
    start: tuple[int, int],
    goal: tuple[int, int],
    cancel_checker: Callable[[], bool] | None = None,
) -> list[tuple[int, int]] | None:
    """The cheapest 8-connected chain of cells (x, y) from `start` to `goal`, or None.

    `penalty` is `step_penalties`' grid (ny, nx). A diagonal step may not cut the
    corner of a blocked cell; the start cell is never blocked. Raises
    `PlannerCancelled` when `cancel_checker` says so.
    """
    ny, nx = penalty.shape
    w = nx + 2  # a border of blocked cells: no bounds checks in the loop
    padded = np.full((ny + 2, w), np.inf)
    padded[1:-1, 1:-1] = penalty
    cost = padded.ravel().tolist()
    h_grid = np.zeros((ny + 2, w))
    h_grid[1:-1, 1:-1] = octile((ny, nx), goal)
    h = h_grid.ravel().tolist()
    s = (start[1] + 1) * w + start[0] + 1
    g = (goal[1] + 1) * w + goal[0] + 1
    # (offset, length, the two cells a diagonal passes between: both must be free)
    moves = [(1, 1.0, 0, 0), (-1, 1.0, 0, 0), (w, 1.0, 0, 0), (-w, 1.0, 0, 0)]
    moves += [(dy + dx, SQRT2, dx, dy) for dx in (1, -1) for dy in (w, -w)]
    inf = math.inf
    best = [inf] * len(cost)
    parent = [-1] * len(cost)
    closed = bytearray(len(cost))
    if cost[s] == inf:
        cost[s] = 1.0  # the robot may leave the (inscribed) cell it is in
    best[s] = 0.0
    heap = [(h[s], h[s], s)]  # (f, h, cell): ties go to the cell nearer the goal
    expansions = 0
    while heap:
        _, _, u = heapq.heappop(heap)
        if closed[u]:
            continue
        if u == g:
            break
        closed[u] = 1
        expansions += 1
        if cancel_checker and expansions % CANCEL_CHECK_EVERY == 1 and cancel_checker():
            raise PlannerCancelled("A* was cancelled")
        gu, cu = best[u], cost[u]
        for offset, length, side_a, side_b in moves:
            v = u + offset
            cv = cost[v]
            if cv == inf or closed[v]:
                continue
            if side_a and (cost[u + side_a] == inf or cost[u + side_b] == inf):
                continue
            ng = gu + length * 0.5 * (cu + cv)
            if ng < best[v]:
                best[v] = ng
                parent[v] = u
                heapq.heappush(heap, (ng + h[v], h[v], v))
    if parent[g] == -1 and g != s:
        return None
    chain = [g]
    while chain[-1] != s:
        chain.append(parent[chain[-1]])
    return [(c % w - 1, c // w - 1) for c in reversed(chain)]


@register("planner", "btnav_example::AStarPlanner")
class AStarPlanner(GlobalPlanner):
    """8-connected A* on the global costmap; poses face along the path, the last the goal's yaw."""

    class Params(GlobalPlanner.Params):
        cost_weight: float = Field(
            1.0, ge=0.0, description="how much a cell's cost (0-252) lengthens a step through it"
        )
        allow_unknown: bool = True

    params: Params

    def create_plan(
        self,
        start: Pose2D,
        goal: Pose2D,
        costmap: Costmap2D,
        cancel_checker: Callable[[], bool] | None = None,
    ) -> Path:
        (sx, sy), start_in = costmap.world_to_map([start.x, start.y])
        if not start_in:
            raise StartOutsideMapBounds(f"start ({start.x:.2f}, {start.y:.2f}) is off the map")
        (gx, gy), goal_in = costmap.world_to_map([goal.x, goal.y])
        if not goal_in:
            raise GoalOutsideMapBounds(f"goal ({goal.x:.2f}, {goal.y:.2f}) is off the map")
        costs = costmap.costs
        if costs[sy, sx] == LETHAL_OBSTACLE:
            raise StartOccupied(f"start ({start.x:.2f}, {start.y:.2f}) is in an obstacle")
        if costs[gy, gx] in (LETHAL_OBSTACLE, INSCRIBED_INFLATED_OBSTACLE):
            raise GoalOccupied(f"goal ({goal.x:.2f}, {goal.y:.2f}) is in an obstacle")

        penalty = step_penalties(costs, self.params.cost_weight, self.params.allow_unknown)
        cells = astar(penalty, (int(sx), int(sy)), (int(gx), int(gy)), cancel_checker)
        if cells is None:
            raise NoValidPathCouldBeFound(
                f"no path from ({start.x:.2f}, {start.y:.2f}) to ({goal.x:.2f}, {goal.y:.2f})"
            )
        xy = costmap.map_to_world(np.array(cells, dtype=np.int64))
        xy[0] = start.x, start.y  # from the robot itself to the goal itself
        if len(xy) == 1:
            xy = np.array([[start.x, start.y], [goal.x, goal.y]])
        xy[-1] = goal.x, goal.y
        poses = np.zeros((len(xy), 3))
        poses[:, :2] = xy
        d = np.diff(xy, axis=0)
        poses[:-1, 2] = np.arctan2(d[:, 1], d[:, 0])
        poses[-1, 2] = goal.yaw
        return Path(0.0, poses, costmap.frame_id)
