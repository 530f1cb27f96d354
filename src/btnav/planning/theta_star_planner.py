"""nav2_theta_star_planner::ThetaStarPlanner: any-angle A* with line-of-sight shortcuts.

Nav2's Theta* (theta_star.cpp): A* over cells at most MAX_NON_OBSTACLE (252), where an
expanded node first tries to hang from its grandparent along a Bresenham line of sight;
costs, errors and the path's poses follow Nav2. btnav differs where Nav2 misbehaves: the
path ends on the goal cell (Nav2's stops one short), a node whose f drops is queued again
(Nav2 lowers it in place and breaks its heap), and the start cell is free for this plan
only (Nav2 writes into the shared costmap). It is a plain heapq loop, so the slowest grid
planner. The full restatement: docs/decisions/0074.
"""

from __future__ import annotations

import heapq
import math
from collections.abc import Callable
from typing import Literal

import numpy as np
from numpy.typing import NDArray
from pydantic import Field

from ..core import fmath
from ..core.geometry import Pose2D
from ..core.messages import Path
from ..costmap.cost_values import FREE_SPACE, LETHAL_OBSTACLE, MAX_NON_OBSTACLE, NO_INFORMATION
from ..costmap.costmap_2d import Costmap2D
from ..plugins import register
from .exceptions import GoalOccupied, NoValidPathCouldBeFound, PlannerCancelled, PlannerException
from .global_planner import GlobalPlanner
from .plan_endpoints import one_pose_plan, set_final_orientation, start_and_goal_cells

#: (dx, dy) of the neighbours in Nav2's order: the 4 sides first, then the 4 corners.
MOVES = ((0, 1), (0, -1), (1, 0), (-1, 0), (1, -1), (-1, 1), (1, 1), (-1, -1))
#: Theta*'s scaled cell cost: `COST_OFFSET + COST_SCALE * cost`, in [26, 255.5].
COST_OFFSET, COST_SCALE = 26.0, 0.9


class ThetaStarGrid:
    """The costmap as one Theta* plan reads it, with a lethal border so that no neighbour
    needs a bounds check. Cells are flat indices into the bordered grid (width `w`); the
    per-cost-value tables turn a cell's cost into what the search needs of it."""

    def __init__(
        self, costs: NDArray[np.uint8], start: tuple[int, int], allow_unknown: bool, w_trav: float
    ) -> None:
        grid = np.pad(costs, 1, constant_values=LETHAL_OBSTACLE)
        grid[start[1] + 1, start[0] + 1] = FREE_SPACE  # clearStart, for this plan only
        self.w = costs.shape[1] + 2
        self.cells = grid.tobytes()
        value = np.arange(256)
        unknown = (value == NO_INFORMATION) & allow_unknown
        scaled = COST_OFFSET + COST_SCALE * value
        safe = (value <= MAX_NON_OBSTACLE) | unknown
        on_line = (scaled <= MAX_NON_OBSTACLE) | unknown
        on_line_scaled = np.where(unknown, float(LETHAL_OBSTACLE - 1), scaled)
        norm = w_trav / (MAX_NON_OBSTACLE * MAX_NON_OBSTACLE)
        #: By cost value: the traversal cost of entering a cell (inf: not safe), whether it
        #: is safe, and its traversal cost on a line of sight (-1: a line may not cross it).
        self.enter: list[float] = np.where(safe, norm * scaled * scaled, math.inf).tolist()
        self.safe: list[bool] = safe.tolist()
        self.line: list[float] = np.where(on_line, norm * on_line_scaled**2, -1.0).tolist()

    def line_of_sight(self, a: int, b: int) -> float:
        """The traversal cost of the Bresenham line from cell `a` to cell `b` (the cells it
        leaves), or -1 if it crosses a cell a line may not or cuts an unsafe corner."""
        w, cells, line, safe = self.w, self.cells, self.line, self.safe
        y0, x0 = divmod(a, w)
        y1, x1 = divmod(b, w)
        dx, sx = abs(x1 - x0), (1 if x0 < x1 else -1)
        dy, sy = abs(y1 - y0), (w if y0 < y1 else -w)
        err = dx - dy
        total = 0.0
        while a != b:
            cost = line[cells[a]]
            if cost < 0.0:
                return -1.0
            total += cost
            e2 = 2 * err
            if -dy < e2 <= dx:  # a diagonal step: the cells beside it must be safe
                if not (safe[cells[a + sx]] and safe[cells[a + sy]]):
                    return -1.0
                a += sx + sy
                err += dx - dy
            elif e2 > -dy:
                a += sx
                err -= dy
            else:
                a += sy
                err += dx
        return total


class ThetaStar:
    """One Theta* search on a ThetaStarGrid, between two of its cells."""

    def __init__(
        self, grid: ThetaStarGrid, src: int, dst: int, params: ThetaStarPlanner.Params
    ) -> None:
        self.grid, self.src, self.dst, self.p = grid, src, dst, params
        #: Expansions so far (Nav2's nodes_opened).
        self.nodes_opened = 0

    def run(self, cancel_checker: Callable[[], bool] | None = None) -> list[int] | None:
        """The tree's cells from start to goal, or None if there is no path."""
        grid, src, dst, p = self.grid, self.src, self.dst, self.p
        w, cells, enter = grid.w, grid.cells, grid.enter
        n = len(cells)
        g, h, f = [math.inf] * n, [math.inf] * n, [math.inf] * n
        parent = [-1] * n
        queued = bytearray(n)
        w_euc, w_h = p.w_euc_cost, min(p.w_euc_cost, 1.0)
        gy, gx = divmod(dst, w)
        moves = [
            (dx + dy * w, w_euc * math.sqrt(dx * dx + dy * dy))
            for dx, dy in MOVES[: p.how_many_corners]
        ]
        sqrt, push, pop = math.sqrt, heapq.heappush, heapq.heappop
        interval = p.terminal_checking_interval

        g[src] = enter[cells[src]]
        y, x = divmod(src, w)
        h[src] = w_h * sqrt((x - gx) * (x - gx) + (y - gy) * (y - gy))
        f[src] = g[src] + h[src]
        parent[src] = src
        heap: list[tuple[float, int, int]] = []
        pushes = 0
        u = src
        while True:
            self.nodes_opened += 1
            if self.nodes_opened % interval == 0 and cancel_checker and cancel_checker():
                raise PlannerCancelled("Planner was canceled")
            # resetParent: hang u from its grandparent if the line between them is clear
            queued[u] = 0
            grand = parent[parent[u]]
            los = grid.line_of_sight(u, grand)
            if los >= 0:
                y0, x0 = divmod(u, w)
                y1, x1 = divmod(grand, w)
                g_los = g[grand] + w_euc * sqrt((x1 - x0) * (x1 - x0) + (y1 - y0) * (y1 - y0)) + los
                if g_los < g[u]:
                    parent[u], g[u], f[u] = grand, g_los, g_los + h[u]
            if u == dst:
                return self._backtrace(parent)
            # setNeighbors: offer each neighbour a way through u
            g_u = g[u]
            for offset, step in moves:
                v = u + offset
                g_v = g_u + step + enter[cells[v]]
                if g_v == math.inf:
                    continue
                vy, vx = divmod(v, w)
                h_v = w_h * sqrt((vx - gx) * (vx - gx) + (vy - gy) * (vy - gy))
                if f[v] > g_v + h_v:
                    g[v], h[v], f[v], parent[v] = g_v, h_v, g_v + h_v, u
                    queued[v] = 1
                    push(heap, (f[v], pushes, v))
                    pushes += 1
            while heap:
                f_v, _, v = pop(heap)
                if queued[v] and f_v == f[v]:
                    break  # else an entry whose f has dropped since
            else:
                return None
            u = v

    def _backtrace(self, parent: list[int]) -> list[int]:
        path = [self.dst]
        while path[-1] != self.src:
            path.append(parent[path[-1]])
        return path[::-1]


def interpolate(points: NDArray[np.float64], step: float) -> NDArray[np.float64]:
    """Nav2's linearInterpolation: each segment from its first point in `step`s (a last
    partial step is left out), then the last point (which Nav2 leaves out)."""
    d = np.diff(points, axis=0)
    dist = fmath.hypot(d[:, 0], d[:, 1])
    counts = np.maximum((dist / step).astype(np.int64), 1)
    seg = np.repeat(np.arange(len(d)), counts)
    k = np.arange(len(seg)) - np.repeat(np.cumsum(counts) - counts, counts)
    along = (k * step / dist[seg])[:, None]
    return np.vstack([points[seg] + along * d[seg], points[-1:]])


@register(
    "planner", "nav2_theta_star_planner::ThetaStarPlanner", aliases=("btnav/ThetaStarPlanner",)
)
class ThetaStarPlanner(GlobalPlanner):
    """Theta* as Nav2 runs it (see the module's notes). `nodes_opened` holds the last
    plan's expansion count."""

    class Params(GlobalPlanner.Params):
        how_many_corners: Literal[4, 8] = Field(8, description="4 or 8 neighbours")
        w_euc_cost: float = Field(1.0, gt=0.0)
        w_traversal_cost: float = Field(2.0, ge=0.0)
        allow_unknown: bool = True
        terminal_checking_interval: int = Field(
            5000, gt=0, description="expansions between two calls of the cancel checker"
        )
        use_final_approach_orientation: bool = False

    params: Params

    def __init__(self, name: str, params: Params | None = None) -> None:
        super().__init__(name, params)
        self.nodes_opened = 0

    def create_plan(
        self,
        start: Pose2D,
        goal: Pose2D,
        costmap: Costmap2D,
        cancel_checker: Callable[[], bool] | None = None,
    ) -> Path:
        p = self.params
        (sx, sy), (gx, gy) = start_and_goal_cells(costmap, start, goal)
        goal_cost = int(costmap.costs[gy, gx])
        if goal_cost == LETHAL_OBSTACLE:
            raise GoalOccupied(
                f"Goal Coordinates of({goal.x:.6f}, {goal.y:.6f}) was in lethal cost"
            )
        frame = costmap.frame_id
        self.nodes_opened = 0
        if (sx, sy) == (gx, gy):
            return one_pose_plan(
                start.x, start.y, start, goal, p.use_final_approach_orientation, frame
            )
        if goal_cost > MAX_NON_OBSTACLE and not (goal_cost == NO_INFORMATION and p.allow_unknown):
            raise PlannerException("Either of the start or goal pose are an obstacle! ")
        grid = ThetaStarGrid(costmap.costs, (sx, sy), p.allow_unknown, p.w_traversal_cost)
        w = grid.w
        theta_star = ThetaStar(grid, (sy + 1) * w + sx + 1, (gy + 1) * w + gx + 1, p)
        try:
            cells = theta_star.run(cancel_checker)
        finally:
            self.nodes_opened = theta_star.nodes_opened
        if cells is None:
            raise NoValidPathCouldBeFound("Could not generate path between the given poses")
        idx = np.array(cells)
        corners = costmap.map_to_world(np.stack([idx % w - 1, idx // w - 1], axis=-1))
        xy = interpolate(corners, costmap.resolution)
        poses = np.zeros((len(xy), 3))
        poses[:, :2] = xy
        set_final_orientation(poses, start, goal, p.use_final_approach_orientation)
        return Path(0.0, poses, frame)
