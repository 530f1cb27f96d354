"""nav2_route's CornerArc: a circular arc of `smoothing_radius` fitted into the corner two
edges make at a node, tangent to both.

No arc when an edge has no length, the edges turn back on themselves (angle 0) or run
nearly straight on (angle between them above `smoothing_angle_threshold`), or the arc's
tangent points would not fit on the edges. Angles come from atan2 and square roots
(fmath), not acos and tan, so the arc is the same on every machine.
"""

from __future__ import annotations

import math

import numpy as np

from ..core import fmath

Point = tuple[float, float]


class CornerArc:
    def __init__(
        self, start: Point, corner: Point, end: Point, radius: float, angle_threshold: float
    ) -> None:
        self.valid = False
        self.start_point: Point = corner
        self.end_point: Point = corner
        self.center: Point = corner
        ax, ay = start[0] - corner[0], start[1] - corner[1]
        bx, by = end[0] - corner[0], end[1] - corner[1]
        la, lb = fmath.hypot(ax, ay), fmath.hypot(bx, by)
        if la == 0.0 or lb == 0.0:
            return
        cross = abs(ax * by - ay * bx)
        dot = ax * bx + ay * by
        angle = float(fmath.arctan2(cross, dot))  # the angle between the edges, [0, pi]
        if angle < 1e-6 or angle > angle_threshold:
            return
        # tan(angle / 2) = sin / (1 + cos), sin(angle / 2) = sqrt((1 - cos) / 2)
        tan_half = cross / (la * lb + dot)
        tangent = radius / tan_half
        if not (tangent < la and tangent < lb):
            return
        ua, ub = (ax / la, ay / la), (bx / lb, by / lb)
        sx, sy = ua[0] + ub[0], ua[1] + ub[1]
        sm = fmath.hypot(sx, sy)
        sin_half = math.sqrt(max(0.0, (1.0 - dot / (la * lb)) / 2.0))
        bisector = radius / sin_half
        self.start_point = (corner[0] + ua[0] * tangent, corner[1] + ua[1] * tangent)
        self.end_point = (corner[0] + ub[0] * tangent, corner[1] + ub[1] * tangent)
        self.center = (corner[0] + sx / sm * bisector, corner[1] + sy / sm * bisector)
        self.valid = True

    def interpolate(self, max_angle_step: float) -> np.ndarray:
        """Points along the arc from its start (included) to its end (excluded), (N, 2)."""
        rs = np.subtract(self.start_point, self.center)
        re = np.subtract(self.end_point, self.center)
        signed = float(fmath.arctan2(rs[0] * re[1] - rs[1] * re[0], rs[0] * re[0] + rs[1] * re[1]))
        n = max(1, math.ceil(abs(signed) / max_angle_step))
        s, c = fmath.sincos(np.arange(n) * (signed / n))
        x = self.center[0] + rs[0] * c - rs[1] * s
        y = self.center[1] + rs[0] * s + rs[1] * c
        return np.stack([x, y], axis=1)
