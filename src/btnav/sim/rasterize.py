"""World -> occupancy grid: the map a perfect mapper would make of the static scene.

Moving obstacles are drawn where they start. A cell is occupied when the geometry
covers its centre or an outline passes through it, so a wall thinner than a cell
never leaves a gap a planner could slip through. Cells inside the world's bounds are
otherwise free; the padding around the bounds is unknown. Everything is vectorised
over cells (loops run over shapes and row chunks only).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from ..core import fmath
from ..core.errors import MapError
from ..core.geometry import Pose2D
from ..maps.occupancy_grid import FREE, OCCUPIED, UNKNOWN, OccupancyGrid
from .scene import build_solids, solids_geometry
from .world import World
from .world_spec import WorldSpec

#: Refuse maps larger than this many cells (int8 data, plus a bool mask, in memory).
MAX_CELLS = 40_000_000
#: Work on at most this many (cell, edge) pairs at once in the point-in-polygon test.
_CHUNK = 2_000_000
#: A sample this close (in cells) to a cell border is ambiguous and left to the fill test.
_BORDER_EPS = 1e-6


class _Raster:
    def __init__(self, shape: tuple[int, int], ox: float, oy: float, res: float) -> None:
        self.occ = np.zeros(shape, dtype=bool)
        self.ox, self.oy, self.res = ox, oy, res

    def _window(
        self, lo: NDArray[np.float64], hi: NDArray[np.float64]
    ) -> tuple[int, int, int, int]:
        """Cell rows/cols [r0, r1) x [c0, c1) whose centres may lie in the box lo..hi."""
        h, w = self.occ.shape
        c0 = max(math.floor((lo[0] - self.ox) / self.res), 0)
        c1 = min(math.floor((hi[0] - self.ox) / self.res) + 1, w)
        r0 = max(math.floor((lo[1] - self.oy) / self.res), 0)
        r1 = min(math.floor((hi[1] - self.oy) / self.res) + 1, h)
        return r0, r1, c0, c1

    def fill_polygon(self, poly: NDArray[np.float64]) -> None:
        """Mark cells whose centre is inside `poly` (even-odd rule, any winding, concave too)."""
        r0, r1, c0, c1 = self._window(poly.min(axis=0), poly.max(axis=0))
        if r0 >= r1 or c0 >= c1:
            return
        xs = self.ox + (np.arange(c0, c1) + 0.5) * self.res
        a, b = poly, np.roll(poly, -1, axis=0)
        rows_per_chunk = max(1, _CHUNK // max(1, (c1 - c0) * len(poly)))
        for rs in range(r0, r1, rows_per_chunk):
            re = min(rs + rows_per_chunk, r1)
            ys = self.oy + (np.arange(rs, re) + 0.5) * self.res
            yy = ys[:, None]  # (R, 1) against (K,) edges
            spans = (a[:, 1] > yy) != (b[:, 1] > yy)
            dy = np.where(spans, b[:, 1] - a[:, 1], 1.0)
            x_cross = a[:, 0] + (yy - a[:, 1]) * (b[:, 0] - a[:, 0]) / dy
            x_cross = np.where(spans, x_cross, -np.inf)  # (R, K)
            inside = (np.count_nonzero(x_cross[:, None, :] > xs[None, :, None], axis=2) % 2) == 1
            self.occ[rs:re, c0:c1] |= inside

    def fill_circle(self, cx: float, cy: float, r: float) -> None:
        r0, r1, c0, c1 = self._window(np.array([cx - r, cy - r]), np.array([cx + r, cy + r]))
        if r0 >= r1 or c0 >= c1:
            return
        xs = self.ox + (np.arange(c0, c1) + 0.5) * self.res - cx
        ys = self.oy + (np.arange(r0, r1) + 0.5) * self.res - cy
        self.occ[r0:r1, c0:c1] |= ys[:, None] ** 2 + xs[None, :] ** 2 <= r * r

    def mark_points(self, pts: NDArray[np.float64]) -> None:
        """Mark the cells containing points (outline samples), skipping points on cell borders."""
        u = (pts[:, 0] - self.ox) / self.res
        v = (pts[:, 1] - self.oy) / self.res
        cu, cv = np.floor(u), np.floor(v)
        fu, fv = u - cu, v - cv
        ok = (
            (fu > _BORDER_EPS)
            & (fu < 1 - _BORDER_EPS)
            & (fv > _BORDER_EPS)
            & (fv < 1 - _BORDER_EPS)
        )
        h, w = self.occ.shape
        ok &= (cu >= 0) & (cu < w) & (cv >= 0) & (cv < h)
        self.occ[cv[ok].astype(np.int64), cu[ok].astype(np.int64)] = True

    def trace_segment(self, a: NDArray[np.float64], b: NDArray[np.float64]) -> None:
        """Mark every cell the segment a-b passes through (an exact supercover).

        The grid lines it crosses cut it into pieces that each lie in one cell; the
        midpoint of each piece names that cell. Pieces along a grid line are skipped
        (`mark_points`), the cells on either side being decided by the fill.
        """
        ua = (a - (self.ox, self.oy)) / self.res
        ub = (b - (self.ox, self.oy)) / self.res
        d = ub - ua
        # Clip to the grid (Liang-Barsky) so a wall running far outside costs nothing.
        t0, t1 = 0.0, 1.0
        h, w = self.occ.shape
        for axis, size in ((0, w), (1, h)):
            if d[axis] == 0.0:
                if not (0.0 <= ua[axis] <= size):
                    return
                continue
            ta, tb = (0.0 - ua[axis]) / d[axis], (size - ua[axis]) / d[axis]
            t0, t1 = max(t0, min(ta, tb)), min(t1, max(ta, tb))
        if t0 >= t1:
            return
        a, b, ua, ub = a + t0 * (b - a), a + t1 * (b - a), ua + t0 * d, ua + t1 * d
        d = ub - ua
        ts = [np.array([0.0, 1.0])]
        for axis in (0, 1):
            if d[axis] != 0.0:
                lo, hi = sorted((ua[axis], ub[axis]))
                lines = np.arange(math.ceil(lo), math.floor(hi) + 1, dtype=float)
                ts.append((lines - ua[axis]) / d[axis])
        t = np.unique(np.clip(np.concatenate(ts), 0.0, 1.0))
        mid = (t[:-1] + t[1:]) / 2.0
        self.mark_points(a + mid[:, None] * (b - a))

    def trace_outline(self, poly: NDArray[np.float64]) -> None:
        for a, b in zip(poly, np.roll(poly, -1, axis=0), strict=True):
            self.trace_segment(a, b)

    def trace_circle(self, cx: float, cy: float, r: float) -> None:
        """The circle's cells, through an inscribed polygon within res/20 of the circle."""
        c = max(1.0 - self.res / 20.0 / r, -1.0)  # acos(c) as fmath's arctan2, on any CPU
        n = max(16, math.ceil(math.pi / fmath.arctan2(math.sqrt(1.0 - c * c), c)))
        s, co = fmath.sincos(np.linspace(0.0, 2 * math.pi, n, endpoint=False))
        self.trace_outline(np.column_stack([cx + r * co, cy + r * s]))


def rasterize(
    world_or_spec: World | WorldSpec, resolution: float = 0.05, padding: float = 0.2
) -> OccupancyGrid:
    """An occupancy grid of the world's solid geometry (moving obstacles at their start).

    The grid covers the bounds plus `padding` on every side, in world coordinates
    (the origin is the bounds' lower-left corner minus the padding), frame `map`.
    """
    spec = world_or_spec.spec if isinstance(world_or_spec, World) else world_or_spec
    if not (math.isfinite(resolution) and resolution > 0):
        raise MapError(f"resolution must be a positive number of metres, got {resolution}")
    if not (math.isfinite(padding) and padding >= 0):
        raise MapError(f"padding must be a non-negative number of metres, got {padding}")
    (x0, y0), (x1, y1) = spec.bounds
    ox, oy = x0 - padding, y0 - padding
    width = max(1, math.ceil((x1 - x0 + 2 * padding) / resolution - 1e-9))
    height = max(1, math.ceil((y1 - y0 + 2 * padding) / resolution - 1e-9))
    if width * height > MAX_CELLS:
        raise MapError(
            f"the map would have {width} x {height} cells (more than {MAX_CELLS:,}); "
            "use a coarser resolution",
            file=spec.file,
            line=spec.line_of("bounds"),
            key="bounds",
        )
    geometry = solids_geometry(build_solids(spec))
    raster = _Raster((height, width), ox, oy, resolution)
    for poly in geometry.polygons:
        raster.fill_polygon(poly)
        raster.trace_outline(poly)
    for cx, cy, r in geometry.circles:
        raster.fill_circle(cx, cy, r)
        raster.trace_circle(cx, cy, r)

    xs = ox + (np.arange(width) + 0.5) * resolution
    ys = oy + (np.arange(height) + 0.5) * resolution
    inside = ((ys >= y0) & (ys <= y1))[:, None] & ((xs >= x0) & (xs <= x1))[None, :]
    data = np.where(inside, np.int8(FREE), np.int8(UNKNOWN)).astype(np.int8)
    data[raster.occ] = OCCUPIED
    return OccupancyGrid(data, resolution, Pose2D(ox, oy, 0.0), "map")
