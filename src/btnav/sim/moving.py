"""Where a moving obstacle is at a given time: a pure function of sim time.

The route starts where the obstacle is drawn (its reference point) and goes through
`moves.path` at constant speed. With `loop: true` it goes back and forth for ever
(ping-pong); with `loop: false` it stops at the last point. Positions come from
the time alone, never from summed steps, so they do not drift and do not depend
on the physics step size.
"""

from __future__ import annotations

from bisect import bisect_right

import numpy as np
from numpy.typing import NDArray

from ..core import fmath
from .world_spec import MovesSpec


class Route:
    """A polyline travelled at constant speed."""

    def __init__(self, start: NDArray[np.float64], moves: MovesSpec) -> None:
        pts = np.vstack([np.asarray(start, dtype=float)[None, :], np.asarray(moves.path, float)])
        keep = np.ones(len(pts), dtype=bool)
        keep[1:] = np.any(np.diff(pts, axis=0) != 0, axis=1)
        self.points = pts[keep]
        seg = fmath.hypot(*np.diff(self.points, axis=0).T) if len(self.points) > 1 else np.zeros(0)
        self.cumulative = np.concatenate([[0.0], np.cumsum(seg)])
        self.length = float(self.cumulative[-1])
        self.speed = float(moves.speed)
        self._pts = [(float(x), float(y)) for x, y in self.points]
        self._cum = [float(c) for c in self.cumulative]
        self.loop = bool(moves.loop)

    def distance_at(self, t: float) -> float:
        """How far along the route the obstacle is at time t (folded for ping-pong)."""
        if self.length <= 0.0:
            return 0.0
        s = self.speed * max(t, 0.0)
        if not self.loop:
            return min(s, self.length)
        u = s % (2.0 * self.length)
        return 2.0 * self.length - u if u > self.length else u

    def position_at(self, t: float) -> tuple[float, float]:
        """The reference point's position at time t (plain floats: this runs every step)."""
        pts = self._pts
        if self.length <= 0.0:
            return pts[0]
        s = self.distance_at(t)
        cum = self._cum
        k = min(max(bisect_right(cum, s) - 1, 0), len(pts) - 2)
        span = cum[k + 1] - cum[k]
        f = (s - cum[k]) / span if span > 0 else 0.0
        (x0, y0), (x1, y1) = pts[k], pts[k + 1]
        return x0 + f * (x1 - x0), y0 + f * (y1 - y0)
