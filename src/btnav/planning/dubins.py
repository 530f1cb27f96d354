"""Dubins curves: the shortest forward-only path between two poses for a car-like base.

SmacPlannerHybrid's DUBIN motion model expands analytically with these curves. The PyPI
packages are stale, so the six words (LSL, RSR, LSR, RSL, RLR, LRL) are written here after
Shkel & Lumelsky, all six solved at once with numpy. Trigonometry goes through core.fmath so
a plan is the same bits on every CPU.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from btnav.core import fmath
from btnav.core.geometry import TWO_PI

WORDS = ("LSL", "RSR", "LSR", "RSL", "RLR", "LRL")
#: How far a square or cosine may round past its bound: tangent circles are a solution.
_TOL = 1e-10


def _mod2pi(a: Any) -> Any:
    """a mod 2 pi in [0, 2 pi), a hair under 2 pi taken as 0: a turn of -1e-17 is rounding,
    not a full circle."""
    m = np.mod(a, TWO_PI)
    return np.where(m > TWO_PI - _TOL, 0.0, m)


@dataclass(frozen=True)
class DubinsPath:
    """One word's three segment lengths in metres; an 'S' segment is straight."""

    word: str
    lengths: tuple[float, float, float]
    turning_radius: float

    @property
    def length(self) -> float:
        a, b, c = self.lengths  # left to right (Python 3.12's sum() compensates: other bits)
        return float(a + b + c)

    def sample(self, start: tuple[float, float, float], step: float) -> np.ndarray:
        """Poses (x, y, yaw) every `step` metres along the path, start and end included."""
        poses = [np.asarray(start, dtype=float)]
        x, y, yaw = start
        r = self.turning_radius
        for letter, seg in zip(self.word, self.lengths, strict=True):
            n = max(1, int(np.ceil(seg / step)))
            s = np.linspace(seg / n, seg, n)
            if letter == "S":
                c, sn = fmath.cos(yaw), fmath.sin(yaw)
                xs, ys, yaws = x + s * c, y + s * sn, np.full(n, yaw)
            else:
                turn = 1.0 if letter == "L" else -1.0
                yaws = yaw + turn * s / r
                xs = x + turn * r * (fmath.sin(yaws) - fmath.sin(yaw))
                ys = y - turn * r * (fmath.cos(yaws) - fmath.cos(yaw))
            poses.append(np.column_stack([xs, ys, yaws]))
            x, y, yaw = float(xs[-1]), float(ys[-1]), float(yaws[-1])
        return np.vstack(poses)


def all_words(
    start: tuple[float, float, float], goal: tuple[float, float, float], turning_radius: float
) -> dict[str, DubinsPath]:
    """Every word that reaches `goal` from `start` (those without a solution are left out)."""
    dx, dy = goal[0] - start[0], goal[1] - start[1]
    d = float(fmath.hypot(dx, dy)) / turning_radius
    theta = float(fmath.arctan2(dy, dx)) if d > 0.0 else 0.0
    a = float(_mod2pi(start[2] - theta))
    b = float(_mod2pi(goal[2] - theta))
    sa, ca = float(fmath.sin(a)), float(fmath.cos(a))
    sb, cb = float(fmath.sin(b)), float(fmath.cos(b))
    cab = float(fmath.cos(a - b))

    p_sq = np.array(
        [
            2.0 + d * d - 2.0 * cab + 2.0 * d * (sa - sb),  # LSL
            2.0 + d * d - 2.0 * cab + 2.0 * d * (sb - sa),  # RSR
            -2.0 + d * d + 2.0 * cab + 2.0 * d * (sa + sb),  # LSR
            -2.0 + d * d + 2.0 * cab - 2.0 * d * (sa + sb),  # RSL
        ]
    )
    straight_ok = p_sq >= -_TOL
    p = np.sqrt(np.maximum(p_sq, 0.0))
    across = np.array([cb - ca, ca - cb, -ca - cb, ca + cb])  # between the circles' centres
    along = np.array([d + sa - sb, d - sa + sb, d + sa + sb, d - sa - sb])
    heading = fmath.arctan2(across, along)
    heading[2:] -= fmath.arctan2(np.array([-2.0, 2.0]), p[2:])  # the cross tangents' tilt
    # LSL and RSR: the straight is the centres' distance (hypot, not the sqrt of a square
    # that cancels). With the goal on the start's circle it has no direction, its bearing
    # is noise: the whole turn goes last, not split in two with a full circle added.
    p[:2] = fmath.hypot(along[:2], across[:2])
    one_circle = p[:2] < _TOL
    p[:2][one_circle] = 0.0
    heading[:2][one_circle] = a
    sign_a = np.array([-1.0, 1.0, -1.0, 1.0])
    t = _mod2pi(sign_a * (a - heading))
    q = _mod2pi(np.array([b - heading[0], -b + heading[1], -b + heading[2], b - heading[3]]))

    # RLR, LRL: three turns; the middle one exists when the circles are close enough.
    cos_mid = np.array(
        [
            (6.0 - d * d + 2.0 * cab + 2.0 * d * (sa - sb)) / 8.0,
            (6.0 - d * d + 2.0 * cab + 2.0 * d * (sb - sa)) / 8.0,
        ]
    )
    turn_ok = np.abs(cos_mid) <= 1.0 + _TOL
    c = np.clip(cos_mid, -1.0, 1.0)
    p_turn = _mod2pi(TWO_PI - fmath.arctan2(np.sqrt(1.0 - c * c), c))
    t_turn = _mod2pi(
        np.array([a, -a])
        - fmath.arctan2(np.array([ca - cb, ca - cb]), np.array([d - sa + sb, d + sa - sb]))
        + p_turn / 2.0
    )
    q_turn = _mod2pi(np.array([a - b, b - a]) - t_turn + p_turn)

    ts = np.concatenate([t, t_turn]) * turning_radius
    ps = np.concatenate([p, p_turn]) * turning_radius
    qs = np.concatenate([q, q_turn]) * turning_radius
    ok = np.concatenate([straight_ok, turn_ok])
    return {
        word: DubinsPath(word, (float(ts[i]), float(ps[i]), float(qs[i])), turning_radius)
        for i, word in enumerate(WORDS)
        if ok[i]
    }


def shortest_path(
    start: tuple[float, float, float], goal: tuple[float, float, float], turning_radius: float
) -> DubinsPath:
    """The shortest of the words that reach `goal` (ties go to the first in WORDS)."""
    return min(all_words(start, goal, turning_radius).values(), key=lambda path: path.length)
