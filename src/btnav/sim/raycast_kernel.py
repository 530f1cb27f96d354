"""The lidar's compiled ray caster: each beam walks a uniform grid of the static geometry.

raycast.py's numpy path costs in proportion to the world's segments; here the static
segments and circles are binned once into a `GridIndex` and each beam walks its cells
(Amanatides & Woo's DDA) until the nearest hit lies within the cells walked. Every number
that decides a range is computed by the same IEEE operations in the same order as
raycast.py, and the grid is conservative, so both paths give the same bits; no libm, no
fastmath, no parallel loop, `cache=True`. Details: docs/decisions/0004.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from numpy.typing import NDArray

#: Beyond its exact extent, every item is registered in the cells within this much of
#: it (metres), and more for a very short segment (see `_segment_margins`).
MARGIN = 1e-6
#: A beam stops walking when the nearest hit t satisfies t (1 + STOP_REL) + MARGIN <= the
#: ray's exit from the cell just walked; the walk ends past max_range by as much.
STOP_REL = 1e-7
#: Items per cell the grid is sized for (on average over the static items).
ITEMS_PER_CELL = 2.0
#: Bounds on the cell side (metres) and on the number of cells.
MIN_CELL, MAX_CELL = 0.05, 4.0
MAX_CELLS = 1 << 22
#: |a x e| (m^2) at or below which the origin counts as on a segment's line; and a
#: ray's sideways miss at a segment's far end within which it runs along it. These are
#: raycast.ON_LINE_AREA and raycast.COLLINEAR_TOL, repeated to keep this module free of
#: imports from its caller (tests/sim/test_raycast_kernel.py checks that they agree).
ON_LINE_AREA = 1e-12
COLLINEAR_TOL = 1e-9

# per-scan states of an item
_SKIP, _NORMAL, _ON_LINE, _ON_SEGMENT = 0, 1, 2, 3  # segments
_INSIDE = 2  # circles: the origin inside (the ray meets it on the way out)

_JIT = {"cache": True, "nogil": True, "error_model": "numpy", "boundscheck": False}


# -- building the grid ------------------------------------------------------------------


def _segment_margins(segments: NDArray[np.float64]) -> NDArray[np.float64]:
    """How far beyond each segment it is registered: MARGIN, the 1e-9 lengthening, and
    ON_LINE_AREA / length (an origin that close to a segment's line counts as on it)."""
    length = np.sqrt(
        (segments[:, 2] - segments[:, 0]) ** 2 + (segments[:, 3] - segments[:, 1]) ** 2
    )
    scale = np.abs(segments).max(axis=1) if len(segments) else np.zeros(0)
    with np.errstate(divide="ignore"):
        return MARGIN + 1e-8 * length + 1e-12 * scale + ON_LINE_AREA / np.maximum(length, 1e-300)


@nb.njit(**_JIT)
def _register(
    segs: NDArray[np.float64],
    seg_margin: NDArray[np.float64],
    circs: NDArray[np.float64],
    x0: float,
    y0: float,
    h: float,
    nx: int,
    ny: int,
    start: NDArray[np.int64],
    items: NDArray[np.int32],
    fill: bool,
) -> None:
    """Count (fill=False: into start[cell + 1]) or write (fill=True: at start[cell], which
    is advanced) the items of every cell: segment i is item i, circle j item S + j.

    A segment goes into each cell of its margin-grown bounding box whose rectangle is
    within its margin of the segment's line (the separating-axis test); a circle into
    each cell within r + margin of its centre. Zero-length segments go nowhere.
    """
    n_s = segs.shape[0]
    for i in range(n_s):
        ax, ay, bx, by = segs[i, 0], segs[i, 1], segs[i, 2], segs[i, 3]
        ex, ey = bx - ax, by - ay
        length = math.sqrt(ex * ex + ey * ey)
        if ax == bx and ay == by:
            continue
        m = seg_margin[i]
        nxu, nyu = -ey / length, ex / length
        reach = 0.5 * h * (abs(nxu) + abs(nyu)) + m
        i0 = max(0, math.floor((min(ax, bx) - m - x0) / h))
        i1 = min(nx - 1, math.floor((max(ax, bx) + m - x0) / h))
        j0 = max(0, math.floor((min(ay, by) - m - y0) / h))
        j1 = min(ny - 1, math.floor((max(ay, by) + m - y0) / h))
        for j in range(j0, j1 + 1):
            cy = y0 + (j + 0.5) * h
            for k in range(i0, i1 + 1):
                cx = x0 + (k + 0.5) * h
                if abs(nxu * (cx - ax) + nyu * (cy - ay)) <= reach:
                    cell = j * nx + k
                    if fill:
                        items[start[cell]] = i
                        start[cell] += 1
                    else:
                        start[cell + 1] += 1
    for i in range(circs.shape[0]):
        cx0, cy0, r = circs[i, 0], circs[i, 1], circs[i, 2]
        reach = r + MARGIN + 1e-9 * (abs(cx0) + abs(cy0) + r)
        i0 = max(0, math.floor((cx0 - reach - x0) / h))
        i1 = min(nx - 1, math.floor((cx0 + reach - x0) / h))
        j0 = max(0, math.floor((cy0 - reach - y0) / h))
        j1 = min(ny - 1, math.floor((cy0 + reach - y0) / h))
        for j in range(j0, j1 + 1):
            ly = y0 + j * h
            qy = min(max(cy0, ly), ly + h)
            for k in range(i0, i1 + 1):
                lx = x0 + k * h
                qx = min(max(cx0, lx), lx + h)
                if (qx - cx0) ** 2 + (qy - cy0) ** 2 <= reach * reach:
                    cell = j * nx + k
                    if fill:
                        items[start[cell]] = n_s + i
                        start[cell] += 1
                    else:
                        start[cell + 1] += 1


class GridIndex:
    """The static segments and circles binned into a uniform grid, with the per-item
    scratch a scan fills in (one index per caster: not shared between threads).

    Cells are squares of side `cell` (default: sized for `ITEMS_PER_CELL` items a cell
    over the geometry's bounding box), stored as compressed rows: the items of cell c
    are `items[start[c]:start[c + 1]]`.
    """

    def __init__(
        self,
        segments: NDArray[np.float64],
        circles: NDArray[np.float64],
        cell: float | None = None,
    ) -> None:
        self.segments = np.array(segments, dtype=np.float64, order="C").reshape(-1, 4)
        self.circles = np.array(circles, dtype=np.float64, order="C").reshape(-1, 3)
        n_s, n_c = len(self.segments), len(self.circles)
        margins = _segment_margins(self.segments)
        lo, hi = _bounds(self.segments, margins, self.circles)
        width, height = hi[0] - lo[0], hi[1] - lo[1]
        if cell is None:
            cell = math.sqrt(width * height * ITEMS_PER_CELL / max(1, n_s + n_c))
            cell = min(MAX_CELL, max(MIN_CELL, cell))
        cell = max(cell, math.sqrt(width * height / MAX_CELLS))
        self.cell = float(cell)
        self.x0, self.y0 = float(lo[0]), float(lo[1])
        self.nx = max(1, math.ceil(width / cell) + 1)
        self.ny = max(1, math.ceil(height / cell) + 1)
        start = np.zeros(self.nx * self.ny + 1, np.int64)
        empty = np.zeros(0, np.int32)
        args = (self.segments, margins, self.circles, self.x0, self.y0, self.cell)
        _register(*args, self.nx, self.ny, start, empty, False)
        np.cumsum(start, out=start)
        items = np.empty(start[-1], np.int32)
        cursor = start[:-1].copy()
        _register(*args, self.nx, self.ny, cursor, items, True)
        self.start, self.items = start, items
        # per-scan scratch: which scan last prepared an item, its state and its rows
        self.scan = 0
        self.seg_stamp = np.full(n_s, -1, np.int64)
        self.seg_state = np.zeros(n_s, np.int8)
        self.seg_rows = np.empty((n_s, 7))
        self.circ_stamp = np.full(n_c, -1, np.int64)
        self.circ_state = np.zeros(n_c, np.int8)
        self.circ_rows = np.empty((n_c, 3))

    def cast(
        self,
        origin: tuple[float, float],
        dirs_t: NDArray[np.float64],
        cap: float,
        prune_segments: bool,
        prune_circles: bool,
        one_sided: bool,
        rows: NDArray[np.float64],
        moving_segments: NDArray[np.float64],
        moving_circles: NDArray[np.float64],
    ) -> NDArray[np.float64]:
        """Ranges of the beams `dirs_t` (2, B) from `origin`, as raycast's numpy path
        gives them for these static items plus `moving_*` (hits beyond `cap`: inf).
        `rows` is raycast._ROWS."""
        self.scan += 1
        out = np.empty(dirs_t.shape[1])
        _cast(
            float(origin[0]),
            float(origin[1]),
            dirs_t,
            float(cap),
            prune_segments,
            prune_circles,
            one_sided,
            rows,
            self.segments,
            self.circles,
            self.x0,
            self.y0,
            self.cell,
            self.nx,
            self.ny,
            self.start,
            self.items,
            self.scan,
            self.seg_stamp,
            self.seg_state,
            self.seg_rows,
            self.circ_stamp,
            self.circ_state,
            self.circ_rows,
            moving_segments,
            moving_circles,
            out,
        )
        return out


def _bounds(
    segs: NDArray[np.float64], margins: NDArray[np.float64], circs: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The grid's corners: every item's registered extent, and a little more."""
    lows, highs = [np.zeros((0, 2))], [np.zeros((0, 2))]
    if len(segs):
        m = np.minimum(margins, 1e3)[:, None]
        lows.append(np.minimum(segs[:, :2], segs[:, 2:]) - m)
        highs.append(np.maximum(segs[:, :2], segs[:, 2:]) + m)
    if len(circs):
        lows.append(circs[:, :2] - circs[:, 2:3])
        highs.append(circs[:, :2] + circs[:, 2:3])
    lo, hi = np.concatenate(lows), np.concatenate(highs)
    if len(lo) == 0:
        return np.zeros(2), np.ones(2)
    lo, hi = lo.min(axis=0), hi.max(axis=0)
    pad = 1e-3 + 1e-9 * np.abs(np.concatenate([lo, hi])).max()
    return lo - pad, hi + pad


# -- the per-scan preparation of one item, as raycast.py does it for all -----------------


@nb.njit(inline="always", **_JIT)
def _prepare_segment(
    x1: float,
    y1: float,
    x2: float,
    y2: float,
    ox: float,
    oy: float,
    cap: float,
    prune: bool,
    one_sided: bool,
    rows: NDArray[np.float64],
    out: NDArray[np.float64],
) -> int:
    """The segment's state this scan and its rows in `out` (7): W, V, K (x, y each) for a
    `_NORMAL` one; p, q, the unit direction and the far end's distance `_ON_LINE`."""
    r0, r1, r2, r3 = x1 - ox, y1 - oy, x2 - ox, y2 - oy
    if prune:  # raycast._prune_segments
        mx = 0.5 * (r0 + r2)
        my = 0.5 * (r1 + r3)
        hx, hy = r2 - r0, r3 - r1
        half = 0.5 * math.sqrt(hx * hx + hy * hy)
        if not (math.sqrt(mx * mx + my * my) - half <= cap):
            return _SKIP
    c = r0 * r3 - r1 * r2  # p x q
    if one_sided and not (c <= ON_LINE_AREA):
        return _SKIP
    if abs(c) <= ON_LINE_AREA:  # raycast._on_line_hits
        ex, ey = r2 - r0, r3 - r1
        length = math.sqrt(ex * ex + ey * ey)
        if not (length > 0):
            return _SKIP
        if (r0 * ex + r1 * ey) * (r2 * ex + r3 * ey) <= 0:
            return _ON_SEGMENT
        out[0], out[1], out[2], out[3] = r0, r1, r2, r3
        out[4], out[5] = ex / length, ey / length
        fp, fq = math.sqrt(r0 * r0 + r1 * r1), math.sqrt(r2 * r2 + r3 * r3)
        out[6] = fp if fp >= fq else fq
        return _ON_LINE
    for j in range(6):  # fmath.matmul_k(rel, _ROWS) / c, one column at a time
        acc = r0 * rows[0, j]
        acc += r1 * rows[1, j]
        acc += r2 * rows[2, j]
        acc += r3 * rows[3, j]
        out[j] = acc / c
    return _NORMAL


@nb.njit(inline="always", **_JIT)
def _prepare_circle(
    cx: float,
    cy: float,
    r: float,
    ox: float,
    oy: float,
    cap: float,
    prune: bool,
    out: NDArray[np.float64],
) -> int:
    """The circle's state this scan and its rows in `out` (3): m / sqrt(c) and 1 / sqrt(c)
    for a `_NORMAL` one, m and c (<= 0) for one around the origin (`_INSIDE`)."""
    rx, ry, rr = cx - ox, cy - oy, r - 0.0
    c = (rx * rx) * 1.0
    c += (ry * ry) * 1.0
    c += (rr * rr) * -1.0  # fmath.dot_rows(rel * rel, _CIRCLE_C)
    if prune and not (c <= cap * (cap + 2.0 * rr)):
        return _SKIP
    if c <= 0:
        out[0], out[1], out[2] = rx, ry, c
        return _INSIDE
    root_c = math.sqrt(c)
    out[0], out[1], out[2] = rx / root_c, ry / root_c, 1.0 / root_c
    return _NORMAL


@nb.njit(inline="always", **_JIT)
def _segment_value(state: int, w: NDArray[np.float64], dx: float, dy: float) -> float:
    """1/t of the beam (dx, dy) at a prepared segment: a hit's is > 0, a miss's <= 0."""
    if state == _NORMAL:
        wv = w[0] * dx + w[1] * dy
        v = w[2] * dx + w[3] * dy
        k = w[4] * dx + w[5] * dy
        if v < wv:
            wv = v
        return wv if wv < k else k
    if state == _ON_LINE:
        side = abs(dx * w[5] - dy * w[4]) * w[6]
        tp = dx * w[0] + dy * w[1]
        tq = dx * w[2] + dy * w[3]
        t = tq if tq < tp else tp
        if side <= COLLINEAR_TOL and t >= 0:
            return 1.0 / t
        return -np.inf
    if state == _ON_SEGMENT:
        return np.inf
    return -np.inf


@nb.njit(inline="always", **_JIT)
def _circle_value(state: int, w: NDArray[np.float64], dx: float, dy: float) -> float:
    """1/t of the beam at a prepared circle (NaN where its line misses: never the max)."""
    if state == _NORMAL:
        b = w[0] * dx + w[1] * dy
        root = b * b
        root -= 1.0
        b += math.sqrt(root)
        return b * w[2]
    if state == _INSIDE:
        b = w[0] * dx + w[1] * dy
        return 1.0 / (b + math.sqrt(b * b - w[2]))
    return -np.inf


# -- the scan -----------------------------------------------------------------------------


@nb.njit(**_JIT)
def _cast(
    ox: float,
    oy: float,
    dirs_t: NDArray[np.float64],
    cap: float,
    prune_s: bool,
    prune_c: bool,
    one_sided: bool,
    rows: NDArray[np.float64],
    segs: NDArray[np.float64],
    circs: NDArray[np.float64],
    x0: float,
    y0: float,
    h: float,
    nx: int,
    ny: int,
    start: NDArray[np.int64],
    items: NDArray[np.int32],
    scan: int,
    seg_stamp: NDArray[np.int64],
    seg_state: NDArray[np.int8],
    seg_rows: NDArray[np.float64],
    circ_stamp: NDArray[np.int64],
    circ_state: NDArray[np.int8],
    circ_rows: NDArray[np.float64],
    mseg: NDArray[np.float64],
    mcirc: NDArray[np.float64],
    out: NDArray[np.float64],
) -> None:
    n_s = segs.shape[0]
    n_rays = dirs_t.shape[1]
    inv_cap = 1.0 / cap
    walk_limit = cap * (1.0 + STOP_REL) + MARGIN
    # the moving items, prepared for every beam
    n_ms, n_mc = mseg.shape[0], mcirc.shape[0]
    ms_state = np.zeros(n_ms, np.int8)
    ms_rows = np.empty((n_ms, 7))
    mc_state = np.zeros(n_mc, np.int8)
    mc_rows = np.empty((n_mc, 3))
    on_segment = False
    for i in range(n_ms):
        s = mseg[i]
        ms_state[i] = _prepare_segment(
            s[0], s[1], s[2], s[3], ox, oy, cap, prune_s, one_sided, rows, ms_rows[i]
        )
        on_segment |= ms_state[i] == _ON_SEGMENT
    for i in range(n_mc):
        s = mcirc[i]
        mc_state[i] = _prepare_circle(s[0], s[1], s[2], ox, oy, cap, prune_c, mc_rows[i])
    # the static items around the origin: an origin on a segment, circles around it
    inside = np.empty(0, np.int64)
    fx, fy = (ox - x0) / h, (oy - y0) / h
    if 0.0 <= fx < nx and 0.0 <= fy < ny:
        cell = math.floor(fy) * nx + math.floor(fx)
        a, b = start[cell], start[cell + 1]
        inside = np.empty(b - a, np.int64)
        n_inside = 0
        for p in range(a, b):
            it = items[p]
            if it < n_s:
                if seg_stamp[it] != scan:
                    s = segs[it]
                    seg_state[it] = _prepare_segment(
                        s[0], s[1], s[2], s[3], ox, oy, cap, prune_s, one_sided, rows, seg_rows[it]
                    )
                    seg_stamp[it] = scan
                on_segment |= seg_state[it] == _ON_SEGMENT
            else:
                ic = it - n_s
                if circ_stamp[ic] != scan:
                    s = circs[ic]
                    circ_state[ic] = _prepare_circle(
                        s[0], s[1], s[2], ox, oy, cap, prune_c, circ_rows[ic]
                    )
                    circ_stamp[ic] = scan
                if circ_state[ic] == _INSIDE:
                    inside[n_inside] = ic
                    n_inside += 1
        inside = inside[:n_inside]
    if on_segment:  # every beam reads 0, as in raycast._on_line_hits
        out[:] = 0.0
        return
    for ray in range(n_rays):
        dx, dy = dirs_t[0, ray], dirs_t[1, ray]
        best = -np.inf
        for i in range(n_ms):
            v = _segment_value(ms_state[i], ms_rows[i], dx, dy)
            if v > best:
                best = v
        for i in range(n_mc):
            v = _circle_value(mc_state[i], mc_rows[i], dx, dy)
            if v > best:
                best = v
        for i in inside:
            v = _circle_value(_INSIDE, circ_rows[i], dx, dy)
            if v > best:
                best = v
        # the walk: clip the ray to the grid, then cell by cell (Amanatides & Woo)
        t_in, t_out = 0.0, walk_limit
        gx1, gy1 = x0 + nx * h, y0 + ny * h
        if dx != 0.0:
            ta, tb = (x0 - ox) / dx, (gx1 - ox) / dx
            t_in = max(t_in, min(ta, tb))
            t_out = min(t_out, max(ta, tb))
        elif not (x0 <= ox <= gx1):
            t_out = -1.0
        if dy != 0.0:
            ta, tb = (y0 - oy) / dy, (gy1 - oy) / dy
            t_in = max(t_in, min(ta, tb))
            t_out = min(t_out, max(ta, tb))
        elif not (y0 <= oy <= gy1):
            t_out = -1.0
        if t_in <= t_out:
            ix = min(nx - 1, max(0, math.floor((ox + t_in * dx - x0) / h)))
            iy = min(ny - 1, max(0, math.floor((oy + t_in * dy - y0) / h)))
            step_x = 1 if dx > 0 else -1
            step_y = 1 if dy > 0 else -1
            t_best = 1.0 / best if best > 0 else np.inf  # the nearest hit so far
            while True:
                cell = iy * nx + ix
                for p in range(start[cell], start[cell + 1]):
                    it = items[p]
                    if it < n_s:
                        if seg_stamp[it] != scan:
                            s = segs[it]
                            seg_state[it] = _prepare_segment(
                                s[0], s[1], s[2], s[3], ox, oy, cap, prune_s, one_sided, rows,
                                seg_rows[it],
                            )  # fmt: skip
                            seg_stamp[it] = scan
                        v = _segment_value(seg_state[it], seg_rows[it], dx, dy)
                    else:
                        ic = it - n_s
                        if circ_stamp[ic] != scan:
                            s = circs[ic]
                            circ_state[ic] = _prepare_circle(
                                s[0], s[1], s[2], ox, oy, cap, prune_c, circ_rows[ic]
                            )
                            circ_stamp[ic] = scan
                        st = circ_state[ic]
                        v = _circle_value(st, circ_rows[ic], dx, dy) if st == _NORMAL else -np.inf
                    if v > best:
                        best = v
                if best > 0:
                    t_best = 1.0 / best
                # where the ray leaves this cell
                if dx > 0:
                    tx = (x0 + (ix + 1) * h - ox) / dx
                elif dx < 0:
                    tx = (x0 + ix * h - ox) / dx
                else:
                    tx = np.inf
                if dy > 0:
                    ty = (y0 + (iy + 1) * h - oy) / dy
                elif dy < 0:
                    ty = (y0 + iy * h - oy) / dy
                else:
                    ty = np.inf
                t_exit = tx if tx < ty else ty
                if t_best * (1.0 + STOP_REL) + MARGIN <= t_exit or t_exit > t_out:
                    break
                if tx < ty:
                    ix += step_x
                    if ix < 0 or ix >= nx:
                        break
                else:
                    iy += step_y
                    if iy < 0 or iy >= ny:
                        break
        out[ray] = 1.0 / best if best >= inv_cap else np.inf


@nb.njit(**_JIT)
def same_prefix(a: NDArray[np.float64], b: NDArray[np.float64]) -> bool:
    """Whether the first len(b) rows of `a` are `b`, bit for bit (both C-contiguous)."""
    if a.shape[0] < b.shape[0] or a.shape[1] != b.shape[1]:
        return False
    fa, fb = a.reshape(-1).view(np.uint64), b.reshape(-1).view(np.uint64)
    for i in range(fb.shape[0]):  # noqa: SIM110 (a loop numba compiles)
        if fa[i] != fb[i]:
            return False
    return True


@nb.njit(**_JIT)
def common_prefix(a: NDArray[np.float64], b: NDArray[np.float64]) -> int:
    """How many leading rows `a` and `b` share, bit for bit (both C-contiguous)."""
    n = min(a.shape[0], b.shape[0])
    if n == 0 or a.shape[1] != b.shape[1]:
        return 0
    k = a.shape[1]
    fa, fb = a.reshape(-1).view(np.uint64), b.reshape(-1).view(np.uint64)
    for i in range(n):
        for j in range(k):
            if fa[i * k + j] != fb[i * k + j]:
                return i
    return n


def _rows(a: NDArray[np.float64], k: int) -> NDArray[np.float64]:
    """`a` as C-contiguous float64 rows of `k` (the very array when it already is)."""
    if a.dtype == np.float64 and a.ndim == 2 and a.shape[1] == k and a.flags.c_contiguous:
        return a
    return np.ascontiguousarray(a, dtype=np.float64).reshape(-1, k)


#: A geometry's items beyond the last one shared with the previous scan's are moving
#: obstacles if there are at most this many; with more, the geometry is a new world.
MAX_MOVING = 256


class GridCaster:
    """Keeps a `GridIndex` of the static part of the geometry it is given scan after
    scan, and casts with the rest as moving items.

    The static part is found, not declared: a world's geometry is its static items
    followed by its moving ones (`World.geometry`). The first scan indexes everything;
    when a later scan's arrays differ from the indexed ones, the rows shared with the
    previous scan become the static part if few items are left over (they moved), or
    the whole geometry is indexed anew (another world). Arrays are compared bit for bit
    unless they are the very arrays indexed, which are assumed unchanged.
    """

    def __init__(self) -> None:
        self.index: GridIndex | None = None
        self._static_ids: tuple[int, int] = (0, 0)  # id() of the arrays indexed whole
        self._static_refs: tuple[object, object] = (None, None)  # keeps those ids alive
        self._last: tuple[NDArray[np.float64], NDArray[np.float64]] | None = None
        self.rebuilds = 0

    def split(
        self, segments: NDArray[np.float64], circles: NDArray[np.float64]
    ) -> tuple[GridIndex, NDArray[np.float64], NDArray[np.float64]]:
        """The index of the static items and the moving segments and circles left over."""
        original_s, original_c = segments, circles
        given = (id(segments), id(circles))
        segments = _rows(segments, 4)
        circles = _rows(circles, 3)
        index = self.index
        if index is not None:
            ns, nc = len(index.segments), len(index.circles)
            same_s = given[0] == self._static_ids[0] or same_prefix(segments, index.segments)
            same_c = given[1] == self._static_ids[1] or same_prefix(circles, index.circles)
            if same_s and same_c:
                self._last = (segments, circles)
                return index, segments[ns:], circles[nc:]
        ns, nc = len(segments), len(circles)
        if self._last is not None:
            ls = common_prefix(segments, self._last[0])
            lc = common_prefix(circles, self._last[1])
            if (ns - ls) + (nc - lc) <= MAX_MOVING:
                ns, nc = ls, lc
        self.index = GridIndex(segments[:ns], circles[:nc])
        self.rebuilds += 1
        self._static_ids = (
            given[0] if ns == len(segments) else 0,
            given[1] if nc == len(circles) else 0,
        )
        self._static_refs = (original_s, original_c)
        self._last = (segments, circles)
        return self.index, segments[ns:], circles[nc:]
