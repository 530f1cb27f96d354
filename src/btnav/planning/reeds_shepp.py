"""Reeds-Shepp curves: the shortest path between two poses for a car that may reverse.

SmacPlannerHybrid's REEDS_SHEPP motion model expands analytically with these curves (Nav2
takes them from OMPL). Reeds & Shepp (1990) name 48 words; nine closed forms, in the
goal's pose seen from the start with the turning radius as unit, give them all once each
form is also solved for the goal's three mirror images (time flipped, reflected, both) and
for the path run backwards. The eight mirrored goals are solved together with numpy, and
each word keeps its shortest solution. Trigonometry goes through core.fmath so a plan is
the same bits on every CPU.

A word such as "L+R-S-L-" reads one letter and gear per segment: L and R turn left and
right at the turning radius, S goes straight, + is forward and - is reverse. Steering left
while reversing turns the car clockwise, so along a segment of signed length s the yaw
changes by +s/r (L), -s/r (R) or not at all (S).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from btnav.core import fmath
from btnav.core.geometry import normalize_angle

_HALF_PI = 0.5 * np.pi
#: A length this far on the wrong side of zero is zero lost to rounding, and a square or
#: a cosine this far past its bound is on it (tangent circles are a solution).
_TOL = 1e-10

#: The eight mirror images, in order: (run backwards, time flipped, reflected).
_MIRRORS = tuple((b, t, f) for b in (False, True) for t in (False, True) for f in (False, True))
_TIME_FLIPPED = np.array([t for _, t, _ in _MIRRORS])
_REFLECTED = np.array([f for _, _, f in _MIRRORS])
_BACKWARDS = np.array([b for b, _, _ in _MIRRORS])

_Form = Callable[
    [np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]
]


# -- the closed forms ---------------------------------------------------------------
# Each takes the goal (x, y, phi) in the start's frame, the turning radius being 1, with
# sin(phi) and cos(phi), for the eight mirrored goals at once, and gives the signed
# segment lengths (one row per segment) and whether the construction exists. Whether the
# lengths have the word's gears is checked by the caller. The start's left circle is
# centred on (0, 1), the goal's left circle on (x - sin phi, y + cos phi) and its right
# circle on (x + sin phi, y - cos phi); every form is a fact about these circles.


def _polar(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    return fmath.hypot(a, b), fmath.arctan2(b, a)


def _asin(h: np.ndarray) -> np.ndarray:
    h = np.clip(h, -1.0, 1.0)
    return fmath.arctan2(h, np.sqrt(1.0 - h * h))


def _acos(c: np.ndarray) -> np.ndarray:
    c = np.clip(c, -1.0, 1.0)
    return fmath.arctan2(np.sqrt(1.0 - c * c), c)


def _sqrt_if(v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """sqrt(v) (0 where v < 0), and where v >= 0 but for rounding."""
    return np.sqrt(np.maximum(v, 0.0)), v >= -_TOL


def _lsl(
    x: np.ndarray, y: np.ndarray, phi: np.ndarray, s: np.ndarray, c: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """L+S+L+: the straight is the outer tangent of the two left circles, as long as their
    centres are apart and parallel to the line through them."""
    u, t = _polar(x - s, y - 1.0 + c)
    # One circle: the straight has no direction (its bearing is rounding's), so no first turn.
    t = np.where(u < _TOL, 0.0, normalize_angle(t))
    return np.stack([t, u, normalize_angle(phi - t)]), np.ones(x.shape, bool)


def _lsr(
    x: np.ndarray, y: np.ndarray, phi: np.ndarray, s: np.ndarray, c: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """L+S+R+: the straight is an inner tangent of the start's left and the goal's right
    circle; with their centres d apart it is sqrt(d^2 - 4) long, tilted atan(2 / u)."""
    d, theta = _polar(x + s, y - 1.0 - c)
    u, ok = _sqrt_if(d * d - 4.0)
    t = normalize_angle(theta + fmath.arctan2(np.full(u.shape, 2.0), u))
    return np.stack([t, u, normalize_angle(t - phi)]), ok


def _lrl(
    x: np.ndarray, y: np.ndarray, phi: np.ndarray, s: np.ndarray, c: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """L+R-L (C|C|C, C|CC): a middle circle touches both left circles, whose centres are d
    <= 4 apart; the isosceles triangle of the three centres makes the middle turn
    2 asin(d / 4)."""
    d, theta = _polar(x - s, y - 1.0 + c)
    half = _asin(d / 4.0)
    u = -2.0 * half
    t = normalize_angle(theta - half + np.pi)
    return np.stack([t, u, normalize_angle(phi - t + u)]), d <= 4.0 + _TOL


def _outer_turns(
    u1: np.ndarray, u2: np.ndarray, xi: np.ndarray, eta: np.ndarray, phi: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The first and last turn of L(t) R(u1) L(u2) R(v) given the middle two: the goal's
    right centre (xi, eta) from the start's left one is 2 (a, b) turned by t, with
    a = sin u1 - sin(u1 - u2) and b = cos u1 - cos(u1 - u2) - 1."""
    s1, c1 = fmath.sincos(u1)
    s12, c12 = fmath.sincos(u1 - u2)
    a, b = s1 - s12, c1 - c12 - 1.0
    t = normalize_angle(fmath.arctan2(a * eta - b * xi, a * xi + b * eta))
    return t, normalize_angle(t - u1 + u2 - phi)


def _lrlr_u(
    x: np.ndarray, y: np.ndarray, phi: np.ndarray, s: np.ndarray, c: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """L+R+L-R- (CC_u|C_uC): the two middle turns are equal and opposite, so the centres
    are d = 2 (2 cos u - 1) apart; cos u = (2 + d) / 4."""
    xi, eta = x + s, y - 1.0 - c
    rho = (2.0 + fmath.hypot(xi, eta)) / 4.0
    u = _acos(rho)
    t, v = _outer_turns(u, -u, xi, eta, phi)
    return np.stack([t, u, -u, v]), rho <= 1.0 + _TOL


def _lrlr_uu(
    x: np.ndarray, y: np.ndarray, phi: np.ndarray, s: np.ndarray, c: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """L+R-L-R+ (C|C_uC_u|C): the two middle turns are equal, so the centres are
    d = 2 sqrt(5 - 4 cos u) apart; Reeds & Shepp keep |u| <= pi/2."""
    xi, eta = x + s, y - 1.0 - c
    rho = (20.0 - xi * xi - eta * eta) / 16.0
    u = -_acos(rho)
    t, v = _outer_turns(u, u, xi, eta, phi)
    return np.stack([t, u, u, v]), (rho >= -_TOL) & (rho <= 1.0 + _TOL)


def _lrsl(
    x: np.ndarray, y: np.ndarray, phi: np.ndarray, s: np.ndarray, c: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """L+R-S-L- (C|C_pi/2 SC): seen from the start's left centre, heading as after the
    first turn, the goal's left centre is at (-2, u - 2), so |u - 2| = sqrt(rho^2 - 4)."""
    rho, theta = _polar(x - s, y - 1.0 + c)
    w, ok = _sqrt_if(rho * rho - 4.0)
    t = normalize_angle(theta + fmath.arctan2(w, np.full(w.shape, -2.0)))
    quarter = np.full(w.shape, -_HALF_PI)
    return np.stack([t, quarter, 2.0 - w, normalize_angle(phi - _HALF_PI - t)]), ok


def _lrsr(
    x: np.ndarray, y: np.ndarray, phi: np.ndarray, s: np.ndarray, c: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """L+R-S-R- (C|C_pi/2 SC): the goal's right centre is 2 - u to the right of the start's
    left centre, heading as after the first turn, which is that centre's bearing plus pi/2."""
    xi, eta = x + s, y - 1.0 - c
    rho, t = _polar(-eta, xi)
    t = normalize_angle(t)
    quarter = np.full(rho.shape, -_HALF_PI)
    return np.stack([t, quarter, 2.0 - rho, normalize_angle(t + _HALF_PI - phi)]), np.ones(
        x.shape, bool
    )


def _lrslr(
    x: np.ndarray, y: np.ndarray, phi: np.ndarray, s: np.ndarray, c: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """L+R-S-L-R+ (C|C_pi/2 SC_pi/2|C): seen from the start's left centre, heading as after
    the first turn, the goal's right centre is at (-2, u - 4), so |u - 4| = sqrt(rho^2 - 4)."""
    rho, theta = _polar(x + s, y - 1.0 - c)
    w, ok = _sqrt_if(rho * rho - 4.0)
    t = normalize_angle(theta + fmath.arctan2(w, np.full(w.shape, -2.0)))
    quarter = np.full(w.shape, -_HALF_PI)
    return np.stack([t, quarter, 4.0 - w, quarter, normalize_angle(t - phi)]), ok


#: Each form with the word it solves; a form whose last gear is free serves two words.
_FAMILIES: tuple[tuple[str, _Form], ...] = (
    ("L+S+L+", _lsl),
    ("L+S+R+", _lsr),
    ("L+R-L+", _lrl),
    ("L+R-L-", _lrl),
    ("L+R+L-R-", _lrlr_u),
    ("L+R-L-R+", _lrlr_uu),
    ("L+R-S-L-", _lrsl),
    ("L+R-S-R-", _lrsr),
    ("L+R-S-L-R+", _lrslr),
)


def _mirror(word: str, backwards: bool, time_flipped: bool, reflected: bool) -> str:
    """The word a mirrored goal's solution becomes back at the real goal."""
    segments = [word[i : i + 2] for i in range(0, len(word), 2)]
    if backwards:
        segments.reverse()
    swap = {"L": "R", "R": "L", "S": "S"} if reflected else {}
    gear = {"+": "-", "-": "+"} if time_flipped else {}
    return "".join(swap.get(s[0], s[0]) + gear.get(s[1], s[1]) for s in segments)


#: The name each family's solution of each mirrored goal goes by.
_NAMES = tuple(tuple(_mirror(word, *m) for m in _MIRRORS) for word, _ in _FAMILIES)
#: Each family's gears as signs, a column to scale its rows of lengths.
_GEARS = tuple(
    np.array([[1.0] if g == "+" else [-1.0] for g in word[1::2]]) for word, _ in _FAMILIES
)
#: All 48 words, ties between equally long words going to the first.
WORDS = tuple(dict.fromkeys(name for names in _NAMES for name in names))
assert len(WORDS) == 48


@dataclass(frozen=True)
class ReedsSheppPath:
    """One word's signed segment lengths in metres; a negative length is driven in reverse."""

    word: str
    lengths: tuple[float, ...]
    turning_radius: float

    @property
    def segments(self) -> str:
        """The segment types, one letter (L, R or S) a segment."""
        return self.word[::2]

    @property
    def length(self) -> float:
        total = 0.0  # left to right (Python 3.12's sum() compensates: other bits)
        for seg in self.lengths:
            total += abs(seg)
        return float(total)

    def sample(self, start: tuple[float, float, float], step: float) -> np.ndarray:
        """Poses (x, y, yaw) every `step` metres along the path, start and end included; yaw
        runs on unwrapped, as in dubins. Segments of zero length add no pose."""
        poses = [np.asarray(start, dtype=float)]
        x, y, yaw = (float(v) for v in start)
        r = self.turning_radius
        for letter, seg in zip(self.segments, self.lengths, strict=True):
            if seg == 0.0:
                continue
            n = max(1, int(np.ceil(abs(seg) / step)))
            s = np.linspace(seg / n, seg, n)
            if letter == "S":
                sn, c = fmath.sincos(yaw)
                xs, ys, yaws = x + s * c, y + s * sn, np.full(n, yaw)
            else:
                turn = 1.0 if letter == "L" else -1.0
                yaws = yaw + turn * s / r
                sins, coss = fmath.sincos(yaws)
                s0, c0 = fmath.sincos(yaw)
                xs = x + turn * r * (sins - s0)
                ys = y - turn * r * (coss - c0)
            poses.append(np.column_stack([xs, ys, yaws]))
            x, y, yaw = float(xs[-1]), float(ys[-1]), float(yaws[-1])
        return np.vstack(poses)


def _mirrored_goals(
    start: tuple[float, float, float], goal: tuple[float, float, float], turning_radius: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The goal in the start's frame (radius 1) and its seven mirror images, with sin and
    cos of their headings (a mirror only flips the sign of sin)."""
    s0, c0 = fmath.sincos(float(start[2]))
    dx, dy = goal[0] - start[0], goal[1] - start[1]
    x = (c0 * dx + s0 * dy) / turning_radius
    y = (c0 * dy - s0 * dx) / turning_radius
    phi = normalize_angle(float(goal[2]) - float(start[2]))
    s, c = fmath.sincos(phi)
    # In reverse order a path ends where, time flipped, it would end run from the goal.
    xs = np.where(_BACKWARDS, x * c + y * s, x)
    ys = np.where(_BACKWARDS, x * s - y * c, y)
    xs = np.where(_TIME_FLIPPED, -xs, xs)
    ys = np.where(_REFLECTED, -ys, ys)
    sign = np.where(_TIME_FLIPPED != _REFLECTED, -1.0, 1.0)
    return xs, ys, sign * phi, sign * s, np.full(8, c)


def all_words(
    start: tuple[float, float, float], goal: tuple[float, float, float], turning_radius: float
) -> dict[str, ReedsSheppPath]:
    """Every word that reaches `goal` from `start`, each by its shortest solution (those
    without a solution are left out), in the order of WORDS."""
    goals = _mirrored_goals(start, goal, turning_radius)
    solved: dict[_Form, tuple[np.ndarray, np.ndarray]] = {}
    best: dict[str, tuple[float, np.ndarray]] = {}
    for (_, form), names, gears in zip(_FAMILIES, _NAMES, _GEARS, strict=True):
        if form not in solved:
            solved[form] = form(*goals)
        lengths, exists = solved[form]
        forward = gears * lengths  # >= 0 where the gears are the word's
        ok = exists & np.all(forward >= -_TOL, axis=0) & np.all(np.isfinite(lengths), axis=0)
        clean = gears * np.maximum(forward, 0.0)
        totals = np.abs(clean).sum(axis=0)
        for k in np.flatnonzero(ok):
            if names[k] not in best or totals[k] < best[names[k]][0]:
                backwards, time_flipped, _ = _MIRRORS[k]
                seg = -clean[:, k] if time_flipped else clean[:, k]
                best[names[k]] = (float(totals[k]), seg[::-1] if backwards else seg)
    return {
        word: ReedsSheppPath(
            word, tuple(float(v) * turning_radius for v in best[word][1]), turning_radius
        )
        for word in WORDS
        if word in best
    }


def shortest_path(
    start: tuple[float, float, float], goal: tuple[float, float, float], turning_radius: float
) -> ReedsSheppPath:
    """The shortest of the words that reach `goal` (ties go to the first in WORDS)."""
    return min(all_words(start, goal, turning_radius).values(), key=lambda path: path.length)
