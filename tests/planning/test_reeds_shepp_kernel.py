"""The compiled Reeds-Shepp and Dubins words are reeds_shepp.py's and dubins.py's, bit for
bit: every word's lengths, the shortest word and the sampled poses."""

from __future__ import annotations

import math

import numpy as np
import pytest

from btnav.planning import dubins, dubins_kernel, reeds_shepp, reeds_shepp_kernel

CURVES = [(reeds_shepp, reeds_shepp_kernel), (dubins, dubins_kernel)]
HALF_PI = math.pi / 2


def queries(seed: int, n: int) -> list[tuple[tuple, tuple, float]]:
    """Random poses and radii, the search's own kind (cell-centre poses, binned yaws) and
    degenerate ones: the same pose, goals straight ahead and behind, on the start's
    circles, headings on multiples of pi/2."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n):
        s, g = rng.uniform(-5, 5, 3).tolist(), rng.uniform(-5, 5, 3).tolist()
        out.append((tuple(s), tuple(g), float(rng.uniform(0.2, 3.0))))
    bins = 2 * math.pi / 72
    for _ in range(n // 2):
        s = (*(rng.integers(0, 40, 2) + 0.5).tolist(), int(rng.integers(0, 72)) * bins)
        g = (*rng.uniform(0, 40, 2).tolist(), float(rng.uniform(-math.pi, math.pi)))
        out.append((s, g, 28.0))
    starts = [(0.0, 0.0, 0.0), (1.0, 2.0, HALF_PI), (-0.5, 0.25, -math.pi), (0.0, 0.0, -0.0)]
    ends = [
        (0.0, 0.0, 0.0), (2.0, 0.0, 0.0), (-2.0, 0.0, 0.0), (0.0, 2.0, math.pi),
        (1.0, 1.0, HALF_PI), (0.0, 0.0, math.pi), (0.0, 4.0, 0.0), (2.0, 2.0, -HALF_PI),
        (4.0, 0.0, math.pi), (0.0, -2.0, -math.pi), (1e-12, 0.0, 1e-12), (3.0, 1e-15, 0.0),
    ]  # fmt: skip
    for s in starts:
        for g in ends:
            for r in (1.0, 0.5, 2.0):
                out.append((s, (s[0] + g[0], s[1] + g[1], g[2]), r))
    return out


def words_bytes(paths: dict) -> dict[str, bytes]:
    return {w: np.array(p.lengths, np.float64).tobytes() for w, p in paths.items()}


@pytest.mark.parametrize(("reference", "kernel"), CURVES, ids=["reeds_shepp", "dubins"])
def test_every_word_has_the_references_bits(reference, kernel):
    for start, goal, r in queries(0, 2000):
        want = reference.all_words(start, goal, r)
        got = kernel.all_words(start, goal, r)
        assert list(got) == list(want), (start, goal, r)
        assert words_bytes(got) == words_bytes(want), (start, goal, r)
        short, ref = kernel.shortest_path(start, goal, r), reference.shortest_path(start, goal, r)
        assert short.word == ref.word and short.lengths == ref.lengths
        assert np.array(short.lengths).tobytes() == np.array(ref.lengths).tobytes()


@pytest.mark.parametrize(("reference", "kernel"), CURVES, ids=["reeds_shepp", "dubins"])
def test_sampled_poses_have_the_references_bits(reference, kernel):
    for start, goal, r in queries(1, 150):
        want = reference.all_words(start, goal, r)
        for word, path in kernel.all_words(start, goal, r).items():
            for step in (math.sqrt(2.0), 0.05, 0.37):
                a, b = want[word].sample(start, step), path.sample(start, step)
                assert a.shape == b.shape and a.tobytes() == b.tobytes(), (word, start, goal)
