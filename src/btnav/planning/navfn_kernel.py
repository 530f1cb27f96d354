"""NavFn's two loops compiled with numba, with navfn.py's bits.

- `dijkstra`: scipy.sparse.csgraph.dijkstra on the planner's graph (navfn.GridGraph),
  from one source, bounded by `limit` as scipy bounds it (an edge is relaxed only to a
  value <= limit). scipy validates and copies the graph, then keeps its cells in a
  Fibonacci heap. Here a cell's 16 weights are read in place and each neighbour is
  found by its flat index step (no CSR indices: less memory traffic), and as no step
  weighs less than one cell of the cheapest mapped cost (`min_weight`, 50 for NavFn's
  costs), cells wait in buckets of half that width (Dial's queue): every cell of the
  lowest bucket is final (any other way to it costs at least a bucket more) and is
  settled without ordering them. The distances are the same floats: each is the least
  `dist[u] + w(u, v)` over the cells u settled before it, whatever the order in which
  cells of equal or nearby distance are settled (a cell settled later cannot lower it).
- `descend`: navfn._descend (calcPath's gradient descent, or its grid-following
  fallback) for a stretch of steps, the same float operations in the same order, the
  gradient recomputed where navfn.py caches it (the same value). It stops and says so
  where navfn.py would read past the potential's ends (a path along the grid's last
  row): the caller then runs navfn.py's own descent.

`cache=True`, no fastmath (no FMA contraction), no parallel, `error_model="numpy"`:
plain IEEE + - * / and sqrt, the bits of CPython's floats (tests/planning/
test_navfn_kernel.py compares both with navfn.py's reference paths).
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from numpy.typing import NDArray

from ..core.fmath_kernels import JIT

#: What `descend` returns as its status.
REACHED, FAILED, MORE, OUT_OF_RANGE = range(4)


@nb.njit(**JIT)
def dijkstra(
    weights: NDArray[np.float64],
    shifts: NDArray[np.int64],
    source: int,
    limit: float,
    min_weight: float,
) -> NDArray[np.float64]:
    """Shortest distances from `source` over a GridGraph: cell u's k-th weight leads to
    cell u + shifts[k] (an off-grid neighbour's weight is inf), none is less than
    `min_weight` (> 0); inf where above `limit` (finite)."""
    n = weights.shape[0]
    width = 0.5 * min_weight
    dist = np.full(n, np.inf)
    settled = np.zeros(n, np.bool_)
    # bucket b holds the cells with tentative distances in [b, b + 1) * width, as a
    # doubly linked list: its first cell, each cell's next and previous, and its bucket
    first = np.full(int(limit / width) + 1, -1, np.int64)
    after = np.empty(n, np.int64)
    before = np.empty(n, np.int64)
    bucket = np.full(n, -1, np.int64)
    dist[source] = 0.0
    first[0], after[source], before[source], bucket[source] = source, -1, -1, 0
    for b in range(first.size):
        while first[b] >= 0:
            u = first[b]
            first[b] = after[u]
            if after[u] >= 0:
                before[after[u]] = -1
            settled[u] = True
            du = dist[u]
            for k in range(shifts.size):
                d = du + weights[u, k]
                if not d <= limit:
                    continue  # beyond the limit, or no edge (an infinite weight)
                v = u + shifts[k]
                if settled[v] or not d < dist[v]:
                    continue
                dist[v] = d
                old = bucket[v]
                if old >= 0:  # out of its bucket
                    if before[v] >= 0:
                        after[before[v]] = after[v]
                    else:
                        first[old] = after[v]
                    if after[v] >= 0:
                        before[after[v]] = before[v]
                new = int(d / width)  # >= b + 2: no cell of bucket b can lower another
                bucket[v], before[v], after[v] = new, -1, first[new]
                if first[new] >= 0:
                    before[first[new]] = v
                first[new] = v
    return dist


@nb.njit(**JIT)
def _grad(pot: NDArray[np.float64], n: int, nx: int, ns: int, high: float, obs: float) -> tuple:
    """navfn._gradients' grad(n): the normalised 4-neighbour difference, pointing down."""
    if n < nx or n > ns - nx:
        return 0.0, 0.0
    cv, lft, rgt, up, dn = pot[n], pot[n - 1], pot[n + 1], pot[n - nx], pot[n + nx]
    gx = 0.0
    gy = 0.0
    if cv >= high:
        if lft < high:
            gx = -obs
        elif rgt < high:
            gx = obs
        if up < high:
            gy = -obs
        elif dn < high:
            gy = obs
    else:
        if lft < high:
            gx += lft - cv
        if rgt < high:
            gx += cv - rgt
        if up < high:
            gy += up - cv
        if dn < high:
            gy += cv - dn
    norm = math.sqrt(gx * gx + gy * gy)
    if norm > 0:
        return gx / norm, gy / norm
    return 0.0, 0.0


@nb.njit(**JIT)
def descend(
    pot: NDArray[np.float64],
    nx: int,
    ns: int,
    state: NDArray[np.float64],
    xs: NDArray[np.float64],
    ys: NDArray[np.float64],
    stop: int,
    on_grid: bool,
    neutral: float,
    high: float,
    obs: float,
    step: float,
) -> int:
    """navfn._descend's steps `state[0]` .. `stop` - 1 from cell `state[1]` at offset
    (`state[2]`, `state[3]`), the path's `state[4]` points so far in xs, ys; updates
    `state` and returns REACHED (the last point is the caller's), FAILED, MORE (at
    `stop`) or OUT_OF_RANGE (navfn.py would read beyond the potential)."""
    i, stc, dx, dy, count = int(state[0]), int(state[1]), state[2], state[3], int(state[4])
    status = MORE
    while i < stop:
        rx = math.floor(dx + 0.5) if dx >= 0 else -math.floor(-dx + 0.5)
        ry = math.floor(dy + 0.5) if dy >= 0 else -math.floor(-dy + 0.5)
        nearest = min(max(stc + rx + nx * ry, 0), ns - 1)
        if pot[nearest] < neutral:
            status = REACHED
            break
        if stc < nx or stc > ns - nx:
            status = FAILED
            break
        if stc - nx - 1 < 0 or stc + nx + 1 >= ns:
            status = OUT_OF_RANGE
            break
        xs[count] = (stc % nx) + dx
        ys[count] = (stc // nx) + dy
        count += 1
        up, down = stc - nx, stc + nx
        follow_grid = (
            on_grid
            or (count > 2 and xs[count - 1] == xs[count - 3] and ys[count - 1] == ys[count - 3])
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
        i += 1
        if follow_grid:
            best, best_pot = stc, pot[stc]
            for k in (up - 1, up, up + 1, stc - 1, stc + 1, down - 1, down, down + 1):
                if pot[k] < best_pot:
                    best, best_pot = k, pot[k]
            stc, dx, dy = best, 0.0, 0.0
            if best_pot >= high:
                status = FAILED
                break
            continue
        if down == ns - nx or down + 1 == ns - nx:  # its gradient would read pot[ns]
            status = OUT_OF_RANGE
            break
        g00x, g00y = _grad(pot, stc, nx, ns, high, obs)
        g10x, g10y = _grad(pot, stc + 1, nx, ns, high, obs)
        g01x, g01y = _grad(pot, down, nx, ns, high, obs)
        g11x, g11y = _grad(pot, down + 1, nx, ns, high, obs)
        x = (1 - dy) * ((1 - dx) * g00x + dx * g10x) + dy * ((1 - dx) * g01x + dx * g11x)
        y = (1 - dy) * ((1 - dx) * g00y + dx * g10y) + dy * ((1 - dx) * g01y + dx * g11y)
        if x == 0.0 and y == 0.0:
            status = FAILED
            break
        ss = step / math.sqrt(x * x + y * y)
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
    state[0], state[1], state[2], state[3], state[4] = i, stc, dx, dy, count
    return status
