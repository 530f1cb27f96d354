"""The loop-closure search's branch and bound finds the exhaustive search's best candidate."""

from __future__ import annotations

import math

import numpy as np
import pytest

from btnav.slam.cartographer.fast_correlative_matcher import (
    FastCorrelativeScanMatcher,
    _Batch,
    match_batch,
)
from btnav.slam.cartographer.matchers import _SPAN, _headings, _point_cells, angular_step
from btnav.slam.cartographer.submaps import MAX_VALUE, MIN_PROBABILITY, Lattice, Submap

RES = 0.05


def _submap(rng: np.random.Generator, shape: tuple[int, int]) -> Submap:
    """Walls (high values) over noise and unknown cells (0), as a finished submap."""
    s = Submap(0, np.zeros(3), Lattice(RES, 0.0, 0.0))
    values = rng.integers(0, MAX_VALUE // 3, shape).astype(np.uint16)
    values[rng.random(shape) < 0.3] = 0
    for _ in range(6):
        r, c = rng.integers(0, shape[0]), rng.integers(0, shape[1])
        values[r, c : c + 40] = MAX_VALUE
        values[r : r + 40, c] = MAX_VALUE - rng.integers(0, 5000)
    s.values, s.row0, s.col0 = values, -7, 5
    s.finished = True
    return s


def _exhaustive(m: FastCorrelativeScanMatcher, level0: np.ndarray, points, initial, lw, aw):
    """Every candidate's score at single cells, lookups clipped into the grid: (scores
    (headings, dy, dx), n, angles)."""
    angles = _headings(float(initial[2]), aw, angular_step(points, RES))
    rows, cols = _point_cells(m.submap, points, initial[:2], angles)
    n = math.ceil(lw / RES)
    h, w = level0.shape
    d = np.arange(-n, n + 1)
    r = np.clip(rows[:, None, None, :] + d[None, :, None, None] - m.row0, 0, h - 1)
    c = np.clip(cols[:, None, None, :] + d[None, None, :, None] - m.col0, 0, w - 1)
    sums = level0[r, c].sum(axis=-1, dtype=np.int64)
    return MIN_PROBABILITY + sums / len(points) * (_SPAN / 255.0), n, angles


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("depth", [4, 6])  # headings one by one from the bottom, from 3
def test_branch_and_bound_finds_the_exhaustive_best(seed, depth):
    rng = np.random.default_rng(seed)
    submap = _submap(rng, (120, 150))
    m = FastCorrelativeScanMatcher(submap, depth)
    level0 = m.levels[0].copy()
    points = rng.uniform(-2.5, 2.5, (int(rng.integers(20, 60)), 2))
    # near the grid's middle, and half off its edge (clipped lookups, the margins)
    centre = np.array([submap.col0 * RES + rng.uniform(0, 7.5), submap.row0 * RES + rng.uniform(0, 6.0)])  # fmt: skip
    initial = np.array([*centre, rng.uniform(-math.pi, math.pi)])
    scores, n, angles = _exhaustive(m, level0, points, initial, 0.5, 0.15)
    best = float(scores.max())
    found = m.match(points, initial, 0.5, 0.15, min_score=0.2)
    assert found is not None and found[1] == best
    pose = found[0]
    a = int(np.flatnonzero(angles == pose[2])[0])
    dx, dy = round((pose[0] - initial[0]) / RES) + n, round((pose[1] - initial[1]) / RES) + n
    assert scores[a, dy, dx] == best
    # nothing above the bound: none; a second search of the same submap agrees
    assert m.match(points, initial, 0.5, 0.15, min_score=best) is None
    again = m.match(points, initial, 0.5, 0.15, min_score=0.2)
    assert again is not None and again[1] == best and np.array_equal(again[0], pose)


def test_a_search_off_the_submap_finds_nothing():
    rng = np.random.default_rng(7)
    m = FastCorrelativeScanMatcher(_submap(rng, (60, 60)), 3)
    points = rng.uniform(-1.0, 1.0, (30, 2))
    assert m.match(points, np.array([40.0, -30.0, 0.3]), 0.4, 0.1, min_score=0.11) is None


def _batch(seed: int) -> tuple[_Batch, int]:
    """One search of 50 random points over a random 160 x 160 submap, 20 cells wide, as
    a batch of one: (the batch, its top level)."""
    rng = np.random.default_rng(seed)
    submap = _submap(rng, (160, 160))
    m = FastCorrelativeScanMatcher(submap, 4)
    points = rng.uniform(-4.0, 4.0, (50, 2))
    initial = np.array([submap.col0 * RES + 4.0, submap.row0 * RES + 4.0, rng.uniform(-3, 3)])
    return _Batch([(m, points, initial)], 1.0, 0.3), len(m.levels) - 1


def _all(batch: _Batch, depth: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Every candidate of a level: (heading, step x, step y), heading-major."""
    steps = np.arange(batch.lattice(depth))
    a, sy, sx = (g.ravel() for g in np.meshgrid(np.arange(len(batch.search)), steps, steps, indexing="ij"))  # fmt: skip
    return a, sx, sy


@pytest.mark.parametrize("seed", range(6))
def test_a_heading_group_bounds_each_part_of_its_headings_points(seed):
    """What the search by heading group rests on: at every level it runs, a group's
    bound of each part of the points is at least the part's sum at any of its headings
    (the points' parts adding up to all of them)."""
    batch, _ = _batch(seed)
    batch.groups(np.array([0]))
    for depth in sorted(batch.group_grids[0]):
        steps = np.arange(batch.lattice(depth))
        g, sy, sx = (v.ravel() for v in np.meshgrid(np.arange(len(batch.group_need)), steps, steps, indexing="ij"))  # fmt: skip
        a, hx, hy, parent = batch.group_headings(g, sx, sy)
        assert np.array_equal(hx, sx[parent]) and np.array_equal(hy, sy[parent])
        assert np.array_equal(np.sort(a), np.repeat(np.arange(len(batch.search)), len(steps) ** 2))  # fmt: skip
        whole = batch.group_sums(depth, g, sx, sy)
        assert np.array_equal(whole, sum(batch.group_sums(depth, g, sx, sy, k) for k in range(len(batch.parts))))  # fmt: skip
        assert (batch.sums(depth, a, hx, hy) <= whole[parent]).all()
        for k in range(len(batch.parts)):
            assert (batch.sums(depth, a, hx, hy, k) <= batch.group_sums(depth, g, sx, sy, k)[parent]).all()  # fmt: skip


def test_the_winner_is_the_first_in_the_trees_order():
    """`tree_order` of single-cell candidates: heading, the top lattice row by row, then
    each level's sub-blocks (x first, then y), as the tree is walked."""
    batch, top = _batch(30)
    a, sx, sy = _all(batch, top)
    for depth in range(top, 0, -1):  # the tree's leaves in its order
        a, sx, sy, _ = batch.children(depth, a, sx, sy)
    key = batch.tree_order(a, sx, sy)
    assert (np.diff(key) > 0).all()


@pytest.mark.parametrize("seed", range(3))
def test_a_parent_bounds_each_part_of_its_childrens_points(seed):
    """What pruning by parts rests on: at every level, each part of the points sums to
    at least what it sums to at any child below."""
    batch, top = _batch(20 + seed)
    for depth in range(top, 0, -1):
        a, sx, sy = _all(batch, depth)
        ca, cx, cy, parent = batch.children(depth, a, sx, sy)
        for k in range(len(batch.parts)):
            above = batch.sums(depth, a, sx, sy, k)
            below = batch.sums(depth - 1, ca, cx, cy, k)
            assert (below <= above[parent]).all()


@pytest.mark.parametrize("seed", range(3))
def test_a_heading_groups_parent_bounds_each_part_of_its_childrens_points(seed):
    """The same for the heading groups' candidates at the levels searched by group."""
    batch, _ = _batch(40 + seed)
    batch.groups(np.array([0]))
    for depth in sorted(batch.group_grids[0])[1:]:
        steps = np.arange(batch.lattice(depth))
        g, sy, sx = (v.ravel() for v in np.meshgrid(np.arange(len(batch.group_need)), steps, steps, indexing="ij"))  # fmt: skip
        cg, cx, cy, parent = batch.children(depth, g, sx, sy)
        for k in range(len(batch.parts)):
            above = batch.group_sums(depth, g, sx, sy, k)
            below = batch.group_sums(depth - 1, cg, cx, cy, k)
            assert (below <= above[parent]).all()


def test_searches_together_find_what_each_finds_alone():
    """A batch of searches over three submaps, points of different counts (a search
    with fewer points reads 0 for the rest), gives each search's own answer."""
    rng = np.random.default_rng(3)
    matchers = [FastCorrelativeScanMatcher(_submap(rng, (120, 150)), 4) for _ in range(3)]
    queries = []
    for k in range(9):
        m = matchers[k % 3]
        points = rng.uniform(-2.5, 2.5, (int(rng.integers(20, 60)), 2))
        centre = [m.submap.col0 * RES + rng.uniform(0, 7.5), m.submap.row0 * RES + rng.uniform(0, 6.0)]  # fmt: skip
        queries.append((m, points, np.array([*centre, rng.uniform(-math.pi, math.pi)])))
    queries.append((matchers[0], np.zeros((0, 2)), np.zeros(3)))  # no points: nothing
    together = match_batch(queries, 0.5, 0.15, 0.2)
    alone = [m.match(p, i, 0.5, 0.15, 0.2) for m, p, i in queries]
    assert together[-1] is None and sum(f is not None for f in alone) >= 5
    for t, s in zip(together, alone, strict=True):
        assert (t is None and s is None) or (np.array_equal(t[0], s[0]) and t[1] == s[1])
