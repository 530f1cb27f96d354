"""Cartographer's FastCorrelativeScanMatcher2D: the loop-closure search over a wide window.

Exact, by branch and bound on a stack of max-pooled grids built once when a submap
finishes (Cartographer's PrecomputationGridStack2D); translations are branched, headings
are not. Values are quantised to 0..255 as Cartographer's, so a score is an integer sum and
every search order finds the same best candidate (the first in the tree's order among
equals). The result is Cartographer's; the order of the work is numpy's: `match_batch`
runs many searches at once, bounds headings 8 at a time and scores children a part of the
points at a time. Details and measurements: docs/decisions/0070.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import numpy as np
from numpy.typing import NDArray

from ...core import fmath
from .matchers import _SPAN, _headings, angular_step
from .submaps import MAX_VALUE, MIN_PROBABILITY, Submap

F64 = NDArray[np.float64]
I64 = NDArray[np.int64]
I32 = NDArray[np.int32]
#: Lookups per batch (int64 indices: 1 MB, in cache with the grid's rows they touch).
_LOOKUPS = 1 << 17
#: Searches run together at most (their arrays: ~10 MB per 16 searches of Intel's).
_SEARCHES = 16
#: Headings bounded together above the top level (see `_Batch.groups`).
_GROUP = 8
#: The levels from the top down searched by heading group only (`_Batch.group_descent`;
#: one extra grid each per submap): below them, heading by heading.
_GROUP_LEVELS = 4
#: The candidates around the initial pose scored first (`_Batch.near`): offsets up to
#: this many cells and headings up to this many steps each way.
_NEAR_CELLS, _NEAR_HEADINGS = 1, 1
#: The points are scored in this many parts (every third point, from the first, second,
#: third), each child's running sum plus its parent's sums of the parts still to come
#: bounding it (`_Batch.run`).
_PARTS = 3
#: A block's four sub-blocks, in Cartographer's order: steps added to (2 x, 2 y).
_QUAD_X, _QUAD_Y = np.array([0, 1, 0, 1]), np.array([0, 0, 1, 1])

#: (points, min_score) -> the least sum of grid values scoring above min_score
_LEAST: dict[tuple[int, float], int] = {}

Query = tuple["FastCorrelativeScanMatcher", F64, F64]
Match = tuple[F64, float] | None


class FastCorrelativeScanMatcher:
    """Branch and bound over a finished submap (see the module doc)."""

    def __init__(self, submap: Submap, branch_and_bound_depth: int) -> None:
        self.submap = submap
        v = np.maximum(submap.values.astype(np.int64), 1) - 1
        half = MAX_VALUE - 1  # round(v 255 / 32766), in integers
        q = ((v * 510 + half) // (2 * half)).astype(np.uint8)
        level = np.pad(q, 1)  # a border of 0 (probability 0.1): clipped lookups read it
        self.row0, self.col0 = submap.row0 - 1, submap.col0 - 1
        self.shape = level.shape
        self.levels = [level]
        for d in range(branch_and_bound_depth - 1):
            w = 1 << d
            p = np.pad(level, ((0, w), (0, w)))
            level = np.maximum(
                np.maximum(p[:-w, :-w], p[:-w, w:]), np.maximum(p[w:, :-w], p[w:, w:])
            )
            self.levels.append(level)
        self.pad = 0  # the levels' margin of clipped lookups (`padded`)
        #: level -> its maximum over heading-group boxes, flat (`padded` builds them)
        self.group_grids: dict[int, NDArray[np.uint8]] = {}

    def padded(self, n: int) -> tuple[list[NDArray[np.uint8]], int]:
        """The levels, flat, each inside a margin of 2 n + 1 cells that read as a clipped
        lookup does (edge values): a search n cells wide then needs no clipping per
        candidate (see `_Batch`); and the padded width. Kept for the next search."""
        margin = 2 * n + 1
        if self.pad != margin:
            h, w = self.shape
            p = self.pad
            self.levels = [
                np.pad(g[p : p + h, p : p + w], margin, mode="edge") for g in self.levels
            ]
            self.pad = margin
            top = len(self.levels) - 1
            self.group_grids = {d: _window_max(self.levels[d], _GROUP).reshape(-1) for d in range(max(top - _GROUP_LEVELS + 1, 0), top + 1)}  # fmt: skip
        return [g.reshape(-1) for g in self.levels], self.shape[1] + 2 * margin

    def match(
        self,
        points: F64,
        initial: F64,
        linear_window: float,
        angular_window: float,
        min_score: float,
    ) -> Match:
        """The best pose (local frame) within the windows around `initial` scoring above
        `min_score`, with its score; None if there is none."""
        return match_batch([(self, points, initial)], linear_window, angular_window, min_score)[0]  # fmt: skip


def match_batch(
    queries: Sequence[Query], linear_window: float, angular_window: float, min_score: float
) -> list[Match]:
    """`FastCorrelativeScanMatcher.match` of each (matcher, points, initial) query, the
    same answers, computed together (see the module doc)."""
    out: list[Match] = [None] * len(queries)
    live = [k for k, q in enumerate(queries) if len(q[1])]
    rank: dict[int, int] = {}
    for k in live:  # a matcher's searches side by side: its grids are read in one run
        rank.setdefault(id(queries[k][0]), len(rank))
    live.sort(key=lambda k: rank[id(queries[k][0])])
    for j in range(0, len(live), _SEARCHES):
        chunk = live[j : j + _SEARCHES]
        found = _Batch([queries[k] for k in chunk], linear_window, angular_window).run(min_score)  # fmt: skip
        for k, f in zip(chunk, found, strict=True):
            out[k] = f
    return out


class _Batch:
    """Searches run together: their headings are the columns of one table of points'
    flat indices, their candidates one array per level (see the module doc).

    A candidate at level d reads cell (r + (sy << d), c + (sx << d)) for each point's
    (r, c) at step 0, clipped into its submap's level (whose border reads 0). The levels
    carry a margin of 2 n + 1 edge cells (`FastCorrelativeScanMatcher.padded`), so a
    lookup up to 2 n past the level reads what the clipped one does; a point already
    beyond that is clipped once, where every step of the window reads the same edge. A
    candidate's indices are then a point's flat index plus one offset.
    """

    def __init__(self, queries: Sequence[Query], linear_window: float, angular_window: float):
        self.queries = queries
        first = queries[0][0]
        res = first.submap.lattice.resolution
        self.res = res
        self.n = n = math.ceil(linear_window / res)
        margin = 2 * n + 1
        self.depth = len(first.levels)
        # the matchers, each with its columns (headings, then heading groups) in a run
        mats: list[FastCorrelativeScanMatcher] = []
        mat_of = np.empty(len(queries), np.int64)
        for s, (m, _, _) in enumerate(queries):
            if not mats or mats[-1] is not m:
                mats.append(m)
            mat_of[s] = len(mats) - 1
        padded = [m.padded(n) for m in mats]
        self.grids = [p[0] for p in padded]
        self.group_grids = [m.group_grids for m in mats]
        self.angles = [_headings(float(q[2][2]), angular_window, angular_step(q[1], res)) for q in queries]  # fmt: skip
        num_h = np.array([len(a) for a in self.angles])
        self.num_points = num_p = np.array([len(q[1]) for q in queries])
        self.first = np.concatenate([[0], np.cumsum(num_h)])  # a search's first heading
        search = np.repeat(np.arange(len(queries)), num_h)  # the search of each heading
        self.search = search
        # every heading's points turned and moved to its search's initial pose, as
        # matchers._point_cells computes them for one search
        pmax = int(num_p.max())
        xy = np.zeros((len(queries), pmax, 2))
        for s, q in enumerate(queries):
            xy[s, : len(q[1])] = q[1]
        sin, cos = fmath.sincos(np.concatenate(self.angles))
        x, y = xy[search, :, 0], xy[search, :, 1]
        init = np.array([q[2][:2] for q in queries])[search]
        lat = first.submap.lattice
        inv = 1.0 / lat.resolution
        cos, sin = cos[:, None], sin[:, None]
        # in place, the same steps: (cos x - sin y + x0 - lattice x0) inv + 0.5, floored
        wx, t = cos * x, sin * y
        wx -= t
        wx += init[:, 0:1]
        wx -= lat.x0
        wx *= inv
        wx += 0.5
        cols = np.floor(wx, out=wx).astype(np.int64)
        wy = np.multiply(sin, x, out=wx)
        np.multiply(cos, y, out=t)
        wy += t
        wy += init[:, 1:2]
        wy -= lat.y0
        wy *= inv
        wy += 0.5
        rows = np.floor(wy, out=wy).astype(np.int64)
        # clipped into each heading's submap; a missing point reads the dead cell
        hm = mat_of[search]
        shape = np.array([m.shape for m in mats])
        row0 = np.array([m.row0 for m in mats])
        col0 = np.array([m.col0 for m in mats])
        width = np.array([p[1] for p in padded])
        h, w = shape[hm, 0][:, None], shape[hm, 1][:, None]
        r, c = rows, cols
        r -= (row0[hm] + n)[:, None]
        c -= (col0[hm] + n)[:, None]
        for v, top in ((r, h), (c, w)):  # np.clip, in place
            np.maximum(v, -margin, out=v)
            np.minimum(v, top, out=v)
            v += margin
        self.dead = (shape[:, 0] + margin) * width + (shape[:, 1] + margin)  # 0 at every step
        missing = np.arange(pmax)[None, :] >= num_p[search][:, None]
        self.missing = missing
        base = r * width[hm][:, None]
        base += c
        np.copyto(base, self.dead[hm][:, None], where=missing)
        self.r, self.c = r, c
        self.parts = [np.ascontiguousarray(base[:, k::_PARTS].T) for k in range(_PARTS)]
        self.width = width[hm]  # per heading
        self.mat_of = mat_of
        self.mat_first = np.concatenate([[0], np.cumsum(np.bincount(hm, minlength=len(mats)))])  # fmt: skip
        self.hm = hm

    # -- the search ---------------------------------------------------------------------

    def run(self, min_score: float) -> list[Match]:
        top = self.depth - 1
        low = max(top - _GROUP_LEVELS + 1, 0)  # the first level scored heading by heading
        need = np.maximum(self.least_above(min_score), self.near())  # per search
        gneed = need[self.search]  # per heading
        # heading groups from the top down to `low`, then their headings
        g, sx, sy, parts = self.group_descent(top, low, need)
        a, sx, sy, parent = self.group_headings(g, sx, sy)
        total = sum(parts) if _PARTS > 1 else parts[0]
        for depth in range(low, -1, -1):
            a, sx, sy, parts, total = self.score_children(self.sums, depth, gneed, a, sx, sy, parent, parts, total)  # fmt: skip
            if depth == 0 or not len(a):
                break
            a, sx, sy, parent = self.children(depth, a, sx, sy)
        out: list[Match] = [None] * len(self.queries)
        if not len(a):
            return out
        # each search's best leaf, the first in its order among equals
        s = self.search[a]
        order = np.lexsort((self.tree_order(a, sx, sy), -total, s))
        firsts = order[np.flatnonzero(np.concatenate([[True], s[order][1:] != s[order][:-1]]))]  # fmt: skip
        score = self.score(total, self.num_points[s])
        n, res = self.n, self.res
        for k in firsts.tolist():
            q = int(s[k])
            initial = self.queries[q][2]
            heading = self.angles[q][int(a[k]) - int(self.first[q])]
            bx, by = int(sx[k]), int(sy[k])
            pose = np.array([initial[0] + (bx - n) * res, initial[1] + (by - n) * res, heading])
            out[q] = (pose, float(score[k]))
        return out

    def lattice(self, depth: int) -> int:
        """Lattice steps at a level: offsets -n, -n + 2^d, ... up to n."""
        return ((2 * self.n) >> depth) + 1

    def children(self, depth: int, a: I64, sx: I64, sy: I64) -> tuple[I64, I64, I64, I64]:
        """The four sub-blocks of each candidate at `depth`, those inside the window,
        and the index of each one's parent."""
        ca = np.repeat(a, 4)
        cx = ((2 * sx)[:, None] + _QUAD_X).ravel()
        cy = ((2 * sy)[:, None] + _QUAD_Y).ravel()
        last = self.lattice(depth - 1) - 1
        ok = (cx <= last) & (cy <= last)
        parent = np.repeat(np.arange(len(a)), 4)
        return ca[ok], cx[ok], cy[ok], parent[ok]

    @staticmethod
    def score(sums: NDArray[np.integer], num_points: NDArray[np.integer] | int) -> F64:
        """Scores (mean probability) of summed grid values."""
        return MIN_PROBABILITY + sums / num_points * (_SPAN / 255.0)

    def least_above(self, min_score: float) -> I64:
        """Per search, the least sum of grid values that scores above `min_score`."""
        out = np.empty(len(self.queries), np.int64)
        for s, p in enumerate(self.num_points.tolist()):
            least = _LEAST.get((p, min_score))
            if least is None:
                table = self.score(np.arange(255 * p + 2), p)
                least = _LEAST[(p, min_score)] = int(np.searchsorted(table, min_score, side="right"))  # fmt: skip
            out[s] = least
        return out

    def near(self) -> I64:
        """Per search, the best sum of the single-cell candidates around the initial pose
        (the middle heading and `_NEAR_HEADINGS` neighbours each way, offsets up to
        `_NEAR_CELLS` cells): a candidate below it cannot win (see the module doc)."""
        n = self.n
        k = np.arange(max(n - _NEAR_CELLS, 0), min(n + _NEAR_CELLS, 2 * n) + 1)
        num = np.diff(self.first)
        centre = self.first[:-1] + num // 2
        h = centre[:, None] + np.arange(-_NEAR_HEADINGS, _NEAR_HEADINGS + 1)
        ok = (h >= self.first[:-1, None]) & (h < self.first[1:, None])
        a, sy, sx = (g.reshape(h.size, -1)[ok.ravel()].ravel() for g in np.meshgrid(h.ravel(), k, k, indexing="ij"))  # fmt: skip
        sums = self.sums(0, a, sx, sy)
        starts = np.flatnonzero(np.concatenate([[True], self.search[a][1:] != self.search[a][:-1]]))  # fmt: skip
        return np.maximum.reduceat(sums, starts).astype(np.int64)

    def _take_sums(self, grids: Sequence[NDArray[np.uint8]], bounds: I64, base_t: I64, cols: I64, offset: I64) -> I32:  # fmt: skip
        """For each candidate k, the sum over points p of grid[base_t[p, cols[k]] +
        offset[k]], the grid its column's matcher's (columns `bounds[m]` up to
        `bounds[m + 1]` are matcher m's); `cols` sorted."""
        sums = np.empty(len(cols), np.int32)
        batch = max(1, _LOOKUPS // base_t.shape[0])
        acc = np.uint16 if base_t.shape[0] <= 257 else np.int32  # 257 x 255 < 2^16
        at = np.searchsorted(cols, bounds)
        for m in range(len(bounds) - 1):
            grid = grids[m]
            for j in range(int(at[m]), int(at[m + 1]), batch):
                k = min(j + batch, int(at[m + 1]))
                c = cols[j:k]
                lo, hi = int(c[0]), int(c[-1]) + 1
                idx = np.repeat(base_t[:, lo:hi], np.bincount(c - lo, minlength=hi - lo), axis=1)
                idx += offset[j:k]
                sums[j:k] = np.take(grid, idx).sum(axis=0, dtype=acc)
        return sums

    def sums(self, depth: int, a: I64, sx: I64, sy: I64, part: int | None = None) -> I32:
        """Summed grid values of candidates at one level, `a` sorted (as every level's
        candidates are: a heading's points are repeated for its run of candidates)."""
        offset = (sy * self.width[a] + sx) << depth
        grids = [g[depth] for g in self.grids]
        if part is None:  # every point
            return sum(self._take_sums(grids, self.mat_first, b, a, offset) for b in self.parts)  # type: ignore[return-value]
        return self._take_sums(grids, self.mat_first, self.parts[part], a, offset)

    def tree_order(self, a: I64, sx: I64, sy: I64) -> I64:
        """Single-cell candidates' places in the tree's order: heading, the top level's
        lattice (row by row), then each level's sub-block (Cartographer's order)."""
        top = self.depth - 1
        steps = self.lattice(top)
        key = (a * steps + (sy >> top)) * steps + (sx >> top)
        for d in range(top - 1, -1, -1):
            key = key * 4 + ((sy >> d) & 1) * 2 + ((sx >> d) & 1)
        return key

    def groups(self, need: I64) -> None:
        """The heading groups: _GROUP headings of a search at a time (its last group
        filled up with its last heading again). A point's cells over a group's headings
        lie in a box _GROUP cells wide (a heading moves the farthest point about a cell),
        so one read of a level's maximum over such boxes bounds the point at every
        heading of the group (a point whose box is wider reads 0 and counts 255)."""
        num = np.diff(self.first)
        per = -(-num // _GROUP)  # groups per search
        gsearch = np.repeat(np.arange(len(num)), per)
        k = np.arange(int(per.sum())) - np.repeat(np.cumsum(per) - per, per)
        fill = np.minimum(self.first[gsearch, None] + k[:, None] * _GROUP + np.arange(_GROUP), self.first[gsearch + 1, None] - 1)  # fmt: skip
        r, c = self.r[fill], self.c[fill]  # (groups, _GROUP, points)
        r0, c0 = r.min(axis=1), c.min(axis=1)
        wide = ((r.max(axis=1) - r0 > _GROUP) | (c.max(axis=1) - c0 > _GROUP)) & ~self.missing[fill[:, 0]]  # fmt: skip
        gm = self.mat_of[gsearch]
        width = self.width[fill[:, 0]]
        base = np.where(wide | self.missing[fill[:, 0]], self.dead[gm][:, None], r0 * width[:, None] + c0)  # fmt: skip
        self.group_base_t = np.ascontiguousarray(base.T)  # (points, groups)
        self.group_parts_t = [np.ascontiguousarray(base[:, q::_PARTS].T) for q in range(_PARTS)]
        self.group_wide = 255 * wide.sum(axis=1)
        self.group_wide_parts = [255 * wide[:, q::_PARTS].sum(axis=1) for q in range(_PARTS)]
        self.group_width = width
        self.group_bounds = np.concatenate([[0], np.cumsum(np.bincount(gm, minlength=len(self.grids)))])  # fmt: skip
        self.group_need = need[gsearch]
        self.group_start = self.first[gsearch] + k * _GROUP  # a group's first heading
        self.group_size = np.minimum(num[gsearch] - k * _GROUP, _GROUP)

    def group_sums(self, depth: int, g: I64, sx: I64, sy: I64, part: int | None = None) -> I64:
        """Bounds of heading groups' candidates at a level (`g` sorted): each one's sum
        at every heading of its group is at most this (see `groups`)."""
        offset = (sy * self.group_width[g] + sx) << depth
        grids = [gg[depth] for gg in self.group_grids]
        if part is None:
            base_t, wide = self.group_base_t, self.group_wide
        else:
            base_t, wide = self.group_parts_t[part], self.group_wide_parts[part]
        return self._take_sums(grids, self.group_bounds, base_t, g, offset) + wide[g]

    def group_descent(self, top: int, low: int, need: I64) -> tuple[I64, I64, I64, list[I64]]:
        """The heading groups' candidates (group, step x, step y) from the top level down
        to `low` whose bounds reach their search's `need` at every level, and their
        bounds at `low` by part of the points."""
        self.groups(need)
        steps = np.arange(self.lattice(top))
        g, sy, sx = (v.ravel() for v in np.meshgrid(np.arange(len(self.group_need)), steps, steps, indexing="ij"))  # fmt: skip
        parts = [self.group_sums(top, g, sx, sy, q) for q in range(_PARTS)]
        total = sum(parts) if _PARTS > 1 else parts[0]
        keep = total >= self.group_need[g]
        g, sx, sy, total = g[keep], sx[keep], sy[keep], total[keep]
        parts = [q[keep] for q in parts]
        for depth in range(top - 1, low - 1, -1):
            g, sx, sy, parent = self.children(depth + 1, g, sx, sy)
            g, sx, sy, parts, total = self.score_children(self.group_sums, depth, self.group_need, g, sx, sy, parent, parts, total)  # fmt: skip
        return g, sx, sy, parts

    @staticmethod
    def score_children(sums: Callable[..., NDArray[np.integer]], depth: int, need: I64, a: I64, sx: I64, sy: I64, parent: I64, parts: list[I64], total: I64) -> tuple[I64, I64, I64, list[I64], I64]:  # fmt: skip
        """The candidates (`a` headings or groups, `sums` theirs) at `depth` that reach
        `need[a]`, with their sums by part and in all: scored a part of the points at a
        time, their sums over the parts done plus their parent's (`parts`, `total`) over
        the parts to come bounding them."""
        remaining, done, new = total, None, []
        for k in range(_PARTS):
            q = sums(depth, a, sx, sy, k)
            done = q if done is None else done + q
            new.append(q)
            if k + 1 < _PARTS:
                remaining = remaining - parts[k]
                keep = done + remaining[parent] >= need[a]
                a, sx, sy, parent, done = a[keep], sx[keep], sy[keep], parent[keep], done[keep]
                new = [q[keep] for q in new]
        keep = done >= need[a]
        return a[keep], sx[keep], sy[keep], [q[keep] for q in new], done[keep]

    def group_headings(self, g: I64, sx: I64, sy: I64) -> tuple[I64, I64, I64, I64]:
        """Each group candidate's headings (heading, step x, step y; sorted by heading),
        and the index of each one's group candidate."""
        size = self.group_size[g]
        parent = np.repeat(np.arange(len(g)), size)
        a = self.group_start[g][parent] + (np.arange(len(parent)) - np.repeat(np.cumsum(size) - size, size))  # fmt: skip
        order = np.argsort(a, kind="stable")
        parent = parent[order]
        return a[order], sx[parent], sy[parent], parent


def _window_max(grid: NDArray[np.uint8], e: int) -> NDArray[np.uint8]:
    """At each cell, the maximum over the (e + 1) x (e + 1) cells from it (the grid's
    far edges: over the part inside)."""
    rows = grid.copy()
    for k in range(1, e + 1):
        np.maximum(rows[:-k], grid[k:], out=rows[:-k])
    out = rows.copy()
    for k in range(1, e + 1):
        np.maximum(out[:, :-k], rows[:, k:], out=out[:, :-k])
    return out
