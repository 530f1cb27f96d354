"""Dubins curves judged by geometry: every word ends on the goal pose, the shortest is no
shorter than the straight line, and no curve turns tighter than its radius."""

import numpy as np
import pytest

from btnav.core.geometry import angle_diff
from btnav.planning.dubins import WORDS, all_words, shortest_path


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


def test_shortest_is_no_shorter_than_the_straight_line_and_no_longer_than_any_word() -> None:
    for start, goal in _poses(1, 300):
        best = shortest_path(start, goal, 0.8)
        assert best.length >= np.hypot(goal[0] - start[0], goal[1] - start[1]) - 1e-9
        assert all(best.length <= p.length for p in all_words(start, goal, 0.8).values())


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
