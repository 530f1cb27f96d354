"""What Nav2's Smac Hybrid-A* and State Lattice planners share: the A* loop with its
analytic expansion and goal approach, the collision checker, the obstacle heuristic,
the params both read and the smoother step.

Nav2 builds both planners on one templated A* (a_star.hpp, analytic_expansion.hpp,
collision_checker.hpp, obstacle_heuristic.hpp); only the node type differs, which here is
the `expand` function a planner hands to `SmacSearch.run`: given a node, the children it
reaches, each with its step cost. Everything is in costmap cells (continuous x, y; a
heading bin), as in Nav2. Each piece restated: docs/decisions/0073.
"""

from __future__ import annotations

import heapq
import itertools
import math
import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, Literal, Protocol

import numpy as np
from numpy.typing import NDArray
from pydantic import Field
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra

from ..core import fmath
from ..core.messages import Path
from ..costmap.cost_values import INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE, NO_INFORMATION
from ..costmap.costmap_2d import Costmap2D
from ..costmap.footprint_cost import footprint_costs
from ..params.schema import ParamsModel, ignored
from . import dubins, dubins_kernel, reeds_shepp, reeds_shepp_kernel
from .exceptions import NoValidPathCouldBeFound, PlannerCancelled, PlannerTimedOut
from .global_planner import GlobalPlanner
from .simple_smoother import SimpleSmoother

SQRT2 = math.sqrt(2.0)
#: How much (relative) a straight line may exceed the maximum length and still be
#: checked: a curve is never shorter than the line, but the two round differently.
_LENGTH_SLACK = 1e-9

#: A node: x, y (cells), heading bin, cost so far, parent index (-1: the start), the
#: primitive that reached it (-1: none), its key (cell * bins + bin).
Node = tuple[float, float, int, float, int, int, int]
#: A child an `expand` offers: key, cell, x, y, bin, step cost, primitive.
Child = tuple[int, int, float, float, int, float, int]
#: A pose in cells: x, y, yaw.
CellPose = tuple[float, float, float]
#: How Hybrid-A* searches and the curves are solved: numba kernels (hybrid_kernel,
#: reeds_shepp_kernel, dubins_kernel) or the Python reference (environment variable
#: BTNAV_SMAC=python); the same plans, bit for bit, either way.
SmacMethod = Literal["kernel", "python"]
DEFAULT_METHOD: SmacMethod = "python" if os.environ.get("BTNAV_SMAC") == "python" else "kernel"


class SmacSmootherParams(ParamsModel):
    """The `smoother:` block of Nav2's Smac planners."""

    max_iterations: int = Field(1000, ge=1)
    w_smooth: float = Field(0.3, ge=0.0)
    w_data: float = Field(0.2, ge=0.0)
    tolerance: float = Field(1e-10, ge=0.0)
    do_refinement: bool = True
    refinement_num: int = Field(2, ge=0)


class SmacParams(GlobalPlanner.Params):
    """The keys SmacPlannerHybrid and SmacPlannerLattice both read, with Hybrid's defaults
    (Lattice overrides the two that differ)."""

    tolerance: float = Field(0.25, ge=0.0, description="m around the goal, if unreachable")
    allow_unknown: bool = True
    max_iterations: int = Field(1_000_000, description="0 or less: no limit, as Nav2")
    max_on_approach_iterations: int = Field(1000, description="0 or less: no limit, as Nav2")
    terminal_checking_interval: int = Field(5000, ge=1)
    max_planning_time: float = ignored(
        5.0, "btnav bounds a search by max_iterations, so a plan never depends on the CPU"
    )
    smooth_path: bool = True
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
    goal_heading_mode: Literal["DEFAULT"] = "DEFAULT"
    coarse_search_resolution: int = Field(1, ge=1)
    smoother: SmacSmootherParams = Field(default_factory=SmacSmootherParams)


# -- collision checking ----------------------------------------------------------------


class GridCollisionChecker:
    """Nav2's GridCollisionChecker on one costmap, decided per cell once a plan.

    `blocked[cell]` is 1 where any pose collides (lethal; inscribed with a radius
    footprint; unknown unless `allow_unknown`); with a polygon footprint `outline[cell]`
    is 1 where the pose's outline must be checked (the circumscribed cost and up, short
    of lethal; Nav2's possible_collision_cost). Off the map always collides.

    Given the search's heading `bins`, a pose's outline is checked as Nav2 checks it: at
    its cell's centre, turned to its heading's bin (the nearest), so the answer belongs to
    the (cell, bin) and is remembered (`footprint_hit`). Each bin's outline is a fixed set
    of cells around the centre cell, so a check is a few dozen byte lookups, not a numpy
    call. Without `bins` (the lattice planner) the outline is laid at the exact pose.
    """

    def __init__(
        self, costmap: Costmap2D, costmap_ros: Any, allow_unknown: bool, bins: int | None = None
    ) -> None:
        self.costmap = costmap
        self.nx, self.ny = costmap.size_x, costmap.size_y
        self.allow_unknown = allow_unknown
        costs = costmap.costs
        self.polygon, possible = footprint_of(costmap_ros)
        unknown = costs == NO_INFORMATION
        solid_from = INSCRIBED_INFLATED_OBSTACLE if self.polygon is None else LETHAL_OBSTACLE
        solid = ~unknown & (costs >= solid_from)
        blocked = solid | (unknown & (not allow_unknown))
        self.blocked: bytes = blocked.astype(np.uint8).tobytes()
        self.outline: bytes | None = None
        if self.polygon is not None:
            self.outline = (~unknown & ~solid & (costs >= possible)).astype(np.uint8).tobytes()
        #: Whether outlines are checked per (cell, bin) (a polygon and the search's bins).
        self._binned = self.polygon is not None and bins is not None
        self._bins = bins or 1
        self._bin_size = 2.0 * math.pi / self._bins
        if self._binned:
            # What puts an outline in collision: lethal, and unknown unless allowed.
            bad = (costs == LETHAL_OBSTACLE) | (unknown & (not allow_unknown))
            self._bad: bytes = np.ascontiguousarray(bad, np.uint8).tobytes()
            self._rims: list[tuple[int, int, int, int, tuple[int, ...]] | None]
            self._rims = [None] * self._bins
            #: Per (cell, bin) key checked so far: whether the outline collides there.
            self._footprint: dict[int, bool] = {}

    def cell(self, x: float, y: float) -> int:
        """The cell index of a pose in cells, or -1 off the map."""
        mx, my = math.floor(x), math.floor(y)
        if 0 <= mx < self.nx and 0 <= my < self.ny:
            return my * self.nx + mx
        return -1

    def colliding(self, x: Sequence[float], y: Sequence[float], yaw: Sequence[float]) -> list[bool]:
        """Whether each pose (cells, radians) collides."""
        if self._binned:
            return [self._binned_hit(*pose) for pose in zip(x, y, yaw, strict=True)]
        out: list[bool] = []
        check: list[int] = []
        for i, (px, py) in enumerate(zip(x, y, strict=True)):
            c = self.cell(px, py)
            hit = c < 0 or self.blocked[c] == 1
            out.append(hit)
            if not hit and self.outline is not None and self.outline[c]:
                check.append(i)
        if check:
            hits = self.outline_hits(
                [x[i] for i in check], [y[i] for i in check], [yaw[i] for i in check]
            )
            for i, hit in zip(check, hits, strict=True):
                out[i] = hit
        return out

    def collides(self, x: Sequence[float], y: Sequence[float], yaw: Sequence[float]) -> bool:
        """Whether any of the poses collides (with `bins`, the first collision ends it)."""
        if self._binned:
            return any(self._binned_hit(*pose) for pose in zip(x, y, yaw, strict=True))
        return any(self.colliding(x, y, yaw))

    def _binned_hit(self, x: float, y: float, yaw: float) -> bool:
        c = self.cell(x, y)
        if c < 0 or self.blocked[c]:
            return True
        outline: bytes = self.outline  # type: ignore[assignment]
        return bool(outline[c]) and self.footprint_hit(c * self._bins + self.bin_of(yaw))

    @property
    def bins(self) -> int:
        """The heading bins outlines are checked on (1 without the search's bins)."""
        return self._bins

    @property
    def bad(self) -> bytes | None:
        """Per cell, whether it puts an outline in collision (None unless outlines are
        checked per (cell, bin))."""
        return self._bad if self._binned else None

    def rim(self, b: int) -> tuple[int, int, int, int, tuple[int, ...]]:
        """Bin b's outline around a cell's centre (see `_rim`), made once."""
        return self._rims[b] or self._rim(b)

    def bin_of(self, yaw: float) -> int:
        """The heading bin nearest `yaw` (radians, any turn)."""
        return round(yaw / self._bin_size) % self._bins

    def footprint_hit(self, key: int) -> bool:
        """Whether the outline collides at `key` (cell * bins + bin), as Nav2 decides it:
        the footprint turned to the bin's heading, on the cell's centre (a vertex off the
        map collides). Remembered for the plan."""
        known = self._footprint.get(key)
        if known is not None:
            return known
        cell, b = divmod(key, self._bins)
        rim = self.rim(b)
        my, mx = divmod(cell, self.nx)
        lo_x, hi_x, lo_y, hi_y, offsets = rim
        if mx + lo_x < 0 or my + lo_y < 0 or mx + hi_x >= self.nx or my + hi_y >= self.ny:
            hit = True
        else:
            bad = self._bad
            hit = any(bad[cell + d] for d in offsets)
        self._footprint[key] = hit
        return hit

    def _rim(self, b: int) -> tuple[int, int, int, int, tuple[int, ...]]:
        """Bin b's outline around a cell's centre: its vertices' cell offsets' bounds and
        its cells as flat offsets, each edge rasterised as footprint_costs does
        (nav2_util::LineIterator: Bresenham's line between the vertices' cells)."""
        sn, cs = fmath.sincos(b * self._bin_size)
        res = self.costmap.resolution
        assert self.polygon is not None
        # The centre is half a cell into its cell: a vertex's cell is that much past it.
        vertices = [
            (math.floor(0.5 + (px * cs - py * sn) / res), math.floor(0.5 + (px * sn + py * cs) / res))
            for px, py in self.polygon.tolist()
        ]  # fmt: skip
        cells: set[tuple[int, int]] = set()
        for (x0, y0), (x1, y1) in zip(vertices, vertices[1:] + vertices[:1], strict=True):
            dx, dy = abs(x1 - x0), abs(y1 - y0)
            major, minor = max(dx, dy), min(dx, dy)
            sx, sy = (1 if x1 >= x0 else -1), (1 if y1 >= y0 else -1)
            for along in range(major + 1):
                across = (major // 2 + along * minor) // max(major, 1)
                if dx >= dy:
                    cells.add((x0 + sx * along, y0 + sy * across))
                else:
                    cells.add((x0 + sx * across, y0 + sy * along))
        xs, ys = [v[0] for v in vertices], [v[1] for v in vertices]
        offsets = tuple(sorted(oy * self.nx + ox for ox, oy in cells))
        rim = (min(xs), max(xs), min(ys), max(ys), offsets)
        self._rims[b] = rim
        return rim

    def outline_hits(
        self, x: Sequence[float], y: Sequence[float], yaw: Sequence[float]
    ) -> list[bool]:
        """Whether the polygon's oriented outline is on a lethal cell at each pose (cells)."""
        cm = self.costmap
        res = cm.resolution
        wx = [cm.origin_x + v * res for v in x]
        wy = [cm.origin_y + v * res for v in y]
        fp = footprint_costs(cm, self.polygon, wx, wy, list(yaw)).tolist()
        unknown_ok = self.allow_unknown
        return [c >= LETHAL_OBSTACLE and (c != NO_INFORMATION or not unknown_ok) for c in fp]


def footprint_of(costmap_ros: Any) -> tuple[NDArray[np.float64] | None, float]:
    """The polygon to check (None: a radius footprint) and the cost from which a cell may
    put it on an obstacle (Nav2's possible_collision_cost)."""
    if costmap_ros is None or costmap_ros.use_radius:
        return None, float(INSCRIBED_INFLATED_OBSTACLE)
    return np.asarray(costmap_ros.footprint, float), max(
        0.0, float(costmap_ros.circumscribed_cost())
    )


def traversal_norms(costmap: Costmap2D, quadratic: bool) -> NDArray[np.float64]:
    """Each cell's normalised cost in a step's cost (cost / 252, squared with
    `use_quadratic_cost_penalty`); unknown cells cost nothing."""
    costs = costmap.costs.ravel()
    norm = np.where(costs == NO_INFORMATION, 0.0, costs / 252.0)
    return norm * norm if quadratic else norm


# -- the obstacle heuristic --------------------------------------------------------------


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


class HeuristicCache:
    """The last obstacle heuristic (as a flat list, what the search reads), reused while
    the same goal cell and penalty are asked on the same costs; with `keep_stale` (Nav2's
    cache_obstacle_heuristic) reused for the same goal cell whatever the costmap now holds."""

    def __init__(self) -> None:
        self._key: tuple[Any, ...] | None = None
        self._costs: bytes = b""
        self._values: list[float] = []
        #: The last values as an array (what a compiled search reads).
        self.array: NDArray[np.float64] = np.zeros(0)

    def get(
        self,
        costmap: Costmap2D,
        goal_cell: tuple[int, int],
        cost_penalty: float,
        downsample: bool,
        keep_stale: bool,
    ) -> list[float]:
        key = (costmap.costs.shape, goal_cell, cost_penalty, downsample)
        costs = costmap.costs.tobytes()
        if key != self._key or (costs != self._costs and not keep_stale):
            h = obstacle_heuristic(costmap.costs, goal_cell, cost_penalty, downsample)
            self.array = np.ascontiguousarray(h.ravel(), np.float64)
            self._key, self._costs, self._values = key, costs, self.array.tolist()
        return self._values


# -- analytic expansion ------------------------------------------------------------------


class Curve(Protocol):
    """A Dubins, Reeds-Shepp or straight path: its length, its signed segment lengths
    (negative: reversing) and poses along it."""

    @property
    def length(self) -> float: ...

    @property
    def lengths(self) -> tuple[float, ...]: ...

    def sample(self, start: tuple[float, float, float], step: float) -> np.ndarray: ...


@dataclass(frozen=True)
class StraightLine:
    """OMPL's SE2 path, Nav2's analytic expansion for omni lattices: the straight line,
    the heading turning the short way as it goes; its length is OMPL's SE2 distance
    (the line plus half the turn in radians)."""

    dx: float
    dy: float
    turn: float

    @property
    def length(self) -> float:
        return fmath.hypot(self.dx, self.dy) + 0.5 * abs(self.turn)

    @property
    def lengths(self) -> tuple[float, ...]:
        return (self.length,)

    def sample(self, start: tuple[float, float, float], step: float) -> np.ndarray:
        n = max(1, math.ceil(self.length / step))
        t = np.linspace(0.0, 1.0, n + 1)
        x, y, yaw = start
        return np.column_stack([x + t * self.dx, y + t * self.dy, yaw + t * self.turn])


def straight_line(start: CellPose, goal: CellPose) -> StraightLine:
    turn = math.remainder(goal[2] - start[2], 2.0 * math.pi)
    return StraightLine(goal[0] - start[0], goal[1] - start[1], turn)


AnalyticModel = Literal["DUBIN", "REEDS_SHEPP", "OMNI"]


class AnalyticExpansion:
    """Nav2's AnalyticExpansion for one plan (all lengths in cells)."""

    def __init__(
        self,
        model: AnalyticModel,
        radius: float,
        checker: GridCollisionChecker,
        params: SmacParams,
        method: SmacMethod = DEFAULT_METHOD,
    ) -> None:
        self.model = model
        self.method = method
        self.radius = radius
        self.checker = checker
        res = checker.costmap.resolution
        self.max_length = params.analytic_expansion_max_length / res
        self.max_cost = params.analytic_expansion_max_cost
        self.override = params.analytic_expansion_max_cost_override

    def curve(self, pose: CellPose, goal: CellPose) -> Curve | None:
        """The shortest curve of the model between two poses in cells."""
        if self.model == "OMNI":
            return straight_line(pose, goal)
        if self.method == "kernel":
            kernels = reeds_shepp_kernel if self.model == "REEDS_SHEPP" else dubins_kernel
            return kernels.shortest_path(pose, goal, self.radius)  # type: ignore[no-any-return]
        curves = reeds_shepp if self.model == "REEDS_SHEPP" else dubins
        return curves.shortest_path(pose, goal, self.radius)  # type: ignore[no-any-return]

    def gap(self, pose: CellPose, goal: CellPose) -> float:
        """How far the base must drive from `pose` to the goal (inf if it cannot)."""
        curve = self.curve(pose, goal)
        return math.inf if curve is None else float(curve.length)

    def path(self, pose: CellPose, goal: CellPose) -> tuple[list[CellPose], int] | None:
        """A valid curve to the goal as poses (the start left out) and its number of
        direction changes, or None."""
        # A curve is never shorter than the straight line: most nodes are too far to try.
        if fmath.hypot(pose[0] - goal[0], pose[1] - goal[1]) > self.max_length * (
            1 + _LENGTH_SLACK
        ):
            return None
        curve = self.curve(pose, goal)
        if curve is None or curve.length > self.max_length:
            return None
        samples = curve.sample(pose, SQRT2)[1:]
        if len(samples) == 0:
            return None
        sx, sy, syaw = samples[:, 0].tolist(), samples[:, 1].tolist(), samples[:, 2].tolist()
        if self.checker.collides(sx, sy, syaw):
            return None
        m = np.floor(samples[:, :2]).astype(np.int64)
        cost = self.checker.costmap.costs[m[:, 1], m[:, 0]]
        high = (cost > self.max_cost) & (cost != NO_INFORMATION)
        # Costly cells only on the final approach (a goal in a tight spot), never entered
        # and left on the way; near the goal `analytic_expansion_max_cost_override` lifts it.
        if high.any() and not high[int(np.argmax(high)) :].all():
            near = curve.length < 2.0 * math.pi * self.radius
            if not (near and self.override):
                return None
        forward = [length > 0.0 for length in curve.lengths if length != 0.0]
        cusps = sum(a != b for a, b in itertools.pairwise(forward))
        return list(zip(sx, sy, syaw, strict=True)), cusps

    def from_node(
        self, nodes: Sequence[Node], i: int, yaws: Sequence[float], goal: CellPose
    ) -> tuple[int, list[CellPose]] | None:
        """The node to leave the search from and its curve to the goal, refined as Nav2's
        refineAnalyticPath does: the curve is tried from every fifth ancestor back (eight
        times at most) and kept from the earliest that is free with no more cusps, so the
        search's first few steps do not leave wiggles a curve could have drawn smooth."""
        x, y, b = nodes[i][:3]
        found = self.path((x, y, yaws[b]), goal)
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
            refined = self.path((x, y, yaws[b]), goal)
            if refined is None:
                break
            if refined[1] <= cusps:
                best, found, cusps = test, refined, refined[1]
        return best, found[0]


# -- the search --------------------------------------------------------------------------

#: A planner's node expansion: the children of `node` that are not in `closed`.
Expand = Callable[[Node, set[int]], list[Child]]


@dataclass
class SearchResult:
    """Where a search ended: a node (the goal's, or the best within tolerance) and, after
    an analytic expansion, the curve's poses from it to the goal."""

    nodes: Sequence[Node]
    end: int
    tail: list[CellPose]
    expansions: int

    def chain(self) -> list[int]:
        """The node indices from the start to the end node."""
        out = []
        i = self.end
        while i >= 0:
            out.append(i)
            i = self.nodes[i][4]
        return out[::-1]


class SmacSearch:
    """Nav2's AStarAlgorithm::createPath over a planner's nodes (see the module's docstring)."""

    def __init__(
        self,
        params: SmacParams,
        checker: GridCollisionChecker,
        heuristic: list[float],
        analytic: AnalyticExpansion,
        bins: int,
        yaws: Sequence[float],
    ) -> None:
        self.params = params
        self.checker = checker
        self.heuristic = heuristic
        self.analytic = analytic
        self.bins = bins
        self.yaws = yaws
        self.expansions = 0

    def key(self, x: float, y: float, b: int) -> int:
        return (math.floor(y) * self.checker.nx + math.floor(x)) * self.bins + b

    def run(
        self,
        start: tuple[float, float, int],
        goal: CellPose,
        goal_bin: int,
        expand: Expand,
        cancel_checker: Callable[[], bool] | None = None,
    ) -> SearchResult:
        """A* from `start` (cells, bin) to `goal` (cells, radians; its bin `goal_bin`)."""
        p = self.params
        nx = self.checker.nx
        hg = self.heuristic
        gx, gy = goal[0], goal[1]
        goal_key = self.key(gx, gy, goal_bin)
        tolerance = p.tolerance / self.checker.costmap.resolution
        ratio = p.analytic_expansion_ratio
        min_countdown = math.ceil(ratio)
        max_iterations = p.max_iterations if p.max_iterations > 0 else math.inf
        max_approach = (
            p.max_on_approach_iterations if p.max_on_approach_iterations > 0 else math.inf
        )
        sqrt, heappush, heappop = math.sqrt, heapq.heappush, heapq.heappop

        sx, sy, sb = start
        start_key = self.key(sx, sy, sb)
        nodes: list[Node] = [(sx, sy, sb, 0.0, -1, -1, start_key)]
        best_g = {start_key: 0.0}
        closed: set[int] = set()
        dx, dy = sx - gx, sy - gy
        h0 = max(hg[math.floor(sy) * nx + math.floor(sx)], sqrt(dx * dx + dy * dy))
        # Equal totals go to the node nearer the goal, so plateaus are crossed, not flooded.
        queue: list[tuple[float, float, int]] = [(h0, h0, 0)]
        countdown, closest = 0, math.inf  # the first node tries the goal at once
        desired = min_countdown
        best_approach: tuple[float, int] | None = None
        approach_iterations = 0
        expansions = 0
        next_poll = 0
        try:
            while queue:
                if cancel_checker is not None and expansions >= next_poll:
                    next_poll = expansions + p.terminal_checking_interval
                    if cancel_checker():
                        raise PlannerCancelled("Planner was cancelled")
                _, here, i = heappop(queue)
                node = nodes[i]
                key = node[6]
                if key in closed:
                    continue
                closed.add(key)
                expansions += 1
                if key == goal_key:
                    return SearchResult(nodes, i, [], expansions)
                if here <= tolerance:
                    # Within tolerance means the base could still get there: along a curve,
                    # not the straight line (a node on the goal facing away is not near it).
                    gap = self.analytic.gap((node[0], node[1], self.yaws[node[2]]), goal)
                    if gap <= tolerance and (best_approach is None or gap < best_approach[0]):
                        best_approach = (gap, i)
                if best_approach is not None:
                    approach_iterations += 1
                    if approach_iterations >= max_approach:
                        break
                if expansions >= max_iterations:
                    break
                # Analytic expansion: more often as the goal nears (Nav2's desired iterations;
                # a start the heuristic cannot reach from the goal has an infinite one).
                if here < closest:
                    closest = here
                    desired = max(int(closest / ratio), min_countdown)
                if desired < countdown:
                    countdown = desired
                if countdown <= 0:
                    countdown = desired
                    found = self.analytic.from_node(nodes, i, self.yaws, goal)
                    if found is not None:
                        return SearchResult(nodes, found[0], found[1], expansions)
                countdown -= 1
                g = node[3]
                for ckey, cell, cx, cy, cb, step, prim in expand(node, closed):
                    g_child = g + step
                    if g_child >= best_g.get(ckey, math.inf):
                        continue
                    best_g[ckey] = g_child
                    nodes.append((cx, cy, cb, g_child, i, prim, ckey))
                    h = hg[cell]
                    dx, dy = cx - gx, cy - gy
                    d = sqrt(dx * dx + dy * dy)
                    if d > h:
                        h = d
                    heappush(queue, (g_child + h, h, len(nodes) - 1))
        finally:
            self.expansions = expansions
        if best_approach is not None:
            return SearchResult(nodes, best_approach[1], [], expansions)
        if expansions >= max_iterations:
            raise PlannerTimedOut(f"exceeded maximum iterations ({p.max_iterations})")
        raise NoValidPathCouldBeFound(f"no path to the goal after {expansions} expansions")


# -- smoothing ---------------------------------------------------------------------------


def smooth_path(
    path: Path,
    costmap: Costmap2D,
    params: SmacSmootherParams,
    minimum_turning_radius: float,
    holonomic: bool = False,
) -> Path:
    """Nav2's Smac smoother: gradient descent on each stretch between cusps, kept only
    while no sampled turn is tighter than the minimum turning radius."""
    if len(path) < 4:
        return path
    smoother = SimpleSmoother(
        "smoother",
        SimpleSmoother.Params(
            max_its=params.max_iterations, w_smooth=params.w_smooth, w_data=params.w_data,
            tolerance=params.tolerance, do_refinement=params.do_refinement,
            refinement_num=params.refinement_num, is_holonomic=holonomic,
        ),
    )  # fmt: skip
    smoothed = smoother.smooth(path, costmap).path
    if max_curvature(smoothed.poses) > 1.0 / minimum_turning_radius * 1.05:
        return path
    return smoothed


def max_curvature(poses: NDArray[np.float64]) -> float:
    """The sharpest turn along a path: |heading change| / distance between samples."""
    d = np.diff(poses[:, :2], axis=0)
    ds = fmath.hypot(d[:, 0], d[:, 1])
    turn = np.abs((np.diff(poses[:, 2]) + np.pi) % (2.0 * np.pi) - np.pi)
    moved = ds > 1e-9
    return float(np.max(turn[moved] / ds[moved], initial=0.0))


def cells_to_world(poses: Sequence[CellPose], costmap: Costmap2D) -> NDArray[np.float64]:
    """(N, 3) poses in the costmap's frame from poses in cells."""
    out = np.array(poses, dtype=np.float64).reshape(-1, 3)
    out[:, 0] = costmap.origin_x + out[:, 0] * costmap.resolution
    out[:, 1] = costmap.origin_y + out[:, 1] * costmap.resolution
    return out
