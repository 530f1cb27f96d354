"""Dubins words solved in a numba kernel, with dubins.py's bits.

Nav2's default Hybrid-A* (DUBIN) asks for a shortest Dubins path at every analytic
expansion; dubins.py solves the six words with small numpy arrays and fmath's
pure-Python scalar steps (~0.3 ms a call). Here the same steps run compiled with
core.fmath_kernels, word by word, in the same IEEE order (numpy's `np.mod`,
`np.maximum(v, 0)` and `np.clip` written out as they compute), so each word's three
lengths are dubins.py's bits (tests/planning/test_reeds_shepp_kernel.py). dubins.py stays
the reference and the documentation; the `DubinsPath` made here is its class.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np

from ..core.fmath_kernels import JIT, arctan2, remainder, sincos
from . import dubins
from .reeds_shepp_kernel import (
    LETTER_CODES,
    clip_unit,
    positive_part,
    sample_segments,
    shortest_word,
    solve_all,
)

_TWO_PI = 2.0 * math.pi
_WRAP = _TWO_PI - dubins._TOL
_TOL = dubins._TOL
#: Every Dubins word has three segments (reeds_shepp_kernel.shortest_word reads a count).
_THREE_SEGMENTS = np.full(len(dubins.WORDS), 3, np.int64)


@nb.njit(**JIT)
def _mod2pi(a: float) -> float:
    """dubins._mod2pi: np.mod(a, 2 pi), a hair under 2 pi taken as 0."""
    m = remainder(a, _TWO_PI)
    return 0.0 if m > _WRAP else m


@nb.njit(**JIT)
def solve_words(
    sx: float,
    sy: float,
    syaw: float,
    gx: float,
    gy: float,
    gyaw: float,
    radius: float,
    lengths: np.ndarray,
    found: np.ndarray,
) -> None:
    """dubins.all_words: each of the six words' (t, p, q) in metres into `lengths` (6, 3),
    `found` whether it exists (WORDS' order: LSL, RSR, LSR, RSL, RLR, LRL)."""
    dx, dy = gx - sx, gy - sy
    d = math.sqrt(dx * dx + dy * dy) / radius
    theta = arctan2(dy, dx) if d > 0.0 else 0.0
    a = _mod2pi(syaw - theta)
    b = _mod2pi(gyaw - theta)
    sa, ca = sincos(a)
    sb, cb = sincos(b)
    cab = sincos(a - b)[1]
    # LSL, RSR, LSR, RSL: a straight between two turns
    p_sq = (
        2.0 + d * d - 2.0 * cab + 2.0 * d * (sa - sb),
        2.0 + d * d - 2.0 * cab + 2.0 * d * (sb - sa),
        -2.0 + d * d + 2.0 * cab + 2.0 * d * (sa + sb),
        -2.0 + d * d + 2.0 * cab - 2.0 * d * (sa + sb),
    )
    across = (cb - ca, ca - cb, -ca - cb, ca + cb)
    along = (d + sa - sb, d - sa + sb, d + sa + sb, d - sa - sb)
    tilt = (0.0, 0.0, -2.0, 2.0)  # the cross tangents' (y of atan2)
    sign_a = (-1.0, 1.0, -1.0, 1.0)
    for i in range(4):
        p = math.sqrt(positive_part(p_sq[i]))
        heading = arctan2(across[i], along[i])
        if i >= 2:
            heading -= arctan2(tilt[i], p)
        else:  # the centres' distance; with one circle, the whole turn goes last
            p = math.sqrt(along[i] * along[i] + across[i] * across[i])
            if p < _TOL:
                p, heading = 0.0, a
        t = _mod2pi(sign_a[i] * (a - heading))
        q = _mod2pi(b - heading) if i == 0 or i == 3 else _mod2pi(-b + heading)
        lengths[i, 0], lengths[i, 1], lengths[i, 2] = t * radius, p * radius, q * radius
        found[i] = p_sq[i] >= -_TOL
    # RLR, LRL: three turns, the middle one when the circles are close enough
    for j in range(2):
        i = 4 + j
        cross = 2.0 * d * (sa - sb) if j == 0 else 2.0 * d * (sb - sa)
        cos_mid = (6.0 - d * d + 2.0 * cab + cross) / 8.0
        c = clip_unit(cos_mid)
        p_turn = _mod2pi(_TWO_PI - arctan2(math.sqrt(1.0 - c * c), c))
        first = a if j == 0 else -a
        along_turn = d - sa + sb if j == 0 else d + sa - sb
        t_turn = _mod2pi(first - arctan2(ca - cb, along_turn) + p_turn / 2.0)
        q_turn = _mod2pi((a - b if j == 0 else b - a) - t_turn + p_turn)
        lengths[i, 0], lengths[i, 1], lengths[i, 2] = (
            t_turn * radius, p_turn * radius, q_turn * radius
        )  # fmt: skip
        found[i] = abs(cos_mid) <= 1.0 + _TOL


class DubinsPath(dubins.DubinsPath):
    """dubins.DubinsPath, sampled by the compiled `sample_segments`."""

    def sample(self, start: tuple[float, float, float], step: float) -> np.ndarray:
        letters = np.array([LETTER_CODES[c] for c in self.word], np.int64)
        return sample_segments(
            float(start[0]), float(start[1]), float(start[2]), letters,
            np.array(self.lengths, np.float64), float(self.turning_radius), float(step), False,
        )  # fmt: skip


def all_words(
    start: tuple[float, float, float], goal: tuple[float, float, float], turning_radius: float
) -> dict[str, DubinsPath]:
    """dubins.all_words, compiled."""
    lengths, found = solve_all(solve_words, len(dubins.WORDS), 3, start, goal, turning_radius)
    return {
        word: DubinsPath(word, tuple(lengths[w].tolist()), turning_radius)
        for w, word in enumerate(dubins.WORDS)
        if found[w]
    }


def shortest_path(
    start: tuple[float, float, float], goal: tuple[float, float, float], turning_radius: float
) -> DubinsPath:
    """dubins.shortest_path, compiled."""
    lengths, found = solve_all(solve_words, len(dubins.WORDS), 3, start, goal, turning_radius)
    w = shortest_word(lengths, found, _THREE_SEGMENTS)  # lengths >= 0: abs changes none
    return DubinsPath(dubins.WORDS[w], tuple(lengths[w].tolist()), turning_radius)
