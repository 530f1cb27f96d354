"""Dubins curves judged by geometry: every word ends on the goal pose, the shortest is no
shorter than the straight line nor longer than a brute-force search's path, and no curve
turns tighter than its radius."""

from __future__ import annotations

import numpy as np
import pytest

from btnav.core.geometry import TWO_PI, angle_diff, compose_arrays
from btnav.planning.dubins import WORDS, all_words, shortest_path


def lattice_paths(
    turning_radius: float, headings: int, cell: float, half_width: float, reverse: bool
) -> tuple[np.ndarray, np.ndarray]:
    """The exact end poses (x, y, yaw) and lengths of paths found without any formula: a
    breadth-first search from the origin whose moves are arcs of 2 pi / `headings` at the
    turning radius and straights as long (so breadth-first is shortest-first), left,
    right and straight, forward (and back if `reverse`). A move into a (x, y, heading) cell
    already reached is dropped; the first path into a cell keeps its exact end pose, so each
    end is reached by its path exactly and its shortest curve can be no longer."""
    turn = TWO_PI / headings
    step = turning_radius * turn
    moves = [(bend, gear) for gear in ((1, -1) if reverse else (1,)) for bend in (1, 0, -1)]
    n = round(2.0 * half_width / cell)
    seen = np.zeros((n, n, headings), bool)
    seen[n // 2, n // 2, 0] = True
    x, y, k = np.zeros(1), np.zeros(1), np.zeros(1, np.int64)
    ends, lengths = [np.zeros((1, 3))], [np.zeros(1)]
    layer = 0
    while x.size:
        layer += 1
        sin, cos = np.sin(k * turn), np.cos(k * turn)
        xs, ys, ks = [], [], []
        for bend, gear in moves:
            if bend == 0:
                xs.append(x + gear * step * cos)
                ys.append(y + gear * step * sin)
                ks.append(k)
            else:
                k_next = (k + bend * gear) % headings
                xs.append(x + bend * turning_radius * (np.sin(k_next * turn) - sin))
                ys.append(y - bend * turning_radius * (np.cos(k_next * turn) - cos))
                ks.append(k_next)
        x, y, k = np.concatenate(xs), np.concatenate(ys), np.concatenate(ks)
        i = np.floor((x + half_width) / cell).astype(np.int64)
        j = np.floor((y + half_width) / cell).astype(np.int64)
        keep = (i >= 0) & (i < n) & (j >= 0) & (j < n)
        keep[keep] = ~seen[i[keep], j[keep], k[keep]]
        _, first = np.unique(((i * n + j) * headings + k)[keep], return_index=True)
        pick = np.flatnonzero(keep)[first]
        x, y, k = x[pick], y[pick], k[pick]
        seen[i[pick], j[pick], k] = True
        ends.append(np.column_stack([x, y, k * turn]))
        lengths.append(np.full(x.size, layer * step))
    return np.vstack(ends), np.concatenate(lengths)


def _poses(seed: int, n: int):
    rng = np.random.default_rng(seed)
    for _ in range(n):
        yield tuple(rng.uniform(-5, 5, 3)), tuple(rng.uniform(-5, 5, 3))


def test_every_word_reaches_its_goal() -> None:
    seen = set()
    for start, goal in _poses(0, 300):
        for word, path in all_words(start, goal, 1.3).items():
            end = path.sample(start, 0.05)[-1]
            assert np.hypot(end[0] - goal[0], end[1] - goal[1]) < 1e-6, word
            assert abs(angle_diff(end[2], goal[2])) < 1e-6, word
            seen.add(word)
    assert seen == set(WORDS)


def test_shortest_is_no_shorter_than_the_straight_line() -> None:
    for start, goal in _poses(1, 300):
        best = shortest_path(start, goal, 0.8)
        assert best.length >= np.hypot(goal[0] - start[0], goal[1] - start[1]) - 1e-9


def test_shortest_is_no_longer_than_a_brute_force_search() -> None:
    # 32 headings, 0.05 m cells in a 6 m square, radius 1 m: ~370 000 cells, each the
    # exact end of a forward lattice path; 1500 of them, seen from a start off the origin.
    # The slack is rounding only (1e-9 m): a lattice path ends on its goal exactly.
    ends, lengths = lattice_paths(1.0, 32, 0.05, 3.0, reverse=False)
    pick = np.random.default_rng(2).choice(len(ends), 1500, replace=False)
    start = np.array([0.7, -1.2, 2.0])
    goals = compose_arrays(start, ends[pick])
    best = np.array([shortest_path(tuple(start), tuple(g), 1.0).length for g in goals])
    assert np.all(best <= lengths[pick] + 1e-9)
    # and the search is fine enough to mean something: its paths are near the optimum
    assert np.median((lengths[pick] - best) / np.maximum(lengths[pick], 1e-9)) < 0.06


def test_path_never_curves_tighter_than_the_turning_radius() -> None:
    start, goal = (0.0, 0.0, 0.0), (0.5, 0.0, np.pi)
    poses = shortest_path(start, goal, 1.0).sample(start, 0.01)
    step = np.hypot(np.diff(poses[:, 0]), np.diff(poses[:, 1]))
    turn = np.abs(np.diff(poses[:, 2]))
    moving = step > 1e-9
    assert np.all(turn[moving] / step[moving] <= 1.0 + 1e-4)  # chord vs arc: 4e-6


@pytest.mark.parametrize("heading", [0.0, np.pi / 2])
def test_a_goal_straight_ahead_is_a_straight_line(heading: float) -> None:
    start = (1.0, 2.0, heading)
    goal = (1.0 + 3.0 * np.cos(heading), 2.0 + 3.0 * np.sin(heading), heading)
    best = shortest_path(start, goal, 0.5)
    assert best.length == pytest.approx(3.0, abs=1e-9)
