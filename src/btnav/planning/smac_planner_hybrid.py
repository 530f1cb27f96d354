"""nav2_smac_planner::SmacPlannerHybrid: Hybrid-A* for car-like and differential bases.

The search is Nav2's, in cells: a node is a continuous (x, y) with a heading bin, its
children Nav2's motion primitives (straight, tightest arcs, interpolated arcs, reversed for
`REEDS_SHEPP`), step costs as NodeHybrid::getTraversalCost; the heuristic, analytic
expansion, goal approach and collision checks are shared with the lattice (`smac_common`).
btnav's heuristic is the straight line, not Nav2's precomputed table, and the search stops
after `max_iterations`, never on wall-clock time, so a plan does not depend on the
machine. It runs compiled (hybrid_kernel) with the Python search's plans bit for bit
(`BTNAV_SMAC=python`). Details and timings: docs/decisions/0073 and 0005.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any, Literal

import numpy as np
from pydantic import Field

from ..core import fmath
from ..core.geometry import Pose2D
from ..core.messages import Path
from ..costmap.costmap_2d import Costmap2D
from ..params.schema import ignored
from ..plugins import register
from . import hybrid_kernel
from .exceptions import (
    GoalOccupied,
    GoalOutsideMapBounds,
    StartOccupied,
    StartOutsideMapBounds,
)
from .global_planner import GlobalPlanner
from .smac_common import (
    DEFAULT_METHOD,
    AnalyticExpansion,
    CellPose,
    Child,
    GridCollisionChecker,
    HeuristicCache,
    Node,
    SmacMethod,
    SmacParams,
    SmacSearch,
    SmacSmootherParams,
    cells_to_world,
    max_curvature,
    smooth_path,
    traversal_norms,
)

__all__ = ["HybridSmootherParams", "Primitives", "SmacPlannerHybrid", "max_curvature"]

SQRT2 = math.sqrt(2.0)
#: A turning primitive's direction, as Nav2's TurnDirection.
FORWARD, LEFT, RIGHT, REVERSE, REV_LEFT, REV_RIGHT = range(6)
#: The smoother block's model (its old name here).
HybridSmootherParams = SmacSmootherParams


class Primitives:
    """Nav2's HybridMotionTable for one turning radius (cells) and bin count: each
    primitive's (dx, dy) rotated to every heading bin, its heading change in bins,
    its turn direction and its travel length."""

    def __init__(self, radius: float, bins: int, reverse: bool, interpolate: bool) -> None:
        bin_size = 2.0 * math.pi / bins
        half_chord = min(1.0, SQRT2 / (2.0 * radius))  # asin, through fmath's arctan2
        angle = 2.0 * fmath.arctan2(half_chord, math.sqrt(1.0 - half_chord * half_chord))
        increments = 1 if angle < bin_size else math.ceil(angle / bin_size)
        angle = increments * bin_size
        s, c = fmath.sincos(angle)
        dx, dy = radius * s, radius - radius * c
        chord = fmath.hypot(dx, dy)
        prims: list[tuple[float, float, int, int]] = [
            (chord, 0.0, 0, FORWARD),
            (dx, dy, increments, LEFT),
            (dx, -dy, -increments, RIGHT),
        ]
        if interpolate:
            for i in range(1, increments):
                a = i * bin_size
                r = chord / (2.0 * fmath.sin(a / 2.0))
                si, ci = fmath.sincos(a)
                prims += [(r * si, r - r * ci, i, LEFT), (r * si, -(r - r * ci), -i, RIGHT)]
        if reverse:
            back = {FORWARD: REVERSE, LEFT: REV_LEFT, RIGHT: REV_RIGHT}
            prims += [(-x, y, -t, back[d]) for x, y, t, d in prims]
        self.bins = bins
        self.bin_size = bin_size
        self.turns = [t for _, _, t, _ in prims]
        self.directions = [d for *_, d in prims]
        self.lengths = []
        for x, y, t, _ in prims:
            if t == 0:
                self.lengths.append(fmath.hypot(x, y))
            else:
                arc = abs(t) * bin_size
                self.lengths.append(fmath.hypot(x, y) / (2.0 * fmath.sin(arc / 2.0)) * arc)
        heading = np.arange(bins) * bin_size
        sh, ch = fmath.sincos(heading)
        px = np.array([p[0] for p in prims])
        py = np.array([p[1] for p in prims])
        #: Per heading bin, the primitives' steps (lists: scalar code reads them fastest).
        self.dx = (px[None, :] * ch[:, None] - py[None, :] * sh[:, None]).tolist()
        self.dy = (px[None, :] * sh[:, None] + py[None, :] * ch[:, None]).tolist()
        #: Per heading bin, each primitive's child bin.
        self.child_bins = [[(b + t) % bins for t in self.turns] for b in range(bins)]
        #: Each bin's yaw (a node's heading).
        self.yaws = [b * bin_size for b in range(bins)]


@register(
    "planner",
    "nav2_smac_planner::SmacPlannerHybrid",
    aliases=("btnav/SmacPlannerHybrid",),
)
class SmacPlannerHybrid(GlobalPlanner):
    """Hybrid-A* with Nav2's params and defaults (see the module's docstring)."""

    class Params(SmacParams):
        downsample_costmap: bool = ignored(False, "btnav searches the costmap at its resolution")
        downsampling_factor: int = ignored(1, "btnav searches the costmap at its resolution")
        angle_quantization_bins: int = Field(72, ge=4, le=720)
        minimum_turning_radius: float = Field(0.4, gt=0.0, description="m")
        allow_primitive_interpolation: bool = False
        motion_model_for_search: Literal["DUBIN", "REEDS_SHEPP"] = "DUBIN"

    params: Params

    def __init__(self, name: str, params: Params | None = None) -> None:
        super().__init__(name, params)
        self._primitives: tuple[tuple[Any, ...], Primitives] | None = None
        self._heuristic = HeuristicCache()
        #: Nodes the last search expanded (for tests and benchmarks).
        self.expansions = 0
        #: The compiled search or the Python reference (the same plans; BTNAV_SMAC=python).
        self.method: SmacMethod = DEFAULT_METHOD

    def _table(self, resolution: float) -> Primitives:
        p = self.params
        key = (resolution, p.minimum_turning_radius, p.angle_quantization_bins,
               p.motion_model_for_search, p.allow_primitive_interpolation)  # fmt: skip
        if self._primitives is None or self._primitives[0] != key:
            table = Primitives(
                p.minimum_turning_radius / resolution,
                p.angle_quantization_bins,
                p.motion_model_for_search == "REEDS_SHEPP",
                p.allow_primitive_interpolation,
            )
            self._primitives = (key, table)
        return self._primitives[1]

    # -- nav2_core::GlobalPlanner ------------------------------------------------------------

    def create_plan(
        self,
        start: Pose2D,
        goal: Pose2D,
        costmap: Costmap2D,
        cancel_checker: Callable[[], bool] | None = None,
    ) -> Path:
        p = self.params
        res = costmap.resolution
        table = self._table(res)
        checker = GridCollisionChecker(costmap, self.costmap_ros, p.allow_unknown, table.bins)

        def cells(pose: Pose2D) -> tuple[float, float]:
            return (pose.x - costmap.origin_x) / res, (pose.y - costmap.origin_y) / res

        sx, sy = cells(start)
        gx, gy = cells(goal)
        if checker.cell(sx, sy) < 0:
            raise StartOutsideMapBounds(f"start ({start.x:.2f}, {start.y:.2f}) is off the costmap")
        if checker.cell(gx, gy) < 0:
            raise GoalOutsideMapBounds(f"goal ({goal.x:.2f}, {goal.y:.2f}) is off the costmap")
        if checker.colliding([sx], [sy], [start.yaw])[0]:
            raise StartOccupied("the start pose is in collision")
        if checker.colliding([gx], [gy], [goal.yaw])[0]:
            raise GoalOccupied("the goal pose is in collision")

        heuristic = self._heuristic.get(
            costmap, (math.floor(gx), math.floor(gy)), p.cost_penalty,
            p.downsample_obstacle_heuristic, p.cache_obstacle_heuristic,
        )  # fmt: skip
        model = p.motion_model_for_search
        radius = p.minimum_turning_radius / res
        analytic = AnalyticExpansion(model, radius, checker, p, self.method)
        search = SmacSearch(p, checker, heuristic, analytic, table.bins, table.yaws)
        bins, bin_size = table.bins, table.bin_size
        start_cell = (sx, sy, round(start.yaw / bin_size) % bins)
        goal_cell = (gx, gy, goal.yaw)
        goal_bin = round(goal.yaw / bin_size) % bins
        norms = traversal_norms(costmap, p.use_quadratic_cost_penalty)
        try:
            if self.method == "kernel":
                tables = self._kernel_tables(
                    table, checker, norms, self._heuristic.array,
                    search.key(gx, gy, goal_bin), goal_cell, cancel_checker is not None,
                )  # fmt: skip
                found = hybrid_kernel.run(search, tables, start_cell, goal_cell, cancel_checker)
            else:
                expand = self._expansion(table, checker, norms)
                found = search.run(start_cell, goal_cell, goal_bin, expand, cancel_checker)
        finally:
            self.expansions = search.expansions
        nodes = found.nodes
        poses: list[CellPose] = [
            (nodes[i][0], nodes[i][1], table.yaws[nodes[i][2]]) for i in found.chain()
        ]
        path = Path(0.0, cells_to_world(poses + found.tail, costmap), costmap.frame_id)
        if not p.smooth_path:
            return path
        return smooth_path(path, costmap, p.smoother, p.minimum_turning_radius)

    # -- the search ------------------------------------------------------------------------

    def _step_factors(
        self, table: Primitives, norms: np.ndarray
    ) -> tuple[np.ndarray, list[list[float]], list[float]]:
        """Nav2's NodeHybrid::getTraversalCost as tables for this plan. A step's cost is
        length * (reward + cost_penalty * norm) * turn * reverse, in that order: the first
        factor per cell, the turn's per (parent's turn + 1, primitive) (row 0: the start,
        no turn penalty) and the reverse one per primitive (1.0: none)."""
        p = self.params
        reward = 1.0 - p.retrospective_penalty
        per_cell = reward + p.cost_penalty * norms
        directions = table.directions
        reverse = [p.reverse_penalty if d >= REVERSE else 1.0 for d in directions]
        turns = [[1.0] * len(directions)] + [
            [
                1.0 if d in (FORWARD, REVERSE)
                else p.non_straight_penalty + (0.0 if d == parent else p.change_penalty)
                for d in directions
            ]
            for parent in range(6)
        ]  # fmt: skip
        return per_cell, turns, reverse

    def _expansion(
        self, table: Primitives, checker: GridCollisionChecker, norms: np.ndarray
    ) -> Callable[[Node, set[int]], list[Child]]:
        """Nav2's NodeHybrid::getNeighbors and getTraversalCost, as tables for this plan:
        the children of a node with their step costs (the Python reference)."""
        nx, ny, bins = checker.nx, checker.ny, table.bins
        blocked, outline = checker.blocked, checker.outline
        per_cell_array, turns, reverse = self._step_factors(table, norms)
        per_cell = per_cell_array.tolist()
        directions = table.directions
        # Per (parent's turn + 1, heading bin), each primitive's step, child bin, length,
        # turn and reverse factors and direction, zipped for one pass.
        rows = [
            [
                list(zip(table.dx[b], table.dy[b], table.child_bins[b], table.lengths,
                         turns[parent + 1], reverse, directions, strict=True))
                for b in range(bins)
            ]
            for parent in range(-1, 6)
        ]  # fmt: skip
        floor = math.floor
        footprint_hit = checker.footprint_hit

        def expand(node: Node, closed: set[int]) -> list[Child]:
            x, y, b, _, _, turn, _ = node
            out: list[Child] = []
            for dx, dy, cb, length, tf, rf, direction in rows[turn + 1][b]:
                cx = x + dx
                cy = y + dy
                mx, my = floor(cx), floor(cy)
                if mx < 0 or my < 0 or mx >= nx or my >= ny:
                    continue
                cell = my * nx + mx
                if blocked[cell]:
                    continue
                key = cell * bins + cb
                if key in closed:
                    continue
                if outline is not None and outline[cell] and footprint_hit(key):
                    continue
                out.append((key, cell, cx, cy, cb, length * per_cell[cell] * tf * rf, direction))
            return out

        return expand

    def _kernel_tables(
        self,
        table: Primitives,
        checker: GridCollisionChecker,
        norms: np.ndarray,
        heuristic: np.ndarray,
        goal_key: int,
        goal: tuple[float, float, float],
        poll: bool,
    ) -> hybrid_kernel.HybridTables:
        """The compiled search's inputs: the same tables `_expansion` zips, as arrays."""
        p = self.params
        per_cell, turns, reverse = self._step_factors(table, norms)
        n_cells = checker.nx * checker.ny
        polygon = checker.bad is not None

        def cells(data: bytes | None) -> np.ndarray:
            if data is None:
                return np.zeros(n_cells, np.uint8)
            return np.frombuffer(data, np.uint8).copy()

        if polygon:
            rim_bounds, rim_start, rim_offsets = hybrid_kernel.rims(checker)
            bad = cells(checker.bad)
        else:
            rim_bounds = np.zeros((table.bins, 4), np.int64)
            rim_start, rim_offsets = np.zeros(table.bins + 1, np.int64), np.zeros(0, np.int64)
            bad = cells(None)
        ratio = p.analytic_expansion_ratio
        no_limit = hybrid_kernel.NO_LIMIT
        return hybrid_kernel.HybridTables(
            dx=np.array(table.dx, np.float64),
            dy=np.array(table.dy, np.float64),
            child_bin=np.array(table.child_bins, np.int64),
            length=np.array(table.lengths, np.float64),
            turn_factor=np.array(turns, np.float64),
            reverse_factor=np.array(reverse, np.float64),
            direction=np.array(table.directions, np.int64),
            per_cell=np.ascontiguousarray(per_cell, np.float64),
            heuristic=heuristic,
            blocked=cells(checker.blocked),
            outline=cells(checker.outline),
            bad=bad,
            rim_bounds=rim_bounds,
            rim_start=rim_start,
            rim_offsets=rim_offsets,
            nx=checker.nx,
            ny=checker.ny,
            bins=table.bins,
            polygon=polygon,
            goal_x=float(goal[0]),
            goal_y=float(goal[1]),
            goal_key=goal_key,
            tolerance=p.tolerance / checker.costmap.resolution,
            ratio=float(ratio),
            min_countdown=math.ceil(ratio),
            max_iterations=p.max_iterations if p.max_iterations > 0 else no_limit,
            max_approach=(
                p.max_on_approach_iterations if p.max_on_approach_iterations > 0 else no_limit
            ),
            poll_interval=p.terminal_checking_interval,
            poll=poll,
        )
