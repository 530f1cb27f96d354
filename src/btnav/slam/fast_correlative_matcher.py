"""Cartographer's FastCorrelativeScanMatcher2D: the loop-closure search over a wide window.

Exact, by branch and bound on a stack of max-pooled grids (level d holds, at each cell,
the maximum over the 2^d x 2^d block of cells from it: an upper bound of every
candidate the block covers), built once when the submap finishes and kept, as
Cartographer's PrecomputationGridStack2D. Headings are not branched; translations are,
from a lattice 2^(depth - 1) cells apart down to single cells. Values are quantised to
0..255 over [0.1, 0.9], as Cartographer's precomputation grids, so a candidate's score
is an integer sum and every search order finds the same best candidate.

How it is computed (the result is Cartographer's; the order of the work is numpy's):

- A candidate is (heading, column step, row step) on its level's lattice: offset
  `step * 2^d - n` cells, n the window's half width in cells. Its children are the
  four sub-blocks at the next level whose offsets stay inside the window.
- Headings are bounded 8 at a time before they are scored one by one (`_Search.groups`:
  a point's cells over 8 neighbouring headings fit in a box 8 cells wide, and an extra
  grid per level holds the level's maximum over such boxes): top-level candidates whose
  group cannot beat `min_score`, and children of the next two levels whose group and
  block cannot beat the best so far (`_Search.group_bound`), are never scored. What is
  dropped could not have won, so every level keeps the same survivors.
- The bound starts at `min_score`, is raised by a beam dive (the best few coarse
  candidates carried down level by level to single cells), then every level's
  survivors (bound above the best score so far) are expanded together.
- Scoring: the levels are kept inside a margin of 2 n + 1 cells copied from their
  edges (what a clipped lookup reads), so a point's flat index at step 0, clipped once
  per search, plus one offset per candidate is every lookup: no table, no clipping per
  candidate. Candidates come sorted by heading, so the indices are the points' column
  of each heading repeated over its run (points x candidates: the sum runs down
  columns). Lookups go in batches that stay in cache; indices are int32. The margins
  and group grids cost memory: ~16 MB a finished submap of Intel's (650 x 690 cells)
  instead of ~3.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from .cartographer_matchers import _SPAN, _headings, _point_cells, angular_step
from .submaps import MAX_VALUE, MIN_PROBABILITY, Submap

F64 = NDArray[np.float64]
I64 = NDArray[np.int64]
I32 = NDArray[np.int32]
#: Lookups per batch (int32 indices: 512 kB, in cache with the grid's rows they touch).
_LOOKUPS = 1 << 17
#: Coarse candidates carried down by the beam dive that seeds the bound.
_BEAM = 4
#: Headings bounded together above the top level (see `_Search.groups`).
_GROUP = 8
#: The levels from the top down whose children are bounded by heading group first
#: (`_Search.group_bound`; one extra grid each per submap).
_GROUP_LEVELS = 3
#: A block's four sub-blocks, in Cartographer's order: steps added to (2 x, 2 y).
_QUAD_X, _QUAD_Y = np.array([0, 1, 0, 1]), np.array([0, 0, 1, 1])


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
        candidate (see `_Search`); and the padded width. Kept for the next search."""
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
    ) -> tuple[F64, float] | None:
        """The best pose (local frame) within the windows around `initial` scoring above
        `min_score`, with its score; None if there is none."""
        if len(points) == 0:
            return None
        res = self.submap.lattice.resolution
        angles = _headings(float(initial[2]), angular_window, angular_step(points, res))
        rows, cols = _point_cells(self.submap, points, initial[:2], angles)
        n = math.ceil(linear_window / res)
        search = _Search(self, rows, cols, n)
        top = len(self.levels) - 1
        steps = np.arange(search.lattice(top))
        a, sy, sx = (g.ravel() for g in np.meshgrid(np.arange(len(angles)), steps, steps, indexing="ij"))  # fmt: skip
        maybe = search.groups(top, min_score)
        a, sx, sy = a[maybe], sx[maybe], sy[maybe]
        score = search.score(search.sums(top, a, sx, sy))
        best: tuple[int, int, int] | None = None
        best_score = min_score
        leaf = search.dive(top, a, sx, sy, score)
        if leaf is not None and leaf[1] > best_score:
            best, best_score = leaf
        for depth in range(top, -1, -1):
            keep = score > best_score
            a, sx, sy, score = a[keep], sx[keep], sy[keep], score[keep]
            if depth == 0 or not len(a):
                break
            a, sx, sy = search.children(depth, a, sx, sy)
            if depth - 1 in search.group_grids:
                maybe = search.group_bound(depth - 1, a, sx, sy, best_score)
                a, sx, sy = a[maybe], sx[maybe], sy[maybe]
            score = search.score(search.sums(depth - 1, a, sx, sy))
        if len(a):
            k = int(np.argmax(score))
            best, best_score = (int(a[k]), int(sx[k]), int(sy[k])), float(score[k])
        if best is None:
            return None
        pose = np.array([initial[0] + (best[1] - n) * res, initial[1] + (best[2] - n) * res, angles[best[0]]])  # fmt: skip
        return pose, best_score


class _Search:
    """One search's points (a flat index per heading and point) and its scoring over the
    level grids.

    A candidate at level d reads cell (r + (sy << d), c + (sx << d)) for each point's
    (r, c) at step 0, clipped into the level (its border reads 0). The levels carry a
    margin of 2 n + 1 edge cells (`FastCorrelativeScanMatcher.padded`), so a lookup up to
    2 n past the level reads what the clipped one does; a point already beyond that is
    clipped once, where every step of the window reads the same edge. A candidate's
    indices are then a point's flat index plus one offset.
    """

    def __init__(self, matcher: FastCorrelativeScanMatcher, rows: I64, cols: I64, n: int) -> None:
        self.grids, width = matcher.padded(n)
        h, w = matcher.shape
        margin = 2 * n + 1
        r = np.clip(rows - (matcher.row0 + n), -margin, h) + margin
        c = np.clip(cols - (matcher.col0 + n), -margin, w) + margin
        base = (r * width + c).astype(np.int32)  # (headings, points)
        self.base = base
        self.r, self.c = r, c
        self.dead = (h + margin) * width + (w + margin)  # reads 0 at every step
        self.group_grids = matcher.group_grids
        self.base_t = np.ascontiguousarray(base.T)  # (points, headings)
        self.width, self.n = width, n
        self.num_points = rows.shape[1]

    def lattice(self, depth: int) -> int:
        """Lattice steps at a level: offsets -n, -n + 2^d, ... up to n."""
        return ((2 * self.n) >> depth) + 1

    def children(self, depth: int, a: I64, sx: I64, sy: I64) -> tuple[I64, I64, I64]:
        """The four sub-blocks of each candidate at `depth`, those inside the window."""
        ca = np.repeat(a, 4)
        cx = ((2 * sx)[:, None] + _QUAD_X).ravel()
        cy = ((2 * sy)[:, None] + _QUAD_Y).ravel()
        last = self.lattice(depth - 1) - 1
        ok = (cx <= last) & (cy <= last)
        return ca[ok], cx[ok], cy[ok]

    def dive(
        self, depth: int, a: I64, sx: I64, sy: I64, score: F64
    ) -> tuple[tuple[int, int, int], float] | None:
        """The best few candidates carried down to single cells: the best leaf reached."""
        o = np.argsort(-score, kind="stable")[:_BEAM]
        a, sx, sy = a[o], sx[o], sy[o]
        for d in range(depth, 0, -1):
            a, sx, sy = self.children(d, a, sx, sy)
            score = self.scores(d - 1, a, sx, sy)
            o = np.argsort(-score, kind="stable")[:_BEAM]
            a, sx, sy, score = a[o], sx[o], sy[o], score[o]
        if not len(a):
            return None
        return (int(a[0]), int(sx[0]), int(sy[0])), float(score[0])

    def groups(self, top: int, min_score: float) -> NDArray[np.bool_]:
        """Which top-level candidates (heading, step y, step x; flat) can score above
        `min_score`: _GROUP headings at a time, each point's cells over the group's
        headings lie in a box _GROUP cells wide (a heading moves the farthest point
        about a cell), so one read of the top level's max over such boxes bounds the
        group (a point whose box is wider counts 255)."""
        num, steps = len(self.r), self.lattice(top)
        groups = -(-num // _GROUP)
        # the last group is filled up with its last heading again
        fill = np.minimum(np.arange(groups * _GROUP), num - 1)
        r, c = self.r[fill].reshape(groups, _GROUP, -1), self.c[fill].reshape(groups, _GROUP, -1)
        r0, c0 = r.min(axis=1), c.min(axis=1)
        wide = (r.max(axis=1) - r0 > _GROUP) | (c.max(axis=1) - c0 > _GROUP)
        base = np.where(wide, self.dead, r0 * self.width + c0).astype(np.int32)
        self.group_base_t = np.ascontiguousarray(base.T)  # (points, groups)
        self.group_wide = 255 * wide.sum(axis=1, dtype=np.int32)
        s = np.arange(steps, dtype=np.int32) << top
        offset = (s[:, None] * self.width + s[None, :]).ravel()
        idx = base[:, None, :] + offset[None, :, None]  # (groups, steps^2, points)
        sums = np.take(self.group_grids[top], idx).sum(axis=2, dtype=np.int32)
        sums += self.group_wide[:, None]
        ok = self.score(sums) > min_score
        return np.repeat(ok, _GROUP, axis=0)[:num].ravel()

    def group_bound(self, depth: int, a: I64, sx: I64, sy: I64, best: float) -> NDArray[np.bool_]:
        """Which candidates at `depth` (below the top) can score above `best`, bounded as
        `groups` does, once for each heading group and block they share (a level's
        survivors come ~8 headings to a block)."""
        steps = self.lattice(depth)
        key = (a // _GROUP * steps + sy) * steps + sx
        keys, which = np.unique(key, return_inverse=True)  # sorted: group-major
        g, ky, kx = keys // (steps * steps), keys // steps % steps, keys % steps
        idx = np.repeat(self.group_base_t, np.bincount(g, minlength=self.group_base_t.shape[1]), axis=1)  # fmt: skip
        idx += ((ky * self.width + kx) << depth).astype(np.int32)
        sums = (
            np.take(self.group_grids[depth], idx).sum(axis=0, dtype=np.int32) + self.group_wide[g]
        )
        return (self.score(sums) > best)[which.reshape(-1)]

    def score(self, sums: NDArray[np.integer]) -> F64:
        """Scores (mean probability) of summed grid values."""
        return MIN_PROBABILITY + sums / self.num_points * (_SPAN / 255.0)

    def sums(self, depth: int, a: I64, sx: I64, sy: I64) -> I32:
        """Summed grid values of candidates at one level, `a` sorted (as every level's
        candidates are: a heading's points are repeated for its run of candidates)."""
        grid, base = self.grids[depth], self.base_t
        offset = ((sy * self.width + sx) << depth).astype(np.int32)
        sums = np.empty(len(a), np.int32)
        batch = max(1, _LOOKUPS // self.num_points)
        for j in range(0, len(a), batch):
            s = slice(j, j + batch)
            idx = np.repeat(base, np.bincount(a[s], minlength=len(self.base)), axis=1)
            idx += offset[s]
            sums[s] = np.take(grid, idx).sum(axis=0, dtype=np.int32)
        return sums

    def scores(self, depth: int, a: I64, sx: I64, sy: I64) -> F64:
        """Scores of a few candidates in any order (the dive's) at one level."""
        grid = self.grids[depth]
        offset = ((sy * self.width + sx) << depth).astype(np.int32)[:, None]
        sums = np.empty(len(a), np.int32)
        batch = max(1, _LOOKUPS // self.num_points)
        for k in range(0, len(a), batch):
            s = slice(k, k + batch)
            idx = np.take(self.base, a[s], axis=0)
            idx += offset[s]
            sums[s] = np.take(grid, idx).sum(axis=1, dtype=np.int32)
        return self.score(sums)


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
