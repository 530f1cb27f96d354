"""Reeds-Shepp words solved in a numba kernel, with reeds_shepp.py's bits.

Hybrid-A*'s analytic expansion asks for a shortest Reeds-Shepp path a few hundred times
a plan; reeds_shepp.py solves the nine forms for the eight mirrored goals as small numpy
arrays, ~0.8 ms a call in fmath's pure-Python scalar steps (half of the racecar's
two-doorway plan). Here the same forms are solved goal by goal in compiled code with
core.fmath_kernels (fmath's steps, the same bits), so a call is a few microseconds.

The same bits as reeds_shepp.py, word by word (tests/planning/test_reeds_shepp_kernel.py
compares every word's lengths on random and degenerate queries): each form computes the
same IEEE operations in the same order; numpy's pieces are written out as they compute
(`np.mod` as numpy's remainder, `np.clip` and `np.maximum(v, 0)` with their NaN and
signed-zero results, a sum over a word's segments first to last); the mirrors, the
words they name, the gears and the shortest-first bookkeeping are reeds_shepp.py's own
tables. reeds_shepp.py stays the reference and the documentation of the forms; the
`ReedsSheppPath` made here is that module's class.
"""

from __future__ import annotations

import math
from typing import Any

import numba as nb
import numpy as np

from ..core.fmath_kernels import JIT, arctan2, remainder, sincos, sincos_steps
from . import reeds_shepp as rs

_PI = math.pi
_TWO_PI = 2.0 * math.pi
_HALF_PI = rs._HALF_PI
_TOL = rs._TOL
#: The most segments a word has.
MAX_SEGMENTS = 5

#: The forms, in reeds_shepp._FAMILIES' order of first use (L+R-L serves two words).
_FORMS = tuple(dict.fromkeys(form for _, form in rs._FAMILIES))
assert [f.__name__ for f in _FORMS] == [
    "_lsl", "_lsr", "_lrl", "_lrlr_u", "_lrlr_uu", "_lrsl", "_lrsr", "_lrslr"
], "_solve numbers the forms in this order"  # fmt: skip
#: Per family: its form's index, its gears (+1 / -1, padded with 0), its segments.
_FAMILY_FORM = np.array([_FORMS.index(form) for _, form in rs._FAMILIES], np.int64)
_FAMILY_GEARS = np.zeros((len(rs._FAMILIES), MAX_SEGMENTS))
for _f, _gears in enumerate(rs._GEARS):
    _FAMILY_GEARS[_f, : len(_gears)] = _gears[:, 0]
_FAMILY_SEGMENTS = np.array([len(g) for g in rs._GEARS], np.int64)
#: Per family and mirror, the index in WORDS of the word its solution goes by.
_FAMILY_WORD = np.array([[rs.WORDS.index(n) for n in names] for names in rs._NAMES], np.int64)
_MIRROR_FLAGS = np.array(rs._MIRRORS, np.bool_)  # (run backwards, time flipped, reflected)
_N_FORMS = len(_FORMS)


# -- numpy's and geometry's pieces, as they compute ---------------------------------------


@nb.njit(**JIT)
def normalize_angle(a: float) -> float:
    """geometry.normalize_angle on a float64 array element: kept when in (-pi, pi], else
    np.mod(a + pi, 2 pi) - pi, moved up a turn at -pi."""
    if -_PI < a <= _PI:
        return a
    out = remainder(a + _PI, _TWO_PI) - _PI
    if out <= -_PI:
        out += _TWO_PI
    return out


@nb.njit(**JIT)
def clip_unit(v: float) -> float:
    """np.clip(v, -1, 1) (NaN stays NaN)."""
    if v < -1.0:
        return -1.0
    if v > 1.0:
        return 1.0
    return v


@nb.njit(**JIT)
def positive_part(v: float) -> float:
    """np.maximum(v, 0.0): a zero of either sign gives +0 (the second operand), NaN NaN."""
    if v > 0.0 or v != v:
        return v
    return 0.0


@nb.njit(**JIT)
def _asin(h: float) -> float:
    h = clip_unit(h)
    return arctan2(h, math.sqrt(1.0 - h * h))


@nb.njit(**JIT)
def _acos(c: float) -> float:
    c = clip_unit(c)
    return arctan2(math.sqrt(1.0 - c * c), c)


# -- the nine forms (reeds_shepp.py documents each), one mirrored goal at a time ----------


@nb.njit(**JIT)
def _outer_turns(u1: float, u2: float, xi: float, eta: float, phi: float) -> tuple[float, float]:
    s1, c1 = sincos_steps(u1)
    s12, c12 = sincos_steps(u1 - u2)
    a, b = s1 - s12, c1 - c12 - 1.0
    t = normalize_angle(arctan2(a * eta - b * xi, a * xi + b * eta))
    return t, normalize_angle(t - u1 + u2 - phi)


@nb.njit(**JIT)
def _solve(form: int, x: float, y: float, phi: float, s: float, c: float, seg: np.ndarray) -> bool:
    """Form `form` (an index into _FORMS) for one goal: its signed segment lengths into
    `seg`, and whether the construction exists."""
    if form == 0:  # L+S+L+
        a, b = x - s, y - 1.0 + c
        u, t = math.sqrt(a * a + b * b), arctan2(b, a)
        t = 0.0 if u < _TOL else normalize_angle(t)
        seg[0], seg[1], seg[2] = t, u, normalize_angle(phi - t)
        return True
    if form == 1:  # L+S+R+
        a, b = x + s, y - 1.0 - c
        d, theta = math.sqrt(a * a + b * b), arctan2(b, a)
        v = d * d - 4.0
        u = math.sqrt(positive_part(v))
        t = normalize_angle(theta + arctan2(2.0, u))
        seg[0], seg[1], seg[2] = t, u, normalize_angle(t - phi)
        return v >= -_TOL
    if form == 2:  # L+R-L
        a, b = x - s, y - 1.0 + c
        d, theta = math.sqrt(a * a + b * b), arctan2(b, a)
        half = _asin(d / 4.0)
        u = -2.0 * half
        t = normalize_angle(theta - half + _PI)
        seg[0], seg[1], seg[2] = t, u, normalize_angle(phi - t + u)
        return d <= 4.0 + _TOL
    if form == 3:  # L+R+L-R-
        xi, eta = x + s, y - 1.0 - c
        rho = (2.0 + math.sqrt(xi * xi + eta * eta)) / 4.0
        u = _acos(rho)
        t, v = _outer_turns(u, -u, xi, eta, phi)
        seg[0], seg[1], seg[2], seg[3] = t, u, -u, v
        return rho <= 1.0 + _TOL
    if form == 4:  # L+R-L-R+
        xi, eta = x + s, y - 1.0 - c
        rho = (20.0 - xi * xi - eta * eta) / 16.0
        u = -_acos(rho)
        t, v = _outer_turns(u, u, xi, eta, phi)
        seg[0], seg[1], seg[2], seg[3] = t, u, u, v
        return rho >= -_TOL and rho <= 1.0 + _TOL
    if form == 5 or form == 7:  # L+R-S-L-, L+R-S-L-R+
        if form == 5:
            a, b = x - s, y - 1.0 + c
        else:
            a, b = x + s, y - 1.0 - c
        rho, theta = math.sqrt(a * a + b * b), arctan2(b, a)
        v = rho * rho - 4.0
        w = math.sqrt(positive_part(v))
        t = normalize_angle(theta + arctan2(w, -2.0))
        seg[0], seg[1] = t, -_HALF_PI
        if form == 5:
            seg[2], seg[3] = 2.0 - w, normalize_angle(phi - _HALF_PI - t)
        else:
            seg[2], seg[3], seg[4] = 4.0 - w, -_HALF_PI, normalize_angle(t - phi)
        return v >= -_TOL
    # form 6, L+R-S-R-
    xi, eta = x + s, y - 1.0 - c
    a, b = -eta, xi
    rho, t = math.sqrt(a * a + b * b), arctan2(b, a)
    t = normalize_angle(t)
    seg[0], seg[1], seg[2], seg[3] = t, -_HALF_PI, 2.0 - rho, normalize_angle(t + _HALF_PI - phi)
    return True


# -- all words --------------------------------------------------------------------------


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
    """reeds_shepp.all_words: each word's shortest solution's signed lengths (metres)
    into `lengths` (48, MAX_SEGMENTS), `found` whether it has one."""
    # the goal in the start's frame (radius 1) and its mirror images (_mirrored_goals)
    s0, c0 = sincos(syaw)
    dx, dy = gx - sx, gy - sy
    x = (c0 * dx + s0 * dy) / radius
    y = (c0 * dy - s0 * dx) / radius
    phi = normalize_angle(gyaw - syaw)
    s, c = sincos(phi)
    n_forms, n_mirrors = _N_FORMS, _MIRROR_FLAGS.shape[0]
    solved = np.zeros((n_forms, n_mirrors, MAX_SEGMENTS))
    exists = np.zeros((n_forms, n_mirrors), np.bool_)
    for k in range(n_mirrors):
        backwards, time_flipped, reflected = _MIRROR_FLAGS[k]
        xk, yk = (x * c + y * s, x * s - y * c) if backwards else (x, y)
        if time_flipped:
            xk = -xk
        if reflected:
            yk = -yk
        sign = -1.0 if time_flipped != reflected else 1.0
        for form in range(n_forms):
            exists[form, k] = _solve(form, xk, yk, sign * phi, sign * s, c, solved[form, k])
    # each family's solutions with the word's gears, the shortest kept per word
    best = np.full(lengths.shape[0], math.inf)
    found[:] = False
    clean = np.zeros(MAX_SEGMENTS)
    for fam in range(_FAMILY_FORM.shape[0]):
        form, n = _FAMILY_FORM[fam], _FAMILY_SEGMENTS[fam]
        for k in range(n_mirrors):
            ok = exists[form, k]
            total = 0.0
            for j in range(n):
                v = solved[form, k, j]
                gear = _FAMILY_GEARS[fam, j]
                forward = gear * v
                ok = ok and forward >= -_TOL and math.isfinite(v)
                clean[j] = gear * positive_part(forward)
                total = abs(clean[j]) if j == 0 else total + abs(clean[j])
            w = _FAMILY_WORD[fam, k]
            if not ok or (found[w] and not total < best[w]):
                continue
            found[w] = True
            best[w] = total
            backwards, time_flipped, _ = _MIRROR_FLAGS[k]
            for j in range(n):
                v = -clean[j] if time_flipped else clean[j]
                lengths[w, n - 1 - j if backwards else j] = v * radius
            lengths[w, n:] = 0.0


@nb.njit(**JIT)
def shortest_word(lengths: np.ndarray, found: np.ndarray, segments: np.ndarray) -> int:
    """The index of the shortest found word (ties to the first), its length the sum of
    its segments' magnitudes first to last, as ReedsSheppPath.length adds them."""
    best, best_length = -1, math.inf
    for w in range(found.shape[0]):
        if not found[w]:
            continue
        total = 0.0
        for j in range(segments[w]):
            total += abs(lengths[w, j])
        if best < 0 or total < best_length:
            best, best_length = w, total
    return best


#: Each word's number of segments.
_WORD_SEGMENTS = np.array([len(word) // 2 for word in rs.WORDS], np.int64)
#: A segment's letter as sample_segments reads it.
LETTER_CODES = {"L": 0, "R": 1, "S": 2}


# -- sampling -----------------------------------------------------------------------------


@nb.njit(**JIT)
def _linspace(a: float, b: float, n: int, k: int) -> float:
    """Element k of np.linspace(a, b, n), as numpy computes it."""
    div = n - 1
    if div > 0 and k == div:
        return b
    delta = b - a
    if div > 0:
        step = delta / div
        y = (k / div) * delta if step == 0 else k * step
    else:
        y = k * delta
    return y + a


@nb.njit(**JIT)
def _segment_samples(length: float, step: float) -> int:
    return max(1, math.ceil(abs(length) / step))


@nb.njit(**JIT)
def sample_segments(
    x: float,
    y: float,
    yaw: float,
    letters: np.ndarray,
    lengths: np.ndarray,
    radius: float,
    step: float,
    skip_zero: bool,
) -> np.ndarray:
    """ReedsSheppPath.sample (skip_zero) and DubinsPath.sample: poses (x, y, yaw) every
    `step` along the segments, start and end included, by their numpy and fmath steps
    (np.linspace per segment, a turn's poses from its yaws' sines and cosines)."""
    total = 1
    for j in range(lengths.shape[0]):
        if not (skip_zero and lengths[j] == 0.0):
            total += _segment_samples(lengths[j], step)
    out = np.empty((total, 3))
    out[0, 0], out[0, 1], out[0, 2] = x, y, yaw
    row = 1
    for j in range(lengths.shape[0]):
        seg = lengths[j]
        if skip_zero and seg == 0.0:
            continue
        n = _segment_samples(seg, step)
        first = seg / n
        if letters[j] == 2:  # straight
            sn, c = sincos(yaw)
            for k in range(n):
                s = _linspace(first, seg, n, k)
                out[row + k, 0], out[row + k, 1], out[row + k, 2] = x + s * c, y + s * sn, yaw
        else:
            turn = 1.0 if letters[j] == 0 else -1.0
            s0, c0 = sincos(yaw)
            for k in range(n):
                heading = yaw + turn * _linspace(first, seg, n, k) / radius
                sk, ck = sincos_steps(heading)
                out[row + k, 0] = x + turn * radius * (sk - s0)
                out[row + k, 1] = y - turn * radius * (ck - c0)
                out[row + k, 2] = heading
        row += n
        x, y, yaw = out[row - 1, 0], out[row - 1, 1], out[row - 1, 2]
    return out


class ReedsSheppPath(rs.ReedsSheppPath):
    """reeds_shepp.ReedsSheppPath, sampled by the compiled `sample_segments`."""

    def sample(self, start: tuple[float, float, float], step: float) -> np.ndarray:
        letters = np.array([LETTER_CODES[c] for c in self.segments], np.int64)
        return sample_segments(
            float(start[0]), float(start[1]), float(start[2]), letters,
            np.array(self.lengths, np.float64), float(self.turning_radius), float(step), True,
        )  # fmt: skip


def all_words(
    start: tuple[float, float, float], goal: tuple[float, float, float], turning_radius: float
) -> dict[str, ReedsSheppPath]:
    """reeds_shepp.all_words, compiled."""
    lengths, found = solve_all(
        solve_words, len(rs.WORDS), MAX_SEGMENTS, start, goal, turning_radius
    )
    return {word: _path(w, lengths, turning_radius) for w, word in enumerate(rs.WORDS) if found[w]}


def shortest_path(
    start: tuple[float, float, float], goal: tuple[float, float, float], turning_radius: float
) -> ReedsSheppPath:
    """reeds_shepp.shortest_path, compiled."""
    lengths, found = solve_all(
        solve_words, len(rs.WORDS), MAX_SEGMENTS, start, goal, turning_radius
    )
    return _path(shortest_word(lengths, found, _WORD_SEGMENTS), lengths, turning_radius)


def solve_all(
    solve: Any,
    n_words: int,
    width: int,
    start: tuple[float, float, float],
    goal: tuple[float, float, float],
    turning_radius: float,
) -> tuple[np.ndarray, np.ndarray]:
    """Every word's segment lengths (n_words, width) and whether it was found, from a
    compiled `solve_words` (this module's or dubins_kernel's)."""
    lengths = np.zeros((n_words, width))
    found = np.zeros(n_words, np.bool_)
    solve(
        float(start[0]), float(start[1]), float(start[2]),
        float(goal[0]), float(goal[1]), float(goal[2]),
        float(turning_radius), lengths, found,
    )  # fmt: skip
    return lengths, found


def _path(w: int, lengths: np.ndarray, turning_radius: float) -> ReedsSheppPath:
    word = rs.WORDS[w]
    return ReedsSheppPath(word, tuple(lengths[w, : len(word) // 2].tolist()), turning_radius)
