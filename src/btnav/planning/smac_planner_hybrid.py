"""nav2_smac_planner::SmacPlannerHybrid: Hybrid-A* for car-like and differential bases.

The search runs as Nav2's does, in cells: a node is a continuous (x, y) with its
heading on one of `angle_quantization_bins`, keyed by its cell and bin. Its children
are Nav2's motion primitives: a straight step and the tightest left and right arcs of
`minimum_turning_radius` whose chord leaves the cell (one heading bin's worth or more),
plus the gentler arcs between when `allow_primitive_interpolation`; `REEDS_SHEPP` adds
the same in reverse. A step costs its arc length times
`(1 - retrospective_penalty) + cost_penalty * cost / 252`, times `non_straight_penalty`
on a turn (plus `change_penalty` when the turn changes side) and `reverse_penalty`
backwards, as NodeHybrid::getTraversalCost. The heuristic is the larger of Nav2's
obstacle heuristic (a cost-aware 8-connected Dijkstra from the goal, on the costmap
halved with `downsample_obstacle_heuristic`) and the straight-line distance. Every few
expansions (fewer as the goal nears: `analytic_expansion_ratio`) a Dubins or
Reeds-Shepp curve to the goal is tried; if it is shorter than
`analytic_expansion_max_length` and collision-free it ends the search, so the path
ends exactly on the goal pose.

Collisions are Nav2's GridCollisionChecker's: with a radius footprint a pose collides
on an inscribed or lethal cell; with a polygon, a pose whose cell is at least the
circumscribed cost has its oriented outline checked (`costmap.footprint_cost`).
Unknown cells are free with `allow_unknown`.

Where btnav differs, and why: the distance heuristic is the straight line, not Nav2's
precomputed Dubins/Reeds-Shepp table (`lookup_table_size` is read, not used: the
table would cost more to build in Python than the searches it speeds); an analytic
expansion is not refined back along earlier nodes (refineAnalyticPath); the search
stops after `max_iterations` expansions, never after a wall-clock `max_planning_time`,
so a plan does not depend on the machine's speed.
"""

from __future__ import annotations

import heapq
import itertools
import math
from collections.abc import Callable
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray
from pydantic import Field
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra

from ..core import fmath
from ..core.geometry import Pose2D
from ..core.messages import Path
from ..costmap.cost_values import INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE, NO_INFORMATION
from ..costmap.costmap_2d import Costmap2D
from ..costmap.footprint_cost import footprint_costs
from ..params.schema import ParamsModel, ignored
from ..plugins import register
from . import dubins, reeds_shepp
from .exceptions import (
    GoalOccupied,
    GoalOutsideMapBounds,
    NoValidPathCouldBeFound,
    StartOccupied,
    StartOutsideMapBounds,
)
from .global_planner import GlobalPlanner
from .simple_smoother import SimpleSmoother

SQRT2 = math.sqrt(2.0)
#: A turning primitive's direction, as Nav2's TurnDirection.
FORWARD, LEFT, RIGHT, REVERSE, REV_LEFT, REV_RIGHT = range(6)


class HybridSmootherParams(ParamsModel):
    """The `smoother:` block of Nav2's Smac planners."""

    max_iterations: int = Field(1000, ge=1)
    w_smooth: float = Field(0.3, ge=0.0)
    w_data: float = Field(0.2, ge=0.0)
    tolerance: float = Field(1e-10, ge=0.0)
    do_refinement: bool = True
    refinement_num: int = Field(2, ge=0)


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
        chord = math.hypot(dx, dy)
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
                self.lengths.append(math.hypot(x, y))
            else:
                arc = abs(t) * bin_size
                self.lengths.append(math.hypot(x, y) / (2.0 * fmath.sin(arc / 2.0)) * arc)
        heading = np.arange(bins) * bin_size
        sh, ch = fmath.sincos(heading)
        px = np.array([p[0] for p in prims])
        py = np.array([p[1] for p in prims])
        #: Per heading bin, the primitives' steps (lists: scalar code reads them fastest).
        self.dx = (px[None, :] * ch[:, None] - py[None, :] * sh[:, None]).tolist()
        self.dy = (px[None, :] * sh[:, None] + py[None, :] * ch[:, None]).tolist()


def obstacle_heuristic(
    costs: NDArray[np.uint8], goal_cell: tuple[int, int], cost_penalty: float, downsample: bool
) -> NDArray[np.float64]:
    """Nav2's obstacle heuristic for every cell, in cells: the cheapest 8-connected way
    from the goal, each step costing its length times (1 + cost_penalty * cost / 252) of
    the cell it enters; inscribed, lethal and unknown-above-inscribed cells are walls.
    Nav2 expands it lazily as the search asks; all of it at once is the same values."""
    grid = costs
    gx, gy = goal_cell
    if downsample:  # each 2x2 block takes its cheapest cell, distances count double
        ny, nx = costs.shape
        padded = np.full((ny + ny % 2, nx + nx % 2), 255, np.uint8)
        padded[:ny, :nx] = costs
        grid = padded.reshape(padded.shape[0] // 2, 2, padded.shape[1] // 2, 2).min(axis=(1, 3))
        gx, gy = gx // 2, gy // 2
    ny, nx = grid.shape
    cost = grid.astype(np.float64).ravel()
    free = cost < INSCRIBED_INFLATED_OBSTACLE
    index = np.arange(nx * ny).reshape(ny, nx)
    rows, cols, weights = [], [], []
    for ox, oy in ((1, 0), (-1, 0), (0, 1), (0, -1), (1, 1), (-1, 1), (1, -1), (-1, -1)):
        src = index[max(0, -oy) : ny - max(0, oy), max(0, -ox) : nx - max(0, ox)].ravel()
        dst = src + oy * nx + ox
        ok = free[dst]
        step = 1.0 if ox == 0 or oy == 0 else SQRT2
        rows.append(src[ok])
        cols.append(dst[ok])
        weights.append(step * (1.0 + cost_penalty * cost[dst[ok]] / 252.0))
    graph = csr_matrix(
        (np.concatenate(weights), (np.concatenate(rows), np.concatenate(cols))),
        shape=(nx * ny, nx * ny),
    )
    h = dijkstra(graph, directed=True, indices=gy * nx + gx).reshape(ny, nx)
    if downsample:
        h = 2.0 * np.repeat(np.repeat(h, 2, axis=0), 2, axis=1)[: costs.shape[0], : costs.shape[1]]
    return h  # type: ignore[no-any-return]


@register(
    "planner",
    "nav2_smac_planner::SmacPlannerHybrid",
    aliases=("btnav/SmacPlannerHybrid",),
)
class SmacPlannerHybrid(GlobalPlanner):
    """Hybrid-A* with Nav2's params and defaults (see the module's docstring)."""

    class Params(GlobalPlanner.Params):
        downsample_costmap: bool = ignored(False, "btnav searches the costmap at its resolution")
        downsampling_factor: int = ignored(1, "btnav searches the costmap at its resolution")
        angle_quantization_bins: int = Field(72, ge=4, le=720)
        tolerance: float = Field(0.25, ge=0.0, description="m around the goal, if unreachable")
        allow_unknown: bool = True
        max_iterations: int = Field(1_000_000, ge=1)
        max_on_approach_iterations: int = Field(1000, ge=1)
        terminal_checking_interval: int = Field(5000, ge=1)
        max_planning_time: float = ignored(
            5.0, "btnav bounds a search by max_iterations, so a plan never depends on the CPU"
        )
        smooth_path: bool = True
        minimum_turning_radius: float = Field(0.4, gt=0.0, description="m")
        allow_primitive_interpolation: bool = False
        cache_obstacle_heuristic: bool = False
        reverse_penalty: float = Field(2.0, ge=1.0)
        change_penalty: float = Field(0.0, ge=0.0)
        non_straight_penalty: float = Field(1.2, ge=1.0)
        cost_penalty: float = Field(2.0, ge=0.0)
        retrospective_penalty: float = Field(0.015, ge=0.0, le=1.0)
        analytic_expansion_ratio: float = Field(3.5, gt=0.0)
        analytic_expansion_max_length: float = Field(3.0, gt=0.0, description="m")
        analytic_expansion_max_cost: float = Field(200.0, ge=0.0)
        analytic_expansion_max_cost_override: bool = False
        use_quadratic_cost_penalty: bool = False
        downsample_obstacle_heuristic: bool = True
        lookup_table_size: float = ignored(
            20.0, "btnav's distance heuristic is the straight line, no Dubins table"
        )
        debug_visualizations: bool = ignored(False, "no RViz markers in btnav")
        motion_model_for_search: Literal["DUBIN", "REEDS_SHEPP"] = "DUBIN"
        goal_heading_mode: Literal["DEFAULT"] = "DEFAULT"
        coarse_search_resolution: int = Field(1, ge=1)
        smoother: HybridSmootherParams = Field(default_factory=HybridSmootherParams)

    params: Params

    def __init__(self, name: str, params: Params | None = None) -> None:
        super().__init__(name, params)
        self._primitives: tuple[tuple[Any, ...], Primitives] | None = None
        #: Nodes the last search expanded (for tests and benchmarks).
        self.expansions = 0

    # -- what the search works on ----------------------------------------------------------

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

    def _footprint(self) -> tuple[NDArray[np.float64] | None, float]:
        """The polygon to check (None: a radius footprint) and the cost from which a cell
        may put the footprint on an obstacle (Nav2's possible_collision_cost)."""
        ros = self.costmap_ros
        if ros is None or ros.use_radius:
            return None, float(INSCRIBED_INFLATED_OBSTACLE)
        return np.asarray(ros.footprint, float), max(0.0, float(ros.circumscribed_cost()))

    def _colliding(
        self,
        costmap: Costmap2D,
        flat: bytes,
        x: list[float],
        y: list[float],
        yaw: list[float],
    ) -> list[bool]:
        """Whether each pose (cells, radians) collides, as Nav2's GridCollisionChecker."""
        nx, ny = costmap.size_x, costmap.size_y
        polygon, possible = self._footprint()
        unknown_ok = self.params.allow_unknown
        out = []
        check: list[int] = []
        for i, (cx, cy) in enumerate(zip(x, y, strict=True)):
            mx, my = math.floor(cx), math.floor(cy)
            if not (0 <= mx < nx and 0 <= my < ny):
                out.append(True)
                continue
            cost = flat[my * nx + mx]
            if cost == NO_INFORMATION:
                out.append(not unknown_ok)
                continue
            if polygon is None:
                out.append(cost >= INSCRIBED_INFLATED_OBSTACLE)
                continue
            if cost >= LETHAL_OBSTACLE:
                out.append(True)
                continue
            out.append(False)
            if cost >= possible:
                check.append(i)
        if check and polygon is not None:
            res = costmap.resolution
            wx = [costmap.origin_x + x[i] * res for i in check]
            wy = [costmap.origin_y + y[i] * res for i in check]
            fp = footprint_costs(costmap, polygon, wx, wy, [yaw[i] for i in check])
            for i, c in zip(check, fp.tolist(), strict=True):
                out[i] = c >= LETHAL_OBSTACLE and (c != NO_INFORMATION or not unknown_ok)
        return out

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
        flat = costmap.costs.tobytes()
        nx = costmap.size_x

        def cells(pose: Pose2D) -> tuple[float, float]:
            return (pose.x - costmap.origin_x) / res, (pose.y - costmap.origin_y) / res

        sx, sy = cells(start)
        gx, gy = cells(goal)
        if not (0 <= sx < nx and 0 <= sy < costmap.size_y):
            raise StartOutsideMapBounds(f"start ({start.x:.2f}, {start.y:.2f}) is off the costmap")
        if not (0 <= gx < nx and 0 <= gy < costmap.size_y):
            raise GoalOutsideMapBounds(f"goal ({goal.x:.2f}, {goal.y:.2f}) is off the costmap")
        if self._colliding(costmap, flat, [sx], [sy], [start.yaw])[0]:
            raise StartOccupied("the start pose is in collision")
        if self._colliding(costmap, flat, [gx], [gy], [goal.yaw])[0]:
            raise GoalOccupied("the goal pose is in collision")

        heuristic = obstacle_heuristic(
            costmap.costs, (math.floor(gx), math.floor(gy)), p.cost_penalty,
            p.downsample_obstacle_heuristic,
        )  # fmt: skip
        found = self._search(
            costmap, flat, table, (sx, sy, start.yaw), (gx, gy, goal.yaw), heuristic
        )
        poses = np.array(found, dtype=np.float64)
        poses[:, 0] = costmap.origin_x + poses[:, 0] * res
        poses[:, 1] = costmap.origin_y + poses[:, 1] * res
        path = Path(0.0, poses, costmap.frame_id)
        return self._smoothed(path, costmap)

    # -- the search ------------------------------------------------------------------------

    def _search(
        self,
        costmap: Costmap2D,
        flat: bytes,
        table: Primitives,
        start: tuple[float, float, float],
        goal: tuple[float, float, float],
        heuristic: NDArray[np.float64],
    ) -> list[tuple[float, float, float]]:
        """Hybrid-A* from `start` to `goal` (cells, radians): the path's poses, in cells."""
        p = self.params
        bins, bin_size = table.bins, table.bin_size
        nx = costmap.size_x
        h_grid = heuristic.ravel().tolist()
        reward = 1.0 - p.retrospective_penalty
        gx, gy, gyaw = goal
        goal_bin = round(gyaw / bin_size) % bins
        goal_key = (math.floor(gy) * nx + math.floor(gx)) * bins + goal_bin
        tolerance = p.tolerance / costmap.resolution

        def h(x: float, y: float) -> float:
            return max(h_grid[math.floor(y) * nx + math.floor(x)], math.hypot(x - gx, y - gy))

        sx, sy, syaw = start
        start_bin = round(syaw / bin_size) % bins
        # node: x, y, bin, g, parent index, turn direction
        nodes: list[tuple[float, float, int, float, int, int]] = [(sx, sy, start_bin, 0.0, -1, -1)]
        best_g = {(math.floor(sy) * nx + math.floor(sx)) * bins + start_bin: 0.0}
        closed: set[int] = set()
        h0 = h(sx, sy)
        # Equal totals go to the node nearer the goal, so plateaus are crossed, not flooded.
        queue: list[tuple[float, float, int]] = [(h0, h0, 0)]
        analytic_countdown, closest = 0, math.inf  # the first node tries the goal at once
        best_approach: tuple[float, int] | None = None
        approach_iterations = 0
        self.expansions = 0
        while queue:
            _, _, i = heapq.heappop(queue)
            x, y, b, g, _, turn = nodes[i]
            key = (math.floor(y) * nx + math.floor(x)) * bins + b
            if key in closed:
                continue
            closed.add(key)
            self.expansions += 1
            if key == goal_key:
                return self._backtrack(nodes, i, bin_size)
            here = h(x, y)
            if here <= tolerance:
                # Within tolerance means the car could still get there: by a curve, not
                # the straight line (a node on the goal facing away is not near it).
                gap = self._curve_length(costmap, (x, y, b * bin_size), goal)
                if gap <= tolerance and (best_approach is None or gap < best_approach[0]):
                    best_approach = (gap, i)
            if best_approach is not None:
                approach_iterations += 1
                if approach_iterations >= p.max_on_approach_iterations:
                    break
            if self.expansions >= p.max_iterations:
                break
            # Analytic expansion: more often as the goal nears (Nav2's desired iterations).
            closest = min(closest, here)
            desired = max(
                int(closest / p.analytic_expansion_ratio), math.ceil(p.analytic_expansion_ratio)
            )
            analytic_countdown = min(analytic_countdown, desired)
            if analytic_countdown <= 0:
                analytic_countdown = desired
                found = self._analytic_from(costmap, flat, nodes, i, goal, bin_size)
                if found is not None:
                    return found
            analytic_countdown -= 1
            cx = [x + d for d in table.dx[b]]
            cy = [y + d for d in table.dy[b]]
            cb = [(b + t) % bins for t in table.turns]
            hit = self._colliding(costmap, flat, cx, cy, [k * bin_size for k in cb])
            for k in range(len(cx)):
                if hit[k]:
                    continue
                child_key = (math.floor(cy[k]) * nx + math.floor(cx[k])) * bins + cb[k]
                if child_key in closed:
                    continue
                cost = flat[math.floor(cy[k]) * nx + math.floor(cx[k])]
                norm = 0.0 if cost == NO_INFORMATION else cost / 252.0
                if p.use_quadratic_cost_penalty:
                    norm *= norm
                step = table.lengths[k] * (reward + p.cost_penalty * norm)
                direction = table.directions[k]
                if direction not in (FORWARD, REVERSE) and turn != -1:
                    step *= p.non_straight_penalty + (
                        0.0 if direction == turn else p.change_penalty
                    )
                if direction >= REVERSE:
                    step *= p.reverse_penalty
                g_child = g + step
                if g_child >= best_g.get(child_key, math.inf):
                    continue
                best_g[child_key] = g_child
                nodes.append((cx[k], cy[k], cb[k], g_child, i, direction))
                h_child = h(cx[k], cy[k])
                heapq.heappush(queue, (g_child + h_child, h_child, len(nodes) - 1))
        if best_approach is not None:
            return self._backtrack(nodes, best_approach[1], bin_size)
        raise NoValidPathCouldBeFound(
            f"no path to the goal after {self.expansions} expansions"
            f"{' (max_iterations)' if self.expansions >= p.max_iterations else ''}"
        )

    def _analytic_from(
        self,
        costmap: Costmap2D,
        flat: bytes,
        nodes: list[tuple[float, float, int, float, int, int]],
        i: int,
        goal: tuple[float, float, float],
        bin_size: float,
    ) -> list[tuple[float, float, float]] | None:
        """The path through node `i` and a curve to the goal, refined as Nav2's
        refineAnalyticPath does: the curve is tried from every fifth ancestor back (eight
        times at most) and kept from the earliest that is free with no more cusps, so the
        search's first few steps do not leave wiggles a curve could have drawn smooth."""
        found = self._analytic(costmap, flat, (*nodes[i][:2], nodes[i][2] * bin_size), goal)
        if found is None:
            return None
        best, cusps = i, found[1]
        test = i
        for _ in range(8):
            for _ in range(5):
                test = nodes[test][4] if test >= 0 else -1
            if test < 0:
                break
            x, y, b = nodes[test][:3]
            refined = self._analytic(costmap, flat, (x, y, b * bin_size), goal)
            if refined is None:
                break
            if refined[1] <= cusps:
                best, found, cusps = test, refined, refined[1]
        return self._backtrack(nodes, best, bin_size) + found[0]

    def _curve(
        self, costmap: Costmap2D, pose: tuple[float, float, float], goal: tuple[float, float, float]
    ) -> Any:
        """The shortest Dubins or Reeds-Shepp curve between two poses in cells."""
        p = self.params
        r = p.minimum_turning_radius / costmap.resolution
        curves = reeds_shepp if p.motion_model_for_search == "REEDS_SHEPP" else dubins
        return curves.shortest_path(pose, goal, r)

    def _curve_length(
        self, costmap: Costmap2D, pose: tuple[float, float, float], goal: tuple[float, float, float]
    ) -> float:
        curve = self._curve(costmap, pose, goal)
        return math.inf if curve is None else float(curve.length)

    def _analytic(
        self,
        costmap: Costmap2D,
        flat: bytes,
        pose: tuple[float, float, float],
        goal: tuple[float, float, float],
    ) -> tuple[list[tuple[float, float, float]], int] | None:
        """A collision-free Dubins or Reeds-Shepp curve to the goal (cells) and its number
        of direction changes, or None."""
        p = self.params
        r = p.minimum_turning_radius / costmap.resolution
        curve = self._curve(costmap, pose, goal)
        if curve is None or curve.length * costmap.resolution > p.analytic_expansion_max_length:
            return None
        samples = curve.sample(pose, SQRT2)[1:]
        if len(samples) == 0:
            return None
        sx, sy, syaw = samples[:, 0].tolist(), samples[:, 1].tolist(), samples[:, 2].tolist()
        if any(self._colliding(costmap, flat, sx, sy, syaw)):
            return None
        m = np.floor(samples[:, :2]).astype(np.int64)
        cost = costmap.costs[m[:, 1], m[:, 0]]
        high = (cost > p.analytic_expansion_max_cost) & (cost != NO_INFORMATION)
        # Costly cells only on the final approach (a goal in a tight spot), never entered
        # and left on the way; near the goal `analytic_expansion_max_cost_override` lifts it.
        if high.any() and not high[int(np.argmax(high)) :].all():
            near = curve.length < 2.0 * math.pi * r
            if not (near and p.analytic_expansion_max_cost_override):
                return None
        forward = [length > 0.0 for length in curve.lengths if length != 0.0]
        cusps = sum(a != b for a, b in itertools.pairwise(forward))
        return [(a, b, c) for a, b, c in zip(sx, sy, syaw, strict=True)], cusps

    @staticmethod
    def _backtrack(
        nodes: list[tuple[float, float, int, float, int, int]], i: int, bin_size: float
    ) -> list[tuple[float, float, float]]:
        out = []
        while i >= 0:
            x, y, b, _, parent, _ = nodes[i]
            out.append((x, y, b * bin_size))
            i = parent
        return out[::-1]

    def _smoothed(self, path: Path, costmap: Costmap2D) -> Path:
        """Nav2's Smac smoother: gradient descent on each stretch between cusps, kept only
        while no sampled turn is tighter than the minimum turning radius."""
        if not self.params.smooth_path or len(path) < 4:
            return path
        s = self.params.smoother
        smoother = SimpleSmoother(
            "smoother",
            SimpleSmoother.Params(
                max_its=s.max_iterations, w_smooth=s.w_smooth, w_data=s.w_data,
                tolerance=s.tolerance, do_refinement=s.do_refinement,
                refinement_num=s.refinement_num, is_holonomic=False,
            ),
        )  # fmt: skip
        smoothed = smoother.smooth(path, costmap).path
        if max_curvature(smoothed.poses) > 1.0 / self.params.minimum_turning_radius * 1.05:
            return path
        return smoothed


def max_curvature(poses: NDArray[np.float64]) -> float:
    """The sharpest turn along a path: |heading change| / distance between samples."""
    d = np.diff(poses[:, :2], axis=0)
    ds = np.hypot(d[:, 0], d[:, 1])
    turn = np.abs((np.diff(poses[:, 2]) + np.pi) % (2.0 * np.pi) - np.pi)
    moved = ds > 1e-9
    return float(np.max(turn[moved] / ds[moved], initial=0.0))
