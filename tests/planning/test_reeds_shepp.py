"""Reeds-Shepp curves judged by geometry: every word ends on the goal pose, the shortest is
no longer than a brute-force search's path nor than the Dubins curve, it is as long either
way round, and no curve turns tighter than its radius."""

from __future__ import annotations

import numpy as np
import pytest

from btnav.core.geometry import angle_diff, compose_arrays
from btnav.planning import dubins
from btnav.planning.reeds_shepp import WORDS, all_words, shortest_path

from .test_dubins import lattice_paths


def _poses(seed: int, n: int):
    rng = np.random.default_rng(seed)
    for _ in range(n):
        yield tuple(rng.uniform(-5, 5, 3)), tuple(rng.uniform(-5, 5, 3))


def test_every_word_occurs_and_reaches_its_goal() -> None:
    seen = set()
    for start, goal in _poses(0, 300):
        for word, path in all_words(start, goal, 1.3).items():
            end = path.sample(start, 0.05)[-1]
            assert np.hypot(end[0] - goal[0], end[1] - goal[1]) < 1e-6, word
            assert abs(angle_diff(end[2], goal[2])) < 1e-6, word
            gears = ["+" if v > 0 else "-" if v < 0 else "0" for v in path.lengths]
            assert all(g in (w, "0") for g, w in zip(gears, word[1::2], strict=True)), word
            seen.add(word)
    assert len(WORDS) == 48
    assert seen == set(WORDS)


def test_shortest_is_no_longer_than_a_brute_force_search() -> None:
    # 32 headings, 0.065 m cells in an 7.8 m square, radius 1.3 m, forward and reverse:
    # ~460 000 cells, each the exact end of a lattice path; 1500 of them, seen from a start
    # off the origin. The slack is rounding only (1e-9 m): a lattice path ends on its goal.
    ends, lengths = lattice_paths(1.3, 32, 0.065, 3.9, reverse=True)
    pick = np.random.default_rng(3).choice(len(ends), 1500, replace=False)
    start = np.array([-2.0, 0.4, -2.5])
    goals = compose_arrays(start, ends[pick])
    best = np.array([shortest_path(tuple(start), tuple(g), 1.3).length for g in goals])
    assert np.all(best <= lengths[pick] + 1e-9)
    # and the search is fine enough to mean something: its paths are near the optimum
    assert np.median((lengths[pick] - best) / np.maximum(lengths[pick], 1e-9)) < 0.06


def test_reversing_never_makes_it_longer_than_dubins() -> None:
    for start, goal in _poses(1, 300):
        forward = dubins.shortest_path(start, goal, 0.8).length
        assert shortest_path(start, goal, 0.8).length <= forward + 1e-9


def test_the_way_back_is_as_long() -> None:
    """A path driven in reverse order and gear goes from the goal to the start."""
    for start, goal in _poses(2, 300):
        there = shortest_path(start, goal, 1.1).length
        assert shortest_path(goal, start, 1.1).length == pytest.approx(there, abs=1e-9)


def test_no_curve_turns_tighter_than_its_radius() -> None:
    for start, goal in _poses(3, 20):
        for word, path in all_words(start, goal, 0.7).items():
            poses = path.sample(start, 0.01)
            step = np.hypot(np.diff(poses[:, 0]), np.diff(poses[:, 1]))
            turn = np.abs(np.diff(poses[:, 2]))
            assert np.all(step <= 0.01 + 1e-12), word
            assert np.all(turn <= step / 0.7 * (1.0 + 1e-4) + 1e-12), word  # chord vs arc: 9e-6
            # the chords add up to the length, short by at most the same chord-vs-arc factor
            assert step.sum() == pytest.approx(path.length, rel=1e-4), word


@pytest.mark.parametrize("heading", [0.0, np.pi / 2, -2.0])
def test_a_goal_straight_behind_is_one_straight_reverse(heading: float) -> None:
    start = (1.0, 2.0, heading)
    goal = (1.0 - 3.0 * np.cos(heading), 2.0 - 3.0 * np.sin(heading), heading)
    best = shortest_path(start, goal, 0.5)
    moves = [
        (kind, seg)
        for kind, seg in zip(best.segments, best.lengths, strict=True)
        if abs(seg) > 1e-9
    ]
    assert [kind for kind, _ in moves] == ["S"]
    assert moves[0][1] == pytest.approx(-3.0, abs=1e-9)
    assert best.length == pytest.approx(3.0, abs=1e-9)
    assert np.all(best.sample(start, 0.1)[:, 2] == heading)
