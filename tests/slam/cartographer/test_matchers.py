"""The real-time correlative matcher's bounded search finds what scoring every candidate finds."""

from __future__ import annotations

import numpy as np
import pytest

from btnav.slam.cartographer import matchers as cm
from btnav.slam.cartographer.options import RealTimeCorrelativeScanMatcher
from btnav.slam.cartographer.submaps import MAX_VALUE, Lattice, Submap

RES = 0.05


def _submap(rng: np.random.Generator) -> Submap:
    """Walls (high values) over noise and unknown cells (0)."""
    s = Submap(0, np.zeros(3), Lattice(RES, 0.0, 0.0))
    values = rng.integers(0, MAX_VALUE // 2, (140, 160)).astype(np.uint16)
    values[rng.random(values.shape) < 0.3] = 0
    for _ in range(8):
        r, c = rng.integers(0, 140), rng.integers(0, 160)
        values[r, c : c + 50] = MAX_VALUE - rng.integers(0, 3000)
        values[r : r + 50, c] = MAX_VALUE - rng.integers(0, 3000)
    s.values, s.row0, s.col0 = values, -20, 10
    return s


def _scan(rng: np.random.Generator, submap: Submap, pose: np.ndarray, n: int) -> np.ndarray:
    """n wall cells of the submap (values above 3/4), seen from `pose`, in its frame."""
    rows, cols = np.nonzero(submap.values > 3 * MAX_VALUE // 4)
    pick = rng.choice(len(rows), n, replace=False)
    xy = submap.lattice.centres(rows[pick] + submap.row0, cols[pick] + submap.col0) - pose[:2]
    s, c = np.sin(pose[2]), np.cos(pose[2])
    return np.column_stack([c * xy[:, 0] + s * xy[:, 1], -s * xy[:, 0] + c * xy[:, 1]])


def _every_candidate(submap, points, prediction, options):
    """The real-time matcher's answer by scoring every (heading, row, column)."""
    angles = cm._headings(float(prediction[2]), options.angular_search_window, cm.angular_step(points, RES))  # fmt: skip
    n = round(options.linear_search_window / RES)
    rows, cols = cm._point_cells(submap, points, prediction[:2], angles)
    size = 2 * n + 1
    grid, r0, c0 = submap.scoring(max(size, 4))
    # a point's window is moved into the grid whole (beyond the border every cell is 0.1)
    top = np.clip(rows - n - r0, 0, grid.shape[0] - size)
    left = np.clip(cols - n - c0, 0, grid.shape[1] - size)
    d = np.arange(-n, n + 1)
    r = top[:, None, None, :] + (d + n)[None, :, None, None]
    c = left[:, None, None, :] + (d + n)[None, None, :, None]
    score = cm._mean_probability(grid[r, c].sum(axis=-1, dtype=np.int64), len(points))
    offsets = d * RES
    cost = (
        cm.fmath.hypot(offsets[:, None], offsets[None, :])[None] * options.translation_delta_cost_weight
        + np.abs(angles - prediction[2])[:, None, None] * options.rotation_delta_cost_weight
    )  # fmt: skip
    score = score * cm.fmath.exp(-(cost * cost))
    a, i, j = np.unravel_index(int(np.argmax(score)), score.shape)
    return np.array([prediction[0] + offsets[j], prediction[1] + offsets[i], angles[a]]), float(score[a, i, j])  # fmt: skip


@pytest.mark.parametrize("seed", range(16))
def test_the_bounded_search_finds_the_exhaustive_best(seed, monkeypatch):
    """Scans of the submap's walls from near the prediction (blocks of headings far off
    score low and are ruled out by their bounds), and random points (few are); windows
    of one block (Cartographer's 0.1 m) and of several (btnav's rescue search)."""
    rng = np.random.default_rng(seed)
    submap = _submap(rng)
    pose = np.array([(10 + rng.uniform(60, 100)) * RES, (-20 + rng.uniform(50, 90)) * RES, rng.uniform(-3, 3)])  # fmt: skip
    n = int(rng.integers(30, 120))
    walls = seed % 8 not in (0, 5)
    points = _scan(rng, submap, pose, n) if walls else rng.uniform(-3.0, 3.0, (n, 2))
    prediction = pose + rng.normal(0.0, [0.03, 0.03, 0.05])
    options = RealTimeCorrelativeScanMatcher(
        linear_search_window=[0.1, 0.5, 0.2, 0.05][seed % 4],
        angular_search_window=0.35,
        translation_delta_cost_weight=0.1,
        rotation_delta_cost_weight=float(rng.choice([0.1, 1.0])),
    )
    scored = []  # offsets scored
    blocks = cm._score_blocks
    monkeypatch.setattr(cm, "_score_blocks", lambda *a: scored.append(a[3].size * a[4].shape[1]) or blocks(*a))  # fmt: skip
    bounded = cm.real_time_correlative_match(submap, points, prediction, options)
    every = _every_candidate(submap, points, prediction, options)
    assert np.array_equal(bounded[0], every[0]) and bounded[1] == every[1]
    if walls:  # most offsets never scored
        headings = len(cm._headings(0.0, 0.35, cm.angular_step(points, RES)))
        assert sum(scored) < headings * (2 * round(options.linear_search_window / RES) + 1) ** 2 / 2


def test_window_maxima_by_doubling_are_every_windows_maximum():
    rng = np.random.default_rng(0)
    grid = rng.integers(0, 1000, (30, 37)).astype(np.uint16)
    for size in (1, 2, 3, 5, 8, 9, 17):
        expected = [[grid[i : i + size, j : j + size].max() for j in range(38 - size)] for i in range(31 - size)]  # fmt: skip
        assert np.array_equal(cm._window_max(grid, size), expected)
