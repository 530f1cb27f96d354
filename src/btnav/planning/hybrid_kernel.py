"""Hybrid-A*'s expansion loop in a numba kernel, with SmacSearch.run's plans bit for bit.

The Python search costs interpreter time per expansion; here the loop runs compiled over
arrays and returns to Python only for what is rare (an analytic expansion, a node within
`tolerance` of the goal, a cancel poll, more room for nodes). It is the same search: the
same node fields, a heap ordered as heapq orders (f, h, index), the same step costs and
heuristic in the same IEEE steps, and SmacSearch.run's order of tests and counters
(tests/planning/test_hybrid_kernel.py compares the plans). `cache=True`, no fastmath, no
parallel. Details: docs/decisions/0005.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import NamedTuple

import numba as nb
import numpy as np
from numpy.typing import NDArray

from ..core.fmath_kernels import JIT
from .exceptions import NoValidPathCouldBeFound, PlannerCancelled, PlannerTimedOut
from .smac_common import CellPose, GridCollisionChecker, Node, SearchResult, SmacSearch

F64 = NDArray[np.float64]
I64 = NDArray[np.int64]
U8 = NDArray[np.uint8]

#: What `advance` returns: why it stopped.
GOAL, GAP, ANALYTIC, POLL, ROOM, EXHAUSTED, STOPPED = range(1, 8)
#: Where `advance` resumes: pop a node; after its tolerance check; after its analytic try.
_POP, _AFTER_GAP, _AFTER_ANALYTIC = range(3)
#: `SearchState.counters` slots.
(PHASE, NODE, N_NODES, HEAP_SIZE, N_BLOCKS, EXPANSIONS, COUNTDOWN, DESIRED,
 APPROACH_ITERATIONS, NEXT_POLL, BEST_NODE) = range(11)  # fmt: skip
#: `SearchState.reals` slots: the popped node's h, the nearest h so far, the best gap.
HERE, CLOSEST, BEST_GAP = range(3)
#: max_iterations and max_on_approach_iterations when Nav2's are 0 or less (no limit).
NO_LIMIT = int(np.iinfo(np.int64).max)


class HybridTables(NamedTuple):
    """One plan's read-only inputs (P primitives, B heading bins, C cells)."""

    dx: F64  # (B, P) each primitive's step from each heading bin (cells)
    dy: F64
    child_bin: I64  # (B, P)
    length: F64  # (P,) travel length
    turn_factor: F64  # (7, P) per parent's turn + 1 (0: the start)
    reverse_factor: F64  # (P,)
    direction: I64  # (P,) the turn a child is reached by (Nav2's TurnDirection)
    per_cell: F64  # (C,) (1 - retrospective_penalty) + cost_penalty * norm
    heuristic: F64  # (C,) the obstacle heuristic
    blocked: U8  # (C,) any pose collides
    outline: U8  # (C,) a polygon's outline must be checked (zeros: a radius footprint)
    bad: U8  # (C,) what puts an outline in collision
    rim_bounds: I64  # (B, 4) lo_x, hi_x, lo_y, hi_y of the bin's vertices' cell offsets
    rim_start: I64  # (B + 1,) bin b's outline cells are rim_offsets[rim_start[b]:...]
    rim_offsets: I64
    nx: int
    ny: int
    bins: int
    polygon: bool
    goal_x: float
    goal_y: float
    goal_key: int
    tolerance: float
    ratio: float
    min_countdown: int
    max_iterations: int
    max_approach: int
    poll_interval: int
    poll: bool


class SearchState(NamedTuple):
    """The search between returns to Python (replaced by a larger one when full)."""

    counters: I64  # see the slot names
    reals: F64
    node_f: F64  # (N, 3) x, y, g
    node_i: I64  # (N, 4) bin, parent, turn, key
    heap_f: F64  # (N, 2) f, h
    heap_i: I64  # (N,) node index
    cell_block: I64  # (C,) block of each cell, -1: none yet
    best_g: F64  # (K, B) per block and bin; inf: never queued
    closed: U8  # (K, B)
    footprint: NDArray[np.int8]  # (K, B) the outline's verdict; -1: not checked yet


# -- the heap -------------------------------------------------------------------------------
# Helpers called in the sift loops take numbers only: numba counts a reference to every
# array handed to a function, inlined or not (~10 ns an array a call).


@nb.njit(inline="always", **JIT)
def _before(f1: float, h1: float, n1: int, f2: float, h2: float, n2: int) -> bool:
    """(f1, h1, n1) < (f2, h2, n2), as Python compares tuples."""
    if f1 != f2:
        return f1 < f2
    if h1 != h2:
        return h1 < h2
    return n1 < n2


@nb.njit(**JIT)
def _push(hf: F64, hi: I64, size: int, f: float, h: float, node: int) -> None:
    """Put (f, h, node) in the heap of `size` entries (hf: f, h; hi: node index)."""
    k = size
    while k > 0:
        parent = (k - 1) >> 1
        if not _before(f, h, node, hf[parent, 0], hf[parent, 1], hi[parent]):
            break
        hf[k, 0], hf[k, 1], hi[k] = hf[parent, 0], hf[parent, 1], hi[parent]
        k = parent
    hf[k, 0], hf[k, 1], hi[k] = f, h, node


@nb.njit(**JIT)
def _pop(hf: F64, hi: I64, size: int) -> None:
    """Take the top off the heap of `size` entries: it moves to slot size - 1."""
    last = size - 1
    top_f, top_h, top_i = hf[0, 0], hf[0, 1], hi[0]
    f, h, node = hf[last, 0], hf[last, 1], hi[last]  # sifted down from the root
    k = 0
    while True:
        child = 2 * k + 1
        if child >= last:
            break
        right = child + 1
        if right < last and _before(
            hf[right, 0], hf[right, 1], hi[right], hf[child, 0], hf[child, 1], hi[child]
        ):
            child = right
        if not _before(hf[child, 0], hf[child, 1], hi[child], f, h, node):
            break
        hf[k, 0], hf[k, 1], hi[k] = hf[child, 0], hf[child, 1], hi[child]
        k = child
    hf[k, 0], hf[k, 1], hi[k] = f, h, node
    hf[last, 0], hf[last, 1], hi[last] = top_f, top_h, top_i


# -- per (cell, bin) ------------------------------------------------------------------------


@nb.njit(**JIT)
def _outline_hit(
    rim_bounds: I64, rim_start: I64, rim_offsets: I64, bad: U8, nx: int, ny: int, cell: int, b: int
) -> bool:
    """GridCollisionChecker.footprint_hit for (cell, bin): bin b's outline laid around the
    cell, colliding off the map or on a bad cell (the caller remembers the answer)."""
    my, mx = cell // nx, cell % nx
    if (
        mx + rim_bounds[b, 0] < 0 or my + rim_bounds[b, 2] < 0
        or mx + rim_bounds[b, 1] >= nx or my + rim_bounds[b, 3] >= ny
    ):  # fmt: skip
        return True
    for j in range(rim_start[b], rim_start[b + 1]):  # noqa: SIM110 (a loop numba compiles)
        if bad[cell + rim_offsets[j]]:
            return True
    return False


# -- the loop -------------------------------------------------------------------------------


@nb.njit(inline="always", **JIT)
def _expand(t: HybridTables, s: SearchState, i: int) -> None:
    """Queue node i's children that are on the map, free, not closed and cheaper than
    their key's best so far (SmacPlannerHybrid's `expand` and SmacSearch.run's loop)."""
    x, y, g = s.node_f[i, 0], s.node_f[i, 1], s.node_f[i, 2]
    b, turn = s.node_i[i, 0], s.node_i[i, 2]
    bins = t.bins
    for p in range(t.length.shape[0]):
        cx = x + t.dx[b, p]
        cy = y + t.dy[b, p]
        mx, my = math.floor(cx), math.floor(cy)
        if mx < 0 or my < 0 or mx >= t.nx or my >= t.ny:
            continue
        cell = my * t.nx + mx
        if t.blocked[cell]:
            continue
        cb = t.child_bin[b, p]
        blk = s.cell_block[cell]
        if blk >= 0 and s.closed[blk, cb]:
            continue
        if t.polygon and t.outline[cell]:
            if blk < 0:  # the cell's block of per-bin entries, on first use
                blk = s.counters[N_BLOCKS]
                s.counters[N_BLOCKS] = blk + 1
                s.cell_block[cell] = blk
            if s.footprint[blk, cb] < 0:
                hit = _outline_hit(
                    t.rim_bounds, t.rim_start, t.rim_offsets, t.bad, t.nx, t.ny, cell, cb
                )
                s.footprint[blk, cb] = 1 if hit else 0
            if s.footprint[blk, cb] == 1:
                continue
        step = t.length[p] * t.per_cell[cell] * t.turn_factor[turn + 1, p] * t.reverse_factor[p]
        g_child = g + step
        if blk >= 0 and not g_child < s.best_g[blk, cb]:
            continue
        if blk < 0:
            blk = s.counters[N_BLOCKS]
            s.counters[N_BLOCKS] = blk + 1
            s.cell_block[cell] = blk
        s.best_g[blk, cb] = g_child
        n = s.counters[N_NODES]
        s.node_f[n, 0], s.node_f[n, 1], s.node_f[n, 2] = cx, cy, g_child
        s.node_i[n, 0], s.node_i[n, 1], s.node_i[n, 2] = cb, i, t.direction[p]
        s.node_i[n, 3] = cell * bins + cb
        s.counters[N_NODES] = n + 1
        h = t.heuristic[cell]
        dx, dy = cx - t.goal_x, cy - t.goal_y
        d = math.sqrt(dx * dx + dy * dy)
        if d > h:
            h = d
        _push(s.heap_f, s.heap_i, s.counters[HEAP_SIZE], g_child + h, h, n)
        s.counters[HEAP_SIZE] += 1


@nb.njit(**JIT)
def advance(t: HybridTables, s: SearchState) -> int:
    """Run SmacSearch.run's loop from where it stopped until Python is needed: returns
    GOAL, GAP or ANALYTIC (node `counters[NODE]`), POLL, ROOM, EXHAUSTED or STOPPED."""
    c, r = s.counters, s.reals
    n_prims = t.length.shape[0]
    while True:
        if c[PHASE] == _POP:
            if c[HEAP_SIZE] == 0:
                return EXHAUSTED
            if t.poll and c[EXPANSIONS] >= c[NEXT_POLL]:
                c[NEXT_POLL] = c[EXPANSIONS] + t.poll_interval
                return POLL
            _pop(s.heap_f, s.heap_i, c[HEAP_SIZE])
            c[HEAP_SIZE] -= 1
            top = c[HEAP_SIZE]
            here, i = s.heap_f[top, 1], s.heap_i[top]
            key = s.node_i[i, 3]
            blk, b = s.cell_block[key // t.bins], s.node_i[i, 0]
            if s.closed[blk, b]:
                continue
            s.closed[blk, b] = 1
            c[EXPANSIONS] += 1
            c[NODE] = i
            r[HERE] = here
            c[PHASE] = _AFTER_GAP
            if key == t.goal_key:
                return GOAL
            if here <= t.tolerance:
                return GAP  # Python measures the curve to the goal
        if c[PHASE] == _AFTER_GAP:
            if c[BEST_NODE] >= 0:
                c[APPROACH_ITERATIONS] += 1
                if c[APPROACH_ITERATIONS] >= t.max_approach:
                    return STOPPED
            if c[EXPANSIONS] >= t.max_iterations:
                return STOPPED
            here = r[HERE]
            if here < r[CLOSEST]:
                r[CLOSEST] = here
                c[DESIRED] = max(int(here / t.ratio), t.min_countdown)
            if c[DESIRED] < c[COUNTDOWN]:
                c[COUNTDOWN] = c[DESIRED]
            c[PHASE] = _AFTER_ANALYTIC
            if c[COUNTDOWN] <= 0:
                c[COUNTDOWN] = c[DESIRED]
                return ANALYTIC  # Python tries a curve to the goal
        # _AFTER_ANALYTIC
        if c[N_NODES] + n_prims > s.node_f.shape[0] or c[N_BLOCKS] + n_prims > s.closed.shape[0]:
            return ROOM
        c[COUNTDOWN] -= 1
        _expand(t, s, c[NODE])
        c[PHASE] = _POP


# -- Python's side --------------------------------------------------------------------------


def new_state(n_cells: int, bins: int, nodes: int = 4096, blocks: int = 512) -> SearchState:
    """An empty search with room for `nodes` nodes and `blocks` cells' entries."""
    counters = np.zeros(11, np.int64)
    counters[BEST_NODE] = -1
    return SearchState(
        counters,
        np.array([0.0, math.inf, math.inf]),
        np.zeros((nodes, 3)),
        np.zeros((nodes, 4), np.int64),
        np.zeros((nodes, 2)),
        np.zeros(nodes, np.int64),
        np.full(n_cells, -1, np.int64),
        np.full((blocks, bins), math.inf),
        np.zeros((blocks, bins), np.uint8),
        np.full((blocks, bins), -1, np.int8),
    )


def _grown(s: SearchState, n_prims: int) -> SearchState:
    """The same search with twice the room where a node's children might not fit."""

    def grow(a: np.ndarray, fill: float) -> np.ndarray:
        out = np.full((2 * a.shape[0] + n_prims, *a.shape[1:]), fill, a.dtype)
        out[: a.shape[0]] = a
        return out

    c = s.counters
    if c[N_NODES] + n_prims > s.node_f.shape[0]:
        s = s._replace(
            node_f=grow(s.node_f, 0.0), node_i=grow(s.node_i, 0),
            heap_f=grow(s.heap_f, 0.0), heap_i=grow(s.heap_i, 0),
        )  # fmt: skip
    if c[N_BLOCKS] + n_prims > s.closed.shape[0]:
        s = s._replace(
            best_g=grow(s.best_g, math.inf), closed=grow(s.closed, 0),
            footprint=grow(s.footprint, -1),
        )  # fmt: skip
    return s


class NodeArrays(Sequence[Node]):
    """The kernel's nodes read as SmacSearch's tuples (what SearchResult and
    AnalyticExpansion.from_node index)."""

    def __init__(self, s: SearchState) -> None:
        self._f, self._i, self._n = s.node_f, s.node_i, int(s.counters[N_NODES])

    def __len__(self) -> int:
        return self._n

    def __getitem__(self, k):  # type: ignore[no-untyped-def, override]
        if not isinstance(k, int | np.integer) or not -self._n <= k < self._n:
            raise IndexError(k)
        x, y, g = self._f[k].tolist()
        b, parent, turn, key = self._i[k].tolist()
        return (x, y, b, g, parent, turn, key)


def rims(checker: GridCollisionChecker) -> tuple[I64, I64, I64]:
    """Every heading bin's outline (GridCollisionChecker's rims) as flat arrays."""
    bounds, starts, offsets = [], [0], []
    for b in range(checker.bins):
        lo_x, hi_x, lo_y, hi_y, cells = checker.rim(b)
        bounds.append((lo_x, hi_x, lo_y, hi_y))
        offsets.extend(cells)
        starts.append(len(offsets))
    return (
        np.array(bounds, np.int64).reshape(-1, 4),
        np.array(starts, np.int64),
        np.array(offsets, np.int64),
    )


def run(
    search: SmacSearch,
    tables: HybridTables,
    start: tuple[float, float, int],
    goal: CellPose,
    cancel_checker: Callable[[], bool] | None = None,
) -> SearchResult:
    """SmacSearch.run for Hybrid-A*, its loop in `advance` (see the module docstring)."""
    nx, bins = tables.nx, tables.bins
    s = new_state(len(tables.heuristic), bins)
    sx, sy, sb = start
    start_cell = math.floor(sy) * nx + math.floor(sx)
    s.node_f[0] = (sx, sy, 0.0)
    s.node_i[0] = (sb, -1, -1, start_cell * bins + sb)
    s.cell_block[start_cell] = 0
    s.best_g[0, sb] = 0.0
    dx, dy = sx - goal[0], sy - goal[1]
    h0 = max(float(tables.heuristic[start_cell]), math.sqrt(dx * dx + dy * dy))
    s.heap_f[0] = (h0, h0)
    c = s.counters
    c[N_NODES], c[HEAP_SIZE], c[N_BLOCKS] = 1, 1, 1
    c[DESIRED] = tables.min_countdown  # countdown 0: the first node tries the goal at once
    tolerance = tables.tolerance
    try:
        while True:
            event = advance(tables, s)
            c = s.counters
            i = int(c[NODE])
            if event == GOAL:
                return SearchResult(NodeArrays(s), i, [], int(c[EXPANSIONS]))
            if event == GAP:
                x, y, b = s.node_f[i, 0], s.node_f[i, 1], int(s.node_i[i, 0])
                gap = search.analytic.gap((float(x), float(y), search.yaws[b]), goal)
                if gap <= tolerance and (c[BEST_NODE] < 0 or gap < s.reals[BEST_GAP]):
                    s.reals[BEST_GAP], c[BEST_NODE] = gap, i
            elif event == ANALYTIC:
                found = search.analytic.from_node(NodeArrays(s), i, search.yaws, goal)
                if found is not None:
                    return SearchResult(NodeArrays(s), found[0], found[1], int(c[EXPANSIONS]))
            elif event == POLL:
                if cancel_checker is not None and cancel_checker():
                    raise PlannerCancelled("Planner was cancelled")
            elif event == ROOM:
                s = _grown(s, len(tables.length))
            else:  # EXHAUSTED or STOPPED
                break
    finally:
        search.expansions = int(s.counters[EXPANSIONS])
    expansions = int(s.counters[EXPANSIONS])
    if s.counters[BEST_NODE] >= 0:
        return SearchResult(NodeArrays(s), int(s.counters[BEST_NODE]), [], expansions)
    if expansions >= tables.max_iterations:
        raise PlannerTimedOut(f"exceeded maximum iterations ({search.params.max_iterations})")
    raise NoValidPathCouldBeFound(f"no path to the goal after {expansions} expansions")
