"""The world's solid geometry at one instant, as arrays for vectorised sensors and rasterising."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray


def _no_circles() -> NDArray[np.float64]:
    return np.zeros((0, 3))


@dataclass
class Geometry:
    """Every solid thing except the robot: convex-or-not polygons (walls, boxes,
    polygons, moving obstacles where they are now) and circles.

    `polygons` are (K, 2) vertex arrays, not repeating the first vertex.
    `circles` is (M, 3): centre x, centre y, radius.

    `one_sided` promises that every polygon is a solid wound counter-clockwise and
    that no sensor sits inside one, so a ray caster may skip the edges that face away
    from the sensor (half of them). The world's geometry keeps that promise; a
    hand-made outline of a room seen from inside does not, and stays two-sided.
    """

    polygons: list[NDArray[np.float64]] = field(default_factory=list)
    circles: NDArray[np.float64] = field(default_factory=_no_circles)
    one_sided: bool = False
    _segments: NDArray[np.float64] | None = field(default=None, repr=False, compare=False)

    @property
    def segments(self) -> NDArray[np.float64]:
        """(N, 4) edges x1, y1, x2, y2 of every polygon (computed once)."""
        if self._segments is None:
            if self.polygons:
                starts = np.concatenate(self.polygons)
                ends = np.concatenate([np.roll(p, -1, axis=0) for p in self.polygons])
                self._segments = np.hstack([starts, ends])
            else:
                self._segments = np.zeros((0, 4))
        return self._segments

    def merged(self, other: Geometry) -> Geometry:
        """Static and moving parts together (the moving part changes every step)."""
        g = Geometry(
            self.polygons + other.polygons,
            np.vstack([self.circles, other.circles]),
            self.one_sided and other.one_sided,
        )
        if self._segments is not None or other._segments is not None:
            g._segments = np.vstack([self.segments, other.segments])
        return g
