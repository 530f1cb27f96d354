"""nav2_smac_planner::SmacPlanner2D: cost-aware 8-connected A* on the costmap, then smoothed.

The search is Nav2's AStarAlgorithm with Node2D: a step to one of the 8 neighbours costs
its length times `1 + cost_travel_multiplier * cost / 252`, the heuristic is the Euclidean
distance (so the path is the cheapest there is), and the goal `tolerance`,
`max_on_approach_iterations` and `max_iterations` end it with Nav2's error codes. btnav
puts path points at cell centres (Nav2's are half a cell off), breaks equal f by queue
order, and never enforces the wall-clock `max_planning_time`, so a plan does not depend on
the machine. The smoother is SimpleSmoother with Smac's settings. The full restatement:
docs/decisions/0074.
"""

from __future__ import annotations

import heapq
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from pydantic import Field

from ..core.geometry import Pose2D
from ..core.messages import Path
from ..costmap.cost_values import (
    INSCRIBED_INFLATED_OBSTACLE,
    LETHAL_OBSTACLE,
    MAX_NON_OBSTACLE,
    NO_INFORMATION,
)
from ..costmap.costmap_2d import Costmap2D
from ..params.schema import ParamsModel, ignored
from ..plugins import register
from .exceptions import (
    GoalOccupied,
    NoValidPathCouldBeFound,
    PlannerCancelled,
    PlannerTimedOut,
    StartOccupied,
)
from .global_planner import GlobalPlanner
from .plan_endpoints import one_pose_plan, set_final_orientation, start_and_goal_cells
from .simple_smoother import SimpleSmoother

SQRT2 = math.sqrt(2.0)
#: Smac smooths a path segment only when it spans more than this many steps.
MIN_SMOOTHED_STEPS = 10


def step_costs(
    cost_travel_multiplier: float, allow_unknown: bool
) -> tuple[list[float], list[float]]:
    """Node2D's traversal cost of entering a cell, by its cost value: (side, diagonal)
    steps; inf where the cell is not valid to enter."""
    cost = np.arange(256, dtype=np.float64)
    valid = (cost < INSCRIBED_INFLATED_OBSTACLE) | ((cost == NO_INFORMATION) & allow_unknown)
    side = np.where(valid, 1.0 + cost_travel_multiplier * cost / MAX_NON_OBSTACLE, math.inf)
    return side.tolist(), (SQRT2 * side).tolist()


def valid_cells(costs: NDArray[np.uint8], allow_unknown: bool) -> NDArray[np.bool_]:
    """GridCollisionChecker with a radius: below inscribed, or unknown when allowed."""
    return (costs < INSCRIBED_INFLATED_OBSTACLE) | ((costs == NO_INFORMATION) & allow_unknown)


def goal_valid(
    costs: NDArray[np.uint8], goal: tuple[float, float], radius: float, allow_unknown: bool
) -> bool:
    """GoalManager::removeInvalidGoals: the goal cell is valid, or (isZoneValid) a cell
    whose centre lies within `radius` cells of the goal point is (never, for a radius
    under one cell)."""
    gx, gy = math.floor(goal[0]), math.floor(goal[1])
    if valid_cells(costs[gy, gx], allow_unknown):
        return True
    if radius < 1:
        return False
    ny, nx = costs.shape
    x0, x1 = max(math.floor(goal[0] - radius), 0), min(math.ceil(goal[0] + radius) + 1, nx)
    y0, y1 = max(math.floor(goal[1] - radius), 0), min(math.ceil(goal[1] + radius) + 1, ny)
    ys, xs = np.mgrid[y0:y1, x0:x1]
    near = (xs + 0.5 - goal[0]) ** 2 + (ys + 0.5 - goal[1]) ** 2 <= radius * radius
    return bool(np.any(near & valid_cells(costs[y0:y1, x0:x1], allow_unknown)))


def downsample(costmap: Costmap2D, factor: int) -> Costmap2D:
    """Nav2's CostmapDownsampler: each coarse cell takes the highest cost of its block
    (so unknown, 255, outranks lethal, as in Nav2)."""
    ny, nx = costmap.costs.shape
    cy, cx = -(-ny // factor), -(-nx // factor)
    padded = np.zeros((cy * factor, cx * factor), np.uint8)  # cells off the map count 0
    padded[:ny, :nx] = costmap.costs
    coarse = padded.reshape(cy, factor, cx, factor).max(axis=(1, 3))
    return Costmap2D(
        coarse,
        costmap.resolution * factor,
        costmap.origin_x,
        costmap.origin_y,
        costmap.frame_id,
        NO_INFORMATION,
    )


@dataclass(frozen=True)
class SearchResult:
    """A* search's answer: cells (N, 2) (mx, my) from the start, whether the last is the
    goal cell, and how many nodes were expanded (Nav2's num_iterations)."""

    cells: NDArray[np.int64]
    reached_goal: bool
    iterations: int


def search(
    costs: NDArray[np.uint8],
    start: tuple[int, int],
    goal: tuple[float, float],
    tolerance: float,
    *,
    cost_travel_multiplier: float = 1.0,
    allow_unknown: bool = True,
    max_iterations: float = math.inf,
    max_on_approach_iterations: float = math.inf,
    terminal_checking_interval: int = 5000,
    cancel_checker: Callable[[], bool] | None = None,
) -> SearchResult:
    """Nav2's AStarAlgorithm::createPath with Node2D, from cell `start` to the map point
    `goal` (in cells; its cell is the goal node), `tolerance` in cells."""
    w = costs.shape[1] + 2  # the grid gets a lethal border, so no neighbour needs a bounds check
    cells = np.pad(costs, 1, constant_values=LETHAL_OBSTACLE).tobytes()
    side, diagonal = step_costs(cost_travel_multiplier, allow_unknown)
    moves = (
        (-1, side), (1, side), (-w, side), (w, side),
        (-w - 1, diagonal), (-w + 1, diagonal), (w - 1, diagonal), (w + 1, diagonal),
    )  # fmt: skip
    src = (start[1] + 1) * w + start[0] + 1
    dst = (math.floor(goal[1]) + 1) * w + math.floor(goal[0]) + 1
    hx, hy = goal[0] + 0.5, goal[1] + 0.5  # the goal, measured from padded cell centres

    n = len(cells)
    g = [math.inf] * n
    parent = [-1] * n
    visited = bytearray(n)
    g[src] = 0.0
    queue: list[tuple[float, int, int]] = [(0.0, 0, src)]
    pushes = 1  # equal f: first queued, first expanded
    best_h, best = math.inf, -1  # the queued cell closest to the goal
    iterations = approach = 0
    sqrt, push, pop = math.sqrt, heapq.heappush, heapq.heappop

    def cells_to(node: int) -> NDArray[np.int64]:
        chain = [node]
        while node != src:
            node = parent[node]
            chain.append(node)
        idx = np.array(chain[::-1], dtype=np.int64)
        return np.stack([idx % w - 1, idx // w - 1], axis=-1)

    while queue and iterations < max_iterations:
        _, _, u = pop(queue)
        if visited[u]:
            continue
        if iterations % terminal_checking_interval == 0 and cancel_checker and cancel_checker():
            raise PlannerCancelled("Planner was cancelled")
        iterations += 1
        visited[u] = 1
        if u == dst:
            return SearchResult(cells_to(u), True, iterations)
        if best_h < tolerance:
            approach += 1
            if approach >= max_on_approach_iterations:
                return SearchResult(cells_to(best), False, iterations)
        g_u = g[u]
        for offset, table in moves:
            v = u + offset
            g_v = g_u + table[cells[v]]
            if g_v < g[v] and not visited[v]:
                g[v] = g_v
                parent[v] = u
                y, x = divmod(v, w)
                h = sqrt((x - hx) * (x - hx) + (y - hy) * (y - hy))
                if h < best_h:
                    best_h, best = h, v
                push(queue, (g_v + h, pushes, v))
                pushes += 1
    if best_h < tolerance:
        return SearchResult(cells_to(best), False, iterations)
    if iterations == 1:
        raise StartOccupied("Start occupied")
    if iterations < max_iterations:
        raise NoValidPathCouldBeFound("no valid path found")
    raise PlannerTimedOut("exceeded maximum iterations")


class SmacSmootherParams(ParamsModel):
    """Smac's `smoother:` block (nav2_smac_planner's SmootherParams)."""

    max_iterations: int = Field(1000, ge=0, description="0 skips smoothing")
    w_smooth: float = Field(0.3, ge=0.0)
    w_data: float = Field(0.2, ge=0.0)
    tolerance: float = Field(1e-10, ge=0.0)
    do_refinement: bool = True
    refinement_num: int = Field(2, ge=0)


@register("planner", "nav2_smac_planner::SmacPlanner2D", aliases=("btnav/SmacPlanner2D",))
class SmacPlanner2D(GlobalPlanner):
    """Smac 2D as Nav2 configures and runs it (see the module's notes for the search).

    - The path runs from the start cell's centre through cell centres to the goal cell,
      whose point is then replaced by the goal itself; or, when only a cell within
      `tolerance` was reached, to that cell's centre.
    - After smoothing each pose faces the next (a path of up to 11 poses is not smoothed
      and keeps yaw 0); the last pose has the goal's yaw, or with
      `use_final_approach_orientation` the direction of the last segment.
    - `iterations` holds the last plan's A* expansion count (Nav2's num_iterations).
    """

    class Params(GlobalPlanner.Params):
        tolerance: float = Field(0.125, ge=0.0, description="metres around an unreachable goal")
        downsample_costmap: bool = False
        downsampling_factor: int = Field(1, ge=1)
        allow_unknown: bool = True
        max_iterations: int = Field(1_000_000, description="<= 0: no limit")
        max_on_approach_iterations: int = Field(1000, description="<= 0: no limit")
        terminal_checking_interval: int = Field(
            5000, gt=0, description="expansions between two calls of the cancel checker"
        )
        max_planning_time: float = ignored(
            2.0,
            "a wall-clock deadline would make plans depend on the machine's speed; "
            "btnav bounds planning by max_iterations",
            ge=0.0,
        )
        cost_travel_multiplier: float = Field(1.0, ge=0.0)
        use_final_approach_orientation: bool = False
        motion_model_for_search: str = ignored(
            "MOORE", "Nav2 dropped it from Smac 2D (2022): the search is always 8-connected"
        )
        smoother: SmacSmootherParams = Field(default_factory=SmacSmootherParams)

    params: Params

    def __init__(self, name: str, params: Params | None = None) -> None:
        super().__init__(name, params)
        #: A* expansions of the last plan (Nav2's num_iterations).
        self.iterations = 0

    def create_plan(
        self,
        start: Pose2D,
        goal: Pose2D,
        costmap: Costmap2D,
        cancel_checker: Callable[[], bool] | None = None,
    ) -> Path:
        p = self.params
        cm = costmap
        if p.downsample_costmap and p.downsampling_factor > 1:
            cm = downsample(costmap, p.downsampling_factor)
        (sx, sy), (gx, gy) = start_and_goal_cells(cm, start, goal)
        frame = costmap.frame_id
        self.iterations = 0
        if (sx, sy) == (gx, gy):
            return one_pose_plan(
                goal.x, goal.y, start, goal, p.use_final_approach_orientation, frame
            )
        res = cm.resolution
        goal_m = ((goal.x - cm.origin_x) / res, (goal.y - cm.origin_y) / res)
        tolerance = p.tolerance / res
        if not goal_valid(cm.costs, goal_m, tolerance, p.allow_unknown):
            raise GoalOccupied("Goal was in lethal cost")
        found = search(
            cm.costs,
            (sx, sy),
            goal_m,
            tolerance,
            cost_travel_multiplier=p.cost_travel_multiplier,
            allow_unknown=p.allow_unknown,
            max_iterations=p.max_iterations if p.max_iterations > 0 else math.inf,
            max_on_approach_iterations=(
                p.max_on_approach_iterations if p.max_on_approach_iterations > 0 else math.inf
            ),
            terminal_checking_interval=p.terminal_checking_interval,
            cancel_checker=cancel_checker,
        )
        self.iterations = found.iterations
        poses = np.zeros((len(found.cells), 3))
        poses[:, :2] = cm.map_to_world(found.cells)
        poses = self._smooth(Path(0.0, poses, frame), cm)
        if found.reached_goal:
            poses[-1, :2] = goal.x, goal.y
        set_final_orientation(poses, start, goal, p.use_final_approach_orientation)
        return Path(0.0, poses, frame)

    def _smooth(self, path: Path, costmap: Costmap2D) -> NDArray[np.float64]:
        """Smac's smoother: one holonomic segment, smoothed when long enough to matter."""
        s = self.params.smoother
        if s.max_iterations == 0 or len(path) - 1 <= MIN_SMOOTHED_STEPS:
            return path.poses
        smoother = SimpleSmoother(
            f"{self.name}.smoother",
            SimpleSmoother.Params(
                tolerance=s.tolerance,
                max_its=s.max_iterations,
                w_data=s.w_data,
                w_smooth=s.w_smooth,
                do_refinement=s.do_refinement,
                refinement_num=s.refinement_num,
                enforce_path_inversion=False,
                is_holonomic=True,
            ),
        )
        return smoother.smooth(path, costmap).path.poses
