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
- The bound starts at `min_score`, is raised by a beam dive (the best few coarse
  candidates carried down level by level to single cells), then every level's
  survivors (bound above the best score so far) are expanded together.
- Scoring: a point's lookup is one flat index, row part plus column part. When a
  level has many candidates, both parts are tabulated once per search for every
  heading, point and lattice step (clipped into the grid's zero border), so a
  candidate's indices are two row copies and an add; few candidates compute theirs
  directly. Lookups go in batches that stay in cache; indices are int32.
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
        self.levels = [level]
        for d in range(branch_and_bound_depth - 1):
            w = 1 << d
            p = np.pad(level, ((0, w), (0, w)))
            level = np.maximum(
                np.maximum(p[:-w, :-w], p[:-w, w:]), np.maximum(p[w:, :-w], p[w:, w:])
            )
            self.levels.append(level)

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
        search = _Search(self, rows.astype(np.int32), cols.astype(np.int32), n)
        top = len(self.levels) - 1
        steps = np.arange(search.lattice(top))
        a, sy, sx = (g.ravel() for g in np.meshgrid(np.arange(len(angles)), steps, steps, indexing="ij"))  # fmt: skip
        score = search.scores(top, a, sx, sy)
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
            score = search.scores(depth - 1, a, sx, sy)
        if len(a):
            k = int(np.argmax(score))
            best, best_score = (int(a[k]), int(sx[k]), int(sy[k])), float(score[k])
        if best is None:
            return None
        pose = np.array([initial[0] + (best[1] - n) * res, initial[1] + (best[2] - n) * res, angles[best[0]]])  # fmt: skip
        return pose, best_score


class _Search:
    """One search's points (cells per heading) and its scoring over the level grids."""

    def __init__(self, matcher: FastCorrelativeScanMatcher, rows: I32, cols: I32, n: int) -> None:
        self.m = matcher
        self.rows, self.cols, self.n = rows, cols, n
        self.num_points = rows.shape[1]
        self.tables: dict[int, tuple[I32, I32, int]] = {}

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

    def scores(self, depth: int, a: I64, sx: I64, sy: I64) -> F64:
        """Scores of candidates (heading, lattice steps) at one level."""
        grid = self.m.levels[depth].reshape(-1)
        tables = self.tables.get(depth)
        if tables is None and 2 * len(a) >= len(self.rows) * self.lattice(depth):
            tables = self.tables[depth] = self._tables(depth)
        sums = np.empty(len(a), np.int64)
        batch = max(1, _LOOKUPS // self.num_points)
        for k in range(0, len(a), batch):
            s = slice(k, k + batch)
            if tables is not None:
                row = a[s] * tables[2]
                idx = np.take(tables[0], row + sy[s], axis=0)
                idx += np.take(tables[1], row + sx[s], axis=0)
            else:
                idx = self._indices(depth, a[s], sx[s], sy[s])
            sums[s] = np.take(grid, idx).sum(axis=1, dtype=np.int32)
        return MIN_PROBABILITY + sums / self.num_points * (_SPAN / 255.0)

    def _tables(self, depth: int) -> tuple[I32, I32, int]:
        """Row parts (times the grid's width) and column parts of the flat indices at one
        level, clipped into the grid's zero border: (headings x lattice steps, points)
        each, row heading * steps + step; and the steps."""
        h, w = self.m.levels[depth].shape
        offsets = (np.arange(self.lattice(depth), dtype=np.int32) << depth) - self.n
        r = self.rows[:, None, :] + (offsets - self.m.row0)[None, :, None]
        np.clip(r, 0, h - 1, out=r)
        r *= w
        c = self.cols[:, None, :] + (offsets - self.m.col0)[None, :, None]
        np.clip(c, 0, w - 1, out=c)
        k = len(offsets)
        return r.reshape(-1, self.num_points), c.reshape(-1, self.num_points), k

    def _indices(self, depth: int, a: I64, sx: I64, sy: I64) -> I32:
        """(candidates, points) flat indices, computed directly (few candidates)."""
        h, w = self.m.levels[depth].shape
        dy = ((sy << depth) - self.n - self.m.row0).astype(np.int32)
        dx = ((sx << depth) - self.n - self.m.col0).astype(np.int32)
        r = self.rows[a] + dy[:, None]
        np.clip(r, 0, h - 1, out=r)
        r *= w
        c = self.cols[a] + dx[:, None]
        np.clip(c, 0, w - 1, out=c)
        r += c
        return r
