"""NavFn's navigation function: cost mapping, potential field and gradient-descent path.

The algorithm of nav2_navfn_planner (navfn.cpp), restated for numpy:

- Costs are mapped as NavFn maps them: a costmap cost `c` < 253 becomes
  `COST_NEUTRAL + floor(COST_FACTOR * c)` (50..251), inscribed and lethal cells become
  `COST_OBS`, unknown cells become `COST_OBS - 1` when unknown space is allowed and
  `COST_OBS` otherwise, and the outer border of the grid is an obstacle.
- The potential is 0 at the robot's cell and grows by a cell's mapped cost for every
  cell length travelled through it; `POT_HIGH` marks cells never reached. NavFn
  propagates a 4-neighbour planar wave with bucketed priorities; here the same cost
  field is propagated by a shortest-path search on the 16-connected grid (the 8
  neighbours and the knight's moves; scipy.sparse.csgraph.dijkstra, a step costs its
  length times the mean cost of the cells it enters, no corner cutting between two
  blocked cells), which is exact for that graph and runs in C. Like NavFn's, the search
  stops soon after the goal: it is bounded by the straight-line cost plus a detour
  allowance (doubled and searched again only if the goal lies beyond). A* (`use_astar`)
  is the same search on heuristic-reduced weights, so it visits only cells near the
  straight line and, its heuristic being consistent, yields the same potential along
  the optimal path.
- The path is extracted as `calcPath` does: from the goal cell, step half a cell down
  the bilinearly interpolated, normalised potential gradient; next to unreached cells
  (or when oscillating) follow the grid to the lowest of the eight neighbours; stop
  when the potential falls below `COST_NEUTRAL` (the robot's cell is next). Where that
  descent fails on this potential although it reached the goal (its 4-neighbour
  gradient can lose its way among unknown cells, see `extract_path`), the path follows
  the grid all the way, which on this potential always reaches the robot.
"""

from __future__ import annotations

import math
from array import array
from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra

from ..core import fmath
from ..core.kernel_switch import Method, default_method
from ..costmap.cost_values import INSCRIBED_INFLATED_OBSTACLE, NO_INFORMATION
from . import navfn_kernel
from .exceptions import PlannerCancelled

#: The search and the descent compiled (navfn_kernel) or scipy's and Python's, the same
#: bits either way; BTNAV_NAVFN=numpy in the environment runs the reference.
DEFAULT_METHOD: Method = default_method("BTNAV_NAVFN")

COST_NEUTRAL = 50
COST_FACTOR = 0.8
COST_OBS = 254
POT_HIGH = 1.0e10
#: Gradient-descent step, in cells (NavFn's pathStep).
PATH_STEP = 0.5
SQRT2 = math.sqrt(2.0)
SQRT5 = math.sqrt(5.0)

#: (dy, dx) of the 16 neighbours (the 8 around a cell and the 8 knight's moves), in
#: the column order of the graph's CSR rows.
_OFFSETS = (
    (-1, -1), (-1, 0), (-1, 1), (0, -1), (0, 1), (1, -1), (1, 0), (1, 1),
    (-2, -1), (-2, 1), (-1, -2), (-1, 2), (1, -2), (1, 2), (2, -1), (2, 1),
)  # fmt: skip
_K = len(_OFFSETS)


def navfn_costs(costs: NDArray[np.uint8], allow_unknown: bool) -> NDArray[np.uint8]:
    """NavFn's `costarr` from a costmap's Nav2 costs (setCostmap + the border of setupNavFn)."""
    out = _navfn_cost_table(allow_unknown)[np.asarray(costs, dtype=np.uint8)]
    out[0, :] = out[-1, :] = COST_OBS
    out[:, 0] = out[:, -1] = COST_OBS
    return out


def _navfn_cost_table(allow_unknown: bool) -> NDArray[np.uint8]:
    """NavFn's mapped cost of each of the 256 costmap costs."""
    c = np.arange(256)
    out = np.full(256, COST_OBS, dtype=np.uint8)
    free = c < INSCRIBED_INFLATED_OBSTACLE
    mapped = COST_NEUTRAL + np.floor(COST_FACTOR * c[free].astype(np.float64))
    out[free] = np.minimum(mapped, COST_OBS - 1).astype(np.uint8)
    if allow_unknown:
        out[NO_INFORMATION] = COST_OBS - 1
    return out


class GridGraph:
    """The 16-connected graph of one grid shape; its structure is built once and reused.

    Every cell has a CSR row of `_K` entries, one per offset; an off-grid neighbour
    points at some cell of the grid with an infinite weight (never relaxed: no edge).
    """

    def __init__(self, ny: int, nx: int) -> None:
        self.shape = (ny, nx)
        n = ny * nx
        #: The flat index step to each neighbour, in the order of a row's weights.
        self.shifts = np.array([dy * nx + dx for dy, dx in _OFFSETS], dtype=np.int64)
        cols = np.arange(n, dtype=np.int32)[:, None] + self.shifts.astype(np.int32)
        np.clip(cols, 0, n - 1, out=cols)  # off-grid: any valid cell, the weight is inf
        self.indices = cols.reshape(-1)
        self.indptr = np.arange(0, _K * n + 1, _K, dtype=np.int32)
        #: Doublings of the detour allowance the last search from this graph needed.
        self.doublings = 0
        self._cache_costs: NDArray[np.uint8] | None = None
        self._cache: csr_matrix | None = None

    def weights(
        self, costarr: NDArray[np.uint8], h: NDArray[np.float64] | None = None
    ) -> NDArray[np.float64]:
        """Edge weights: the step length times the mean mapped cost of the cells it
        enters (for a straight or diagonal step, the one cell entered).

        With a heuristic `h` (ny, nx), the weights are reduced by it (A*'s
        `w(u, v) + h(v) - h(u)`, clipped at 0 against rounding)."""
        ny, nx = self.shape
        out = np.empty((ny, nx, _K))
        # computed offset by offset on contiguous planes of a block of rows (small enough
        # to stay in cache), then laid out as CSR rows
        rows = max(1, min(ny, 16384 // max(nx, 1)))
        for y0 in range(0, ny, rows):
            y1 = min(ny, y0 + rows)
            out[y0:y1] = _weight_block(costarr, h, y0, y1, 0, nx)
        return out.reshape(-1)

    def cached_graph(self, costarr: NDArray[np.uint8]) -> csr_matrix:
        """The graph of `costarr`'s own weights, updated only where the costs changed
        (a planner server replans on a mostly unchanged global costmap): a weight depends
        only on the cells within two of its own, so the rows and columns of each changed
        stretch of rows, two cells wider, are recomputed (the same values a full rebuild
        gives them)."""
        ny, nx = self.shape
        cached = self._cache_costs
        if self._cache is None or cached is None or cached.shape != costarr.shape:
            self._cache = self.graph(self.weights(costarr))
            self._cache_costs = costarr.copy()
            return self._cache
        changed = costarr != cached
        rows = np.flatnonzero(changed.any(axis=1))
        if rows.size == 0:
            return self._cache
        data = self._cache.data.reshape(ny, nx, _K)
        # stretches of changed rows less than 5 apart are done together
        breaks = np.flatnonzero(np.diff(rows) > 4)
        firsts = np.r_[rows[0], rows[breaks + 1]].tolist()
        lasts = np.r_[rows[breaks], rows[-1]].tolist()
        for r0, r1 in zip(firsts, lasts, strict=True):
            cols = np.flatnonzero(changed[r0 : r1 + 1].any(axis=0))
            y0, y1 = max(r0 - 2, 0), min(r1 + 3, ny)
            x0, x1 = max(int(cols[0]) - 2, 0), min(int(cols[-1]) + 3, nx)
            data[y0:y1, x0:x1] = _weight_block(costarr, None, y0, y1, x0, x1)
        np.copyto(cached, costarr)
        return self._cache

    def graph(self, weights: NDArray[np.float64]) -> csr_matrix:
        """The CSR graph of these weights (an infinite weight is never relaxed: no edge)."""
        n = self.indptr.size - 1
        return csr_matrix((weights, self.indices, self.indptr), shape=(n, n))


def _weight_block(
    costarr: NDArray[np.uint8],
    h: NDArray[np.float64] | None,
    y0: int,
    y1: int,
    x0: int,
    x1: int,
) -> NDArray[np.float64]:
    """The (y1 - y0, x1 - x0, _K) edge weights of cells [y0, y1) x [x0, x1) (see
    `GridGraph.weights`), from the cells within two of them (off-grid cells are blocked)."""
    ny, nx = costarr.shape
    r, c = y1 - y0, x1 - x0
    # the block and a margin of two cells, padded with inf (blocked) off the grid
    pad = np.full((r + 4, c + 4), np.inf)
    sy0, sy1, sx0, sx1 = max(y0 - 2, 0), min(y1 + 2, ny), max(x0 - 2, 0), min(x1 + 2, nx)
    src = costarr[sy0:sy1, sx0:sx1]
    inner = pad[sy0 - y0 + 2 : sy1 - y0 + 2, sx0 - x0 + 2 : sx1 - x0 + 2]
    np.copyto(inner, src)
    np.copyto(inner, np.inf, where=src >= COST_OBS)
    blocked = np.isinf(pad)
    hpad = None
    if h is not None:
        hpad = np.zeros((r + 4, c + 4))  # off-grid weights are inf whatever h adds
        hpad[sy0 - y0 + 2 : sy1 - y0 + 2, sx0 - x0 + 2 : sx1 - x0 + 2] = h[sy0:sy1, sx0:sx1]

    def at(dy: int, dx: int, a: NDArray[np.float64] = pad) -> NDArray[np.float64]:
        return a[2 + dy : 2 + dy + r, 2 + dx : 2 + dx + c]

    blk = np.empty((_K, r, c))
    for k, (dy, dx) in enumerate(_OFFSETS):
        w = blk[k]
        if abs(dy) + abs(dx) == 1:
            np.copyto(w, at(dy, dx))
        elif abs(dy) == abs(dx):
            np.multiply(at(dy, dx), SQRT2, out=w)
            # no corner cutting: both cells beside the diagonal must be passable
            np.copyto(w, np.inf, where=at(dy, 0, blocked) | at(0, dx, blocked))
        else:
            # a knight's move crosses two cells on its way into a third
            sy, sx = int(np.sign(dy)), int(np.sign(dx))
            np.add(at(sy, 0) if abs(dy) == 2 else at(0, sx), at(sy, sx), out=w)
            w += at(dy, dx)
            w *= SQRT5 / 3.0
        if hpad is not None:
            w += at(dy, dx, hpad)
            w -= at(0, 0, hpad)
    if hpad is not None:
        np.maximum(blk, 0.0, out=blk)  # rounding: h is consistent
    return blk.transpose(1, 2, 0)


def _search(
    graph: csr_matrix,
    source: int,
    limit: float = np.inf,
    method: Method = DEFAULT_METHOD,
    min_weight: float = 0.0,
    shifts: NDArray[np.int64] | None = None,
) -> NDArray[np.float64]:
    """Shortest distances from `source` over a `GridGraph`'s graph; inf beyond `limit`.

    The compiled search needs the grid's `shifts`, a finite limit and the least edge
    weight (A*'s reduced weights can be 0: scipy's search then)."""
    if method == "kernel" and shifts is not None and min_weight > 0 and math.isfinite(limit):
        weights = graph.data.reshape(-1, shifts.size)
        return navfn_kernel.dijkstra(weights, shifts, source, limit, min_weight)
    return dijkstra(graph, directed=True, indices=source, limit=limit)  # type: ignore[no-any-return]


#: At most this many doublings of the detour allowance are searched ahead.
_MAX_AHEAD = 3


class _BoundedSearch:
    """`_search(csr, source, limit)` for a growing limit, from as few searches as can be.

    Dijkstra with a limit keeps exactly the distances <= limit (scipy relaxes an edge
    only to a value <= limit, and a shorter search never changes the distances it
    keeps), so cutting a longer search at `limit` gives the very same array."""

    def __init__(
        self,
        csr: csr_matrix,
        source: int,
        method: Method = DEFAULT_METHOD,
        min_weight: float = 0.0,
        shifts: NDArray[np.int64] | None = None,
    ) -> None:
        self.csr, self.source, self.method = csr, source, method
        self.min_weight, self.shifts = min_weight, shifts
        self.searched = -math.inf
        self.dist: NDArray[np.float64] | None = None

    def up_to(self, limit: float, reach: float) -> NDArray[np.float64]:
        """The distances up to `limit` (inf beyond); a new search goes on to `reach`."""
        if self.dist is None or limit > self.searched:
            self.searched = max(limit, reach)
            self.dist = _search(
                self.csr, self.source, self.searched, self.method, self.min_weight, self.shifts
            )
        dist = self.dist
        if limit >= self.searched:
            return dist.copy()
        return np.where(dist <= limit, dist, np.inf)


#: The first search allows paths this much longer (relative) than the straight line
#: before it searches again with twice the allowance.
DETOUR = 0.15
#: Potential beyond the goal's that is still computed, for the descent around the goal.
GOAL_BAND = 8 * COST_NEUTRAL


def compute_potential(
    graph: GridGraph,
    costarr: NDArray[np.uint8],
    start: tuple[int, int],
    goal: tuple[int, int],
    use_astar: bool = False,
    cancel_checker: Callable[[], bool] | None = None,
    method: Method = DEFAULT_METHOD,
) -> NDArray[np.float64]:
    """The (ny, nx) potential from the robot cell `start` (mx, my); POT_HIGH where unreached.

    Both searches stop soon after reaching `goal` (as NavFn's do): a single search
    bounded by the straight-line cost plus an allowance for detours, which is doubled
    (and the search repeated) only when the goal lies beyond it.
    """
    ny, nx = costarr.shape
    src = start[1] * nx + start[0]
    dst = goal[1] * nx + goal[0]
    _check(cancel_checker)
    straight = COST_NEUTRAL * fmath.hypot(goal[0] - start[0], goal[1] - start[1])
    # A step never adds more than this, so no reached cell lies beyond the bound by more.
    max_step = 2.0 * COST_OBS * SQRT2
    h = None
    if use_astar:
        ys, xs = np.ogrid[:ny, :nx]
        h = COST_NEUTRAL * fmath.hypot(xs - goal[0], ys - goal[1])
        csr = graph.graph(graph.weights(costarr, h))
        base = 0.0  # reduced distances: the goal's is its detour over the straight line
    else:
        csr = graph.cached_graph(costarr)
        base = straight
    slack = DETOUR * straight + GOAL_BAND
    # no step weighs less than one cell of the cheapest cost (A*'s reduced weights: 0)
    min_weight = 0.0 if use_astar else float(costarr.min())
    search = _BoundedSearch(csr, src, method, min_weight, graph.shifts)
    # The searches below are cut from one longer search where they can be: as far as the
    # bound the last plan needed (most replans need as many doublings as the one before).
    ahead = base + slack * 2.0**graph.doublings
    doublings = 0
    while True:
        _check(cancel_checker)
        bound = base + slack
        dist = search.up_to(bound, max(bound, ahead) + GOAL_BAND)
        reached = np.isfinite(dist)
        if reached[dst] or dist[reached].max() + max_step < bound:
            break  # found, or the reachable region is exhausted below the bound
        slack *= 2.0
        doublings += 1
    graph.doublings = min(doublings, _MAX_AHEAD)
    if reached[dst] and dist[dst] + GOAL_BAND > bound:
        # a band of a few cells beyond the goal, for the gradient descent around it
        limit = dist[dst] + GOAL_BAND
        dist = search.up_to(limit, limit + GOAL_BAND)
    if h is not None:
        dist = dist - h.reshape(-1) + h.flat[src]
    dist[~np.isfinite(dist)] = POT_HIGH
    return dist.reshape(ny, nx)


def _check(cancel_checker: Callable[[], bool] | None) -> None:
    if cancel_checker is not None and cancel_checker():
        raise PlannerCancelled("planning was cancelled by its cancel_checker")


def _c_round(v: float) -> int:
    """C's round(): halves away from zero."""
    return math.floor(v + 0.5) if v >= 0 else -math.floor(-v + 0.5)


def extract_path(
    potential: NDArray[np.float64],
    from_xy: tuple[float, float],
    to_cell: tuple[int, int],
    max_cycles: int,
    cancel_checker: Callable[[], bool] | None = None,
    method: Method = DEFAULT_METHOD,
) -> NDArray[np.float64] | None:
    """NavFn's calcPath: (N, 2) map coordinates from `from_xy` down the potential to
    `to_cell` (the potential's zero), or None on failure.

    Coordinates are in cells with cell centres at integers (cell (i, j) is (i, j));
    the descent starts at `from_xy` itself, not at its cell's centre.

    calcPath reads its gradient from a cell's four neighbours. That leads down NavFn's
    own potential (a planar-wave update leaves a cell above its lowest 4-neighbour) but
    not always down this 16-connected one: a cell reached by a diagonal or knight's step
    between two costlier cells, such as the unknown cells (COST_OBS - 1) scattered along
    a SLAM map's frontier, lies below all four of its neighbours; around it the gradient
    turns back uphill, and the descent circles until `max_cycles` (calcPath's
    oscillation check, an exact repeat two steps back, misses a drifting loop, and its
    fallback steps onto that very cell). So when calcPath fails, the path follows the
    grid all the way instead: a path calcPath finds is kept as it is.
    """
    if method == "kernel":
        flat = np.ascontiguousarray(potential, dtype=np.float64).reshape(-1)
        for on_grid in (False, True):
            path = _descend_compiled(
                flat, potential.shape[1], from_xy, to_cell, max_cycles, on_grid, cancel_checker
            )
            if path is _OUT_OF_RANGE:
                break  # the reference reads beyond the grid here: its answer is the one
            if path is not None:
                return path  # type: ignore[return-value]
        else:
            return None
    ny, nx = potential.shape
    pot = array("d")
    pot.frombytes(np.ascontiguousarray(potential, dtype=np.float64).tobytes())
    gradients = _gradients(pot, nx, nx * ny)
    for on_grid in (False, True):
        path = _descend(
            pot, nx, ny, gradients, from_xy, to_cell, max_cycles, on_grid, cancel_checker
        )
        if path is not None:
            return path
    return None


#: `_descend_compiled`'s answer where the reference descent reads beyond the potential.
_OUT_OF_RANGE = object()
#: `_descend`'s steps between two polls of the cancel checker.
_POLL_EVERY = 1000


def _descend_compiled(
    pot: NDArray[np.float64],
    nx: int,
    from_xy: tuple[float, float],
    to_cell: tuple[int, int],
    max_cycles: int,
    on_grid: bool,
    cancel_checker: Callable[[], bool] | None,
) -> NDArray[np.float64] | object | None:
    """`_descend` in navfn_kernel.descend, stretch by stretch between the polls of the
    cancel checker `_descend` makes (before steps 999, 1999, ...)."""
    fx, fy = math.floor(from_xy[0]), math.floor(from_xy[1])
    state = np.array([0.0, fy * nx + fx, from_xy[0] - fx, from_xy[1] - fy, 0.0])
    xs, ys = np.empty(max_cycles + 1), np.empty(max_cycles + 1)
    stop = min(max_cycles, _POLL_EVERY - 1)
    while True:
        status = navfn_kernel.descend(pot, nx, pot.size, state, xs, ys, stop, on_grid,
                                      COST_NEUTRAL, POT_HIGH, COST_OBS, PATH_STEP)  # fmt: skip
        if status == navfn_kernel.REACHED:
            n = int(state[4])
            xs[n], ys[n] = to_cell
            return np.column_stack([xs[: n + 1], ys[: n + 1]])
        if status == navfn_kernel.OUT_OF_RANGE:
            return _OUT_OF_RANGE
        if status == navfn_kernel.FAILED or stop >= max_cycles:
            return None
        _check(cancel_checker)
        stop = min(max_cycles, stop + _POLL_EVERY)


def _gradients(
    pot: array[float], nx: int, ns: int
) -> tuple[dict[int, tuple[float, float]], Callable[[int], tuple[float, float]]]:
    """NavFn's gradCell (the normalised 4-neighbour potential difference, pointing down)
    and its cache, shared by both descents."""
    grads: dict[int, tuple[float, float]] = {}

    def grad(n: int) -> tuple[float, float]:
        g = grads.get(n)
        if g is not None:
            return g
        if n < nx or n > ns - nx:
            g = (0.0, 0.0)
        else:
            cv, lft, rgt, up, dn = pot[n], pot[n - 1], pot[n + 1], pot[n - nx], pot[n + nx]
            gx = gy = 0.0
            if cv >= POT_HIGH:
                if lft < POT_HIGH:
                    gx = -COST_OBS
                elif rgt < POT_HIGH:
                    gx = COST_OBS
                if up < POT_HIGH:
                    gy = -COST_OBS
                elif dn < POT_HIGH:
                    gy = COST_OBS
            else:
                if lft < POT_HIGH:
                    gx += lft - cv
                if rgt < POT_HIGH:
                    gx += cv - rgt
                if up < POT_HIGH:
                    gy += up - cv
                if dn < POT_HIGH:
                    gy += cv - dn
            norm = fmath.hypot(gx, gy)
            g = (gx / norm, gy / norm) if norm > 0 else (0.0, 0.0)
        grads[n] = g
        return g

    return grads, grad


def _descend(
    pot: array[float],
    nx: int,
    ny: int,
    gradients: tuple[dict[int, tuple[float, float]], Callable[[int], tuple[float, float]]],
    from_xy: tuple[float, float],
    to_cell: tuple[int, int],
    max_cycles: int,
    on_grid: bool,
    cancel_checker: Callable[[], bool] | None,
) -> NDArray[np.float64] | None:
    """calcPath's descent; `on_grid` follows the grid at every step (calcPath's fallback
    next to unreached cells: to the lowest of the eight neighbours). On this potential
    that always goes down (a reached cell's predecessor in the search, or for a knight's
    move the cell it crosses first, is one of its eight neighbours and lower), so it
    reaches the robot's cell within as many steps as there are cells on the way."""
    ns = nx * ny
    fx, fy = math.floor(from_xy[0]), math.floor(from_xy[1])
    stc = fy * nx + fx
    dx, dy = from_xy[0] - fx, from_xy[1] - fy
    xs: list[float] = []
    ys: list[float] = []
    high = POT_HIGH
    floor = math.floor
    grads, grad = gradients
    get = grads.get
    for i in range(max_cycles):
        if i % 1000 == 999:
            _check(cancel_checker)
        # _c_round(dx), _c_round(dy), inlined
        rx = floor(dx + 0.5) if dx >= 0 else -floor(-dx + 0.5)
        ry = floor(dy + 0.5) if dy >= 0 else -floor(-dy + 0.5)
        nearest = min(max(stc + rx + nx * ry, 0), ns - 1)
        if pot[nearest] < COST_NEUTRAL:
            xs.append(float(to_cell[0]))
            ys.append(float(to_cell[1]))
            return np.column_stack([xs, ys])
        if stc < nx or stc > ns - nx:
            return None
        xs.append(stc % nx + dx)
        ys.append(stc // nx + dy)
        up, down = stc - nx, stc + nx
        follow_grid = (
            on_grid
            or (len(xs) > 2 and xs[-1] == xs[-3] and ys[-1] == ys[-3])  # oscillating
            or pot[stc] >= high
            or pot[up - 1] >= high
            or pot[up] >= high
            or pot[up + 1] >= high
            or pot[stc - 1] >= high
            or pot[stc + 1] >= high
            or pot[down - 1] >= high
            or pot[down] >= high
            or pot[down + 1] >= high
        )
        if follow_grid:
            ring = (up - 1, up, up + 1, stc - 1, stc + 1, down - 1, down, down + 1)
            best, best_pot = stc, pot[stc]
            for k in ring:
                if pot[k] < best_pot:
                    best, best_pot = k, pot[k]
            stc, dx, dy = best, 0.0, 0.0
            if best_pot >= high:
                return None
            continue
        # gradients from the cache when there (a gradient is a non-empty tuple: truthy)
        g00 = get(stc) or grad(stc)
        g10 = get(stc + 1) or grad(stc + 1)
        g01 = get(down) or grad(down)
        g11 = get(down + 1) or grad(down + 1)
        x = (1 - dy) * ((1 - dx) * g00[0] + dx * g10[0]) + dy * ((1 - dx) * g01[0] + dx * g11[0])
        y = (1 - dy) * ((1 - dx) * g00[1] + dx * g10[1]) + dy * ((1 - dx) * g01[1] + dx * g11[1])
        if x == 0.0 and y == 0.0:
            return None
        ss = PATH_STEP / fmath.hypot(x, y)
        dx += x * ss
        dy += y * ss
        if dx > 1.0:
            stc += 1
            dx -= 1.0
        if dx < -1.0:
            stc -= 1
            dx += 1.0
        if dy > 1.0:
            stc += nx
            dy -= 1.0
        if dy < -1.0:
            stc -= nx
            dy += 1.0
    return None
