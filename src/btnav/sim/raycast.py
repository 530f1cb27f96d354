"""Vectorised ray casting: many rays from one origin against every segment and circle at once.

The lidar's inner loop, written for numpy rather than for reading one ray: rays x segments
as whole arrays, the hit test rewritten in inverse range (1/t) so that one `fmath.matmul_k`
product and two minimums and a max decide every pair, with no division and no masks. Rare
cases (an origin on a segment's line, inside a circle) take a small exact side path.
A `RayCaster` keeps its scratch buffers, so a sensor owns one. By default the compiled
`raycast_kernel` does the same work with the same bits (`method="kernel"`; see
docs/decisions/0004-numba-lidar-kernel.md); the formulas: docs/decisions/0023.
"""

from __future__ import annotations

import importlib
import math
import warnings
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..core import fmath
from ..core.kernel_switch import Method, default_method
from .geometry import Geometry

if TYPE_CHECKING:
    from .raycast_kernel import GridCaster

#: Ray x segment pairs evaluated in one block: bounds the scratch memory (2 x 3 x 512 kB).
CHUNK_PAIRS = 1 << 16
#: Relative lengthening of every segment, so vertices shared by two edges are hit.
ENDPOINT_EPS = 1e-9
#: From this many segments (circles) on, those out of range are dropped first by default.
PRUNE_MIN_SEGMENTS = 128
PRUNE_MIN_CIRCLES = 32
#: |a x e| (m^2) at or below which the origin counts as on a segment's line.
ON_LINE_AREA = 1e-12
#: Sideways miss (m) at a segment's far end within which a ray counts as running along it.
COLLINEAR_TOL = 1e-9

#: Scale of the W and V rows (a power of two, so exact): min(K, min(W, V)) is then K
#: for every hit but those within 2^-40 of a (lengthened) segment's end, which read a
#: hit a hair farther, and <= 0 for a miss.
_BIG = 2.0**40
_E = ENDPOINT_EPS
_S = 1.0 / (1.0 + 2.0 * ENDPOINT_EPS)
#: A segment (px, py, qx, qy) relative to the origin, @ _ROWS, / (p x q), gives the W,
#: V and K rows, two columns each: BIG (-a_y, a_x), BIG ((e_y, -e_x) - (-a_y, a_x)) and
#: (e_y, -e_x), with a = p - eps e the lengthened start and u measured along the
#: lengthened segment (hence the factor 1 / (1 + 2 eps)).
_K_COLS = np.array([[0.0, 1.0], [-1.0, 0.0], [0.0, -1.0], [1.0, 0.0]])
_W_COLS = np.array(
    [[0.0, (1.0 + _E) * _S], [-(1.0 + _E) * _S, 0.0], [0.0, -_E * _S], [_E * _S, 0.0]]
)
_ROWS = np.hstack([_BIG * _W_COLS, _BIG * (_K_COLS - _W_COLS), _K_COLS])
#: (mx, my, r) @ this, squared first: |m|^2 - r^2.
_CIRCLE_C = np.array([1.0, 1.0, -1.0])
_NO_SEGMENTS = np.zeros((0, 4))
_NO_CIRCLES = np.zeros((0, 3))
_NO_ROWS = np.zeros((0, 2))
#: Where rays end when `max_range` is infinite (metres): no world is this big.
_FAR = 1e100

#: How a `RayCaster` made without a `method` casts: the compiled grid walk, or numpy
#: (environment variable BTNAV_RAYCAST=numpy; the same bits either way).
DEFAULT_METHOD: Method = default_method("BTNAV_RAYCAST")


def beam_directions(angles: ArrayLike) -> NDArray[np.float64]:
    """(B, 2) unit vectors for beam angles (radians), to be cached by a sensor."""
    s, c = fmath.sincos(np.asarray(angles, dtype=float))
    return np.stack([c, s], axis=-1)


def _prune_segments(segs: NDArray[np.float64], max_range: float) -> NDArray[np.float64]:
    """Drop segments (already relative to the origin) wholly beyond `max_range`.

    Conservative and cheap: a segment goes only if its bounding circle (centre at its
    midpoint, radius half its length) lies beyond the range circle.
    """
    mx = 0.5 * (segs[:, 0] + segs[:, 2])
    my = 0.5 * (segs[:, 1] + segs[:, 3])
    half = 0.5 * fmath.hypot(segs[:, 2] - segs[:, 0], segs[:, 3] - segs[:, 1])
    keep = fmath.hypot(mx, my) - half <= max_range
    return segs if keep.all() else segs[keep]


def _on_line_hits(segs: NDArray[np.float64], dirs: NDArray[np.float64]) -> NDArray[np.float64]:
    """Nearest t per ray for the (few) segments whose line passes through the origin.

    If the origin lies on such a segment every ray hits it at t = 0; otherwise only a
    ray running along the line toward the segment hits it, at its nearer end.
    """
    out = np.full(len(dirs), np.inf)
    p, q = segs[:, :2], segs[:, 2:]
    e = q - p
    length = fmath.hypot(e[:, 0], e[:, 1])
    on_seg = fmath.dot_rows(p, e) * fmath.dot_rows(q, e) <= 0  # o between p and q
    on_seg &= length > 0  # a zero-length segment is a point: never hit
    if np.any(on_seg):
        out[:] = 0.0
        return out
    keep = length > 0
    p, q, e, length = p[keep], q[keep], e[keep], length[keep]
    if len(p) == 0:
        return out
    unit = e / length[:, None]
    # A ray is along the line if its sideways miss at the far end is within tolerance.
    far = np.maximum(fmath.hypot(p[:, 0], p[:, 1]), fmath.hypot(q[:, 0], q[:, 1]))
    side = np.abs(dirs[:, 0:1] * unit[:, 1] - dirs[:, 1:2] * unit[:, 0]) * far
    tp, tq = fmath.matmul_k(dirs, p.T), fmath.matmul_k(dirs, q.T)  # along each ray to each end
    t = np.minimum(tp, tq)
    hit = (side <= COLLINEAR_TOL) & (t >= 0)
    if np.any(hit):
        out = np.minimum(out, np.where(hit, t, np.inf).min(axis=1))
    return out


class RayCaster:
    """Casts fans of rays, reusing its scratch buffer from one call to the next.

    One per sensor (not shared between threads). Methods take `dirs` as (B, 2) unit
    vectors in the world frame; the transpose of a C-ordered (2, B) array saves a copy.

    `method` (default `DEFAULT_METHOD`): "kernel" walks a grid index of the geometry the
    caster keeps from scan to scan (its static part; see `raycast_kernel.GridCaster`),
    "numpy" evaluates every ray against every segment in range. Both give the same bits;
    without numba the kernel falls back to numpy, with one warning.
    """

    def __init__(self, chunk_pairs: int | None = None, method: Method | None = None) -> None:
        self.chunk_pairs = CHUNK_PAIRS if chunk_pairs is None else max(1, int(chunk_pairs))
        self._buf = np.empty(0)
        method = DEFAULT_METHOD if method is None else method
        if method not in ("kernel", "numpy"):
            raise ValueError(f"method is 'kernel' or 'numpy', got {method!r}")
        self.method: Method = method
        self._grid: GridCaster | None = None
        if method == "kernel":
            self._grid = _grid_caster()
            if self._grid is None:
                self.method = "numpy"

    def cast(
        self,
        geometry: Geometry,
        origin: ArrayLike,
        dirs: NDArray[np.float64],
        max_range: float = math.inf,
        *,
        prune: bool | None = None,
    ) -> NDArray[np.float64]:
        """Distance along each ray from `origin` to the nearest solid of `geometry`;
        `inf` for rays with no hit within `max_range`.

        With `prune` (default: when there are many) segments and circles wholly beyond
        `max_range` are dropped before the rays x segments block.
        """
        return self._cast(
            origin, dirs, geometry.segments, geometry.circles, max_range, prune, geometry.one_sided
        )

    def cast_segments(
        self,
        origin: ArrayLike,
        dirs: NDArray[np.float64],
        segments: NDArray[np.float64],
        max_range: float = math.inf,
        *,
        prune: bool | None = None,
    ) -> NDArray[np.float64]:
        """Like `cast`, for (S, 4) segments x1, y1, x2, y2 only."""
        return self._cast(origin, dirs, segments, _NO_CIRCLES, max_range, prune)

    def cast_circles(
        self,
        origin: ArrayLike,
        dirs: NDArray[np.float64],
        circles: NDArray[np.float64],
        max_range: float = math.inf,
    ) -> NDArray[np.float64]:
        """Like `cast`, for (M, 3) circles cx, cy, r only."""
        return self._cast(origin, dirs, _NO_SEGMENTS, circles, max_range, None)

    # -- the work, in inverse range ------------------------------------------------------

    def _cast(
        self,
        origin: ArrayLike,
        dirs: NDArray[np.float64],
        segments: NDArray[np.float64],
        circles: NDArray[np.float64],
        max_range: float,
        prune: bool | None,
        one_sided: bool = False,
    ) -> NDArray[np.float64]:
        ox, oy = float(origin[0]), float(origin[1])  # type: ignore[index]
        dirs_t = np.ascontiguousarray(dirs.T, dtype=np.float64)
        n_rays = dirs_t.shape[1]
        t = np.full(n_rays, np.inf)
        if n_rays == 0:
            return t
        # Hits beyond `cap` read inf; an infinite max_range still needs a finite cap here.
        cap = max_range if math.isfinite(max_range) else _FAR
        if self._grid is not None:
            index, moving_s, moving_c = self._grid.split(segments, circles)
            return index.cast(
                (ox, oy),
                dirs_t,
                cap,
                len(segments) >= PRUNE_MIN_SEGMENTS if prune is None else prune,
                len(circles) >= PRUNE_MIN_CIRCLES if prune is None else prune,
                one_sided,
                _ROWS,
                moving_s,
                moving_c,
            )
        extras: list[NDArray[np.float64]] = []  # per-ray 1/t from the exact side paths
        seg_rows, circ_rows, inv_root_c = _NO_ROWS, _NO_ROWS, _NO_ROWS
        if len(segments):
            prune_s = len(segments) >= PRUNE_MIN_SEGMENTS if prune is None else prune
            seg_rows = _segment_rows(
                segments - (ox, oy, ox, oy), dirs_t, cap, prune_s, one_sided, extras
            )
        if len(circles):
            prune_c = len(circles) >= PRUNE_MIN_CIRCLES if prune is None else prune
            circ_rows, inv_root_c = _circle_rows(
                circles - (ox, oy, 0.0), dirs_t, cap, prune_c, extras
            )
        best = None
        if len(seg_rows) or len(circ_rows):
            best = self._nearest(seg_rows, circ_rows, inv_root_c, dirs_t)
        for extra in extras:
            best = extra if best is None else np.fmax(best, extra, out=best)
        if best is not None:
            # A miss left k <= 0 or NaN, a hit beyond the cap 0 < k < 1/cap: all read inf.
            np.reciprocal(best, out=t, where=best >= 1.0 / cap)
        return t

    def _nearest(
        self,
        seg_rows: NDArray[np.float64],
        circ_rows: NDArray[np.float64],
        inv_root_c: NDArray[np.float64],
        dirs_t: NDArray[np.float64],
    ) -> NDArray[np.float64]:
        """Per ray, the largest 1/t over all segments and circles: one product, one reduction.

        Block rows: W, V, K of the S segments, then b' of the C circles. K and the
        circles' 1/t end up side by side, so a single `fmax` over them finds the nearest.
        """
        n_s, n_c = len(seg_rows) // 3, len(circ_rows)
        rows = (
            np.concatenate([seg_rows, circ_rows]) if n_s and n_c else seg_rows if n_s else circ_rows
        )
        n_rows, n_rays = len(rows), dirs_t.shape[1]
        per_ray = n_rows + n_c  # the circles need one scratch row each
        step = max(1, min(n_rays, self.chunk_pairs // (n_s + n_c)))
        if self._buf.size < (per_ray + n_rows) * step:
            self._buf = np.empty((per_ray + n_rows) * step)
        tmp = self._buf[per_ray * step : (per_ray + n_rows) * step]
        best = np.empty(n_rays)
        with np.errstate(invalid="ignore"):
            for start in range(0, n_rays, step):
                stop = min(n_rays, start + step)
                n = stop - start
                block = self._buf[: n_rows * n].reshape(n_rows, n)
                # rows @ dirs_t as two products and a sum (BLAS: CPU-dependent bits)
                fmath.matmul_k(rows, dirs_t[:, start:stop], out=block, tmp=tmp[: n_rows * n])
                if n_s:
                    w, v, k = block[:n_s], block[n_s : 2 * n_s], block[2 * n_s : 3 * n_s]
                    np.minimum(w, v, out=w)  # >= 0 exactly when the ray crosses the segment
                    np.minimum(k, w, out=k)  # so a hit keeps its 1/t and a miss goes <= 0
                if n_c:
                    b = block[3 * n_s :]
                    root = self._buf[n_rows * n : per_ray * n].reshape(n_c, n)
                    np.multiply(b, b, out=root)
                    root -= 1.0
                    np.sqrt(root, out=root)  # NaN where the ray's line misses the circle
                    b += root
                    b *= inv_root_c  # 1/t of the near crossing; < 0 for a circle behind
                np.fmax.reduce(block[2 * n_s :], axis=0, out=best[start:stop])
        return best


_KERNEL_MISSING: list[str] = []


def _grid_caster() -> GridCaster | None:
    """A new grid caster, or None (with one warning per process) if numba is missing."""
    if _KERNEL_MISSING:
        return None
    try:
        raycast_kernel = importlib.import_module(f"{__package__}.raycast_kernel")
    except ImportError as err:
        _KERNEL_MISSING.append(str(err))
        warnings.warn(
            f"btnav's compiled lidar kernel is unavailable ({err}); casting with numpy"
            " (the same ranges, slower in big worlds)",
            stacklevel=3,
        )
        return None
    return raycast_kernel.GridCaster()


def _segment_rows(
    rel: NDArray[np.float64],
    dirs_t: NDArray[np.float64],
    max_range: float,
    prune: bool,
    one_sided: bool,
    extras: list[NDArray[np.float64]],
) -> NDArray[np.float64]:
    """The (3S, 2) W, V and K rows (in blocks of S) of the segments `rel` (relative to the
    origin); segments whose line passes the origin take the exact side path (`extras`)."""
    if prune:
        rel = _prune_segments(rel, max_range)
    if len(rel) == 0:
        return _NO_ROWS
    c = rel[:, 0] * rel[:, 3]
    c -= rel[:, 1] * rel[:, 2]  # a x e = p x q: zero when the line passes the origin
    if one_sided:
        # p x q > 0: the origin is on the inner side of a counter-clockwise solid's
        # edge, which faces away; a ray meets a nearer front edge of that solid first.
        front = c <= ON_LINE_AREA
        rel, c = rel[front], c[front]
        if len(rel) == 0:
            return _NO_ROWS
    if c.max() >= -ON_LINE_AREA if one_sided else np.abs(c).min() <= ON_LINE_AREA:
        on_line = np.abs(c) <= ON_LINE_AREA
        with np.errstate(divide="ignore"):
            extras.append(1.0 / _on_line_hits(rel[on_line], dirs_t.T))
        rel, c = rel[~on_line], c[~on_line]
        if len(rel) == 0:
            return _NO_ROWS
    coef = fmath.matmul_k(rel, _ROWS)
    coef /= c[:, None]
    return np.ascontiguousarray(coef.reshape(len(rel), 3, 2).swapaxes(0, 1)).reshape(-1, 2)


def _circle_rows(
    rel: NDArray[np.float64],
    dirs_t: NDArray[np.float64],
    max_range: float,
    prune: bool,
    extras: list[NDArray[np.float64]],
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The (C, 2) rows m / sqrt(c) of the circles `rel` (centres relative to the origin)
    and the (C, 1) factors 1 / sqrt(c); circles around the origin take the side path."""
    c = fmath.dot_rows(rel * rel, _CIRCLE_C)  # |m|^2 - r^2: <= 0 with the origin inside
    if prune:
        keep = c <= max_range * (max_range + 2.0 * rel[:, 2])  # |m| - r <= max_range
        rel, c = rel[keep], c[keep]
    if len(c) == 0:
        return _NO_ROWS, _NO_ROWS
    if c.min() <= 0:
        inside = c <= 0
        # The sensor inside a pillar: t = b + sqrt(b^2 - c), where the ray gets out.
        b = fmath.matmul_k(rel[inside, :2], dirs_t)
        with np.errstate(divide="ignore"):  # on the boundary, going out: t = 0
            extras.append((1.0 / (b + np.sqrt(b * b - c[inside][:, None]))).max(axis=0))
        rel, c = rel[~inside], c[~inside]
        if len(c) == 0:
            return _NO_ROWS, _NO_ROWS
    root_c = np.sqrt(c)[:, None]
    return rel[:, :2] / root_c, 1.0 / root_c


def cast(
    geometry: Geometry,
    origin: ArrayLike,
    dirs: NDArray[np.float64],
    max_range: float = math.inf,
    *,
    prune: bool | None = None,
) -> NDArray[np.float64]:
    """Distance along each ray (from `origin`, unit `dirs` (B, 2), world frame) to the
    nearest solid of `geometry`; `inf` for rays with no hit within `max_range`.

    A one-off call; a sensor that casts every scan keeps a `RayCaster` instead.
    """
    return RayCaster().cast(geometry, origin, dirs, max_range, prune=prune)


def cast_segments(
    origin: ArrayLike,
    dirs: NDArray[np.float64],
    segments: NDArray[np.float64],
    max_range: float = math.inf,
    *,
    prune: bool | None = None,
) -> NDArray[np.float64]:
    """Distance along each ray to the nearest of (S, 4) segments x1, y1, x2, y2.

    Hits beyond `max_range` read `inf`; with `prune` (default: when there are many
    segments) segments wholly beyond it are dropped before the S x B block.
    """
    return RayCaster().cast_segments(origin, dirs, segments, max_range, prune=prune)


def cast_circles(
    origin: ArrayLike,
    dirs: NDArray[np.float64],
    circles: NDArray[np.float64],
    max_range: float = math.inf,
) -> NDArray[np.float64]:
    """Distance along each ray to the nearest of (M, 3) circles cx, cy, r.

    A ray starting inside a circle hits its boundary on the way out, as a ray inside a
    polygon hits its edges: a solid the sensor is buried in is still seen.
    """
    return RayCaster().cast_circles(origin, dirs, circles, max_range)


def cast_from_pose(
    geometry: Geometry,
    pose: ArrayLike,
    angles: ArrayLike,
    max_range: float = math.inf,
) -> NDArray[np.float64]:
    """Ranges of beams at `angles` (radians, in the frame of `pose` = x, y, yaw)."""
    x, y, yaw = (float(v) for v in np.asarray(pose, dtype=float)[:3])
    return cast(geometry, (x, y), beam_directions(np.asarray(angles, dtype=float) + yaw), max_range)
