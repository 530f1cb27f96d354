"""Cartographer's 2D scan matchers against a submap, and the voxel filters that feed them.

- `real_time_correlative_match` (RealTimeCorrelativeScanMatcher2D, Olson's real-time
  correlative matching): every candidate of a small window around the prediction,
  scored by the mean probability of the cells its points fall in, times
  exp(-(|dt| translation_delta_cost_weight + |dtheta| rotation_delta_cost_weight)^2).
  The angular step is the one that moves the farthest point by about one cell.
- `ceres_match` (CeresScanMatcher2D): Ceres's least-squares cost, the points on the
  submap's bicubic (Catmull-Rom, as ceres::BiCubicInterpolator) probability surface,
  pulled towards a target translation and the initial heading. Minimised by damped
  Newton with the exact Hessian (Gauss-Newton, Ceres's method, oscillates on this
  curved surface: ~20 steps where Newton takes 2 or 3); 3 x 3 systems solved by hand.

The loop-closure search (FastCorrelativeScanMatcher2D) is `fast_correlative_matcher.py`.

Candidates are scored as whole arrays (points x candidates, integer sums of grid
values); trigonometry is `fmath`; no BLAS.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from ...core import fmath
from .options import AdaptiveVoxelFilter, CeresScanMatcher, RealTimeCorrelativeScanMatcher
from .submaps import MAX_VALUE, MIN_PROBABILITY, Submap

F64 = NDArray[np.float64]
I64 = NDArray[np.int64]
_SPAN = 1.0 - 2.0 * MIN_PROBABILITY  # probability spread of the cell values


# -- point clouds -----------------------------------------------------------------------


def voxel_filter(points: F64, size: float) -> F64:
    """One point per `size` square (the first of each, in scan order): Cartographer's VoxelFilter."""
    if len(points) == 0 or size <= 0.0:
        return points
    k = np.floor(points / size).astype(np.int64) + (1 << 30)
    _, first = np.unique(k[:, 0] * (1 << 31) + k[:, 1], return_index=True)
    return points[np.sort(first)]


def adaptive_voxel_filter(points: F64, options: AdaptiveVoxelFilter) -> F64:
    """Cartographer's AdaptiveVoxelFilter: the coarsest voxel (at most `max_length`) that
    leaves at least `min_num_points`, found by halving then bisecting to 10%."""
    max_length, min_num_points = options.max_length, options.min_num_points
    points = points[(points * points).sum(axis=1) <= options.max_range**2]
    if len(points) <= min_num_points:
        return points
    result = voxel_filter(points, max_length)
    if len(result) >= min_num_points:
        return result
    high = max_length
    while high > 1e-2 * max_length:  # a handful of voxel sizes, each one vectorised pass
        low = high / 2.0
        result = voxel_filter(points, low)
        if len(result) >= min_num_points:
            while (high - low) / low > 1e-1:
                mid = (low + high) / 2.0
                candidate = voxel_filter(points, mid)
                if len(candidate) >= min_num_points:
                    low, result = mid, candidate
                else:
                    high = mid
            return result
        high /= 2.0
    return result


def angular_step(points: F64, resolution: float) -> float:
    """The heading step that moves the farthest point (at least 3 cells out) by about a cell."""
    far = max(
        3.0 * resolution,
        float(np.sqrt((points * points).sum(axis=1).max())) if len(points) else 0.0,
    )
    s = resolution / (2.0 * far)  # acos(1 - r^2 / (2 d^2)) = 2 asin(r / (2 d))
    return (1.0 - 1e-3) * 2.0 * float(fmath.arctan2(s, math.sqrt(1.0 - s * s)))


def _headings(centre: float, window: float, step: float) -> F64:
    n = math.ceil(window / step)
    return centre + step * np.arange(-n, n + 1)


def _point_cells(submap: Submap, points: F64, pose_xy: F64, angles: F64) -> tuple[I64, I64]:
    """(A, N) lattice cells of the points turned to each heading and moved to `pose_xy`."""
    s, c = fmath.sincos(angles)
    s, c = s[:, None], c[:, None]
    x, y = points[:, 0][None, :], points[:, 1][None, :]
    lat = submap.lattice
    inv = 1.0 / lat.resolution
    # in place, these steps: ((c x - s y + pose x) - lattice x0) inv + 0.5, floored
    v, t = c * x, s * y
    v -= t
    v += pose_xy[0]
    v -= lat.x0
    v *= inv
    v += 0.5
    cols = np.floor(v, out=v).astype(np.int64)
    np.multiply(s, x, out=v)
    v += np.multiply(c, y, out=t)
    v += pose_xy[1]
    v -= lat.y0
    v *= inv
    v += 0.5
    rows = np.floor(v, out=v).astype(np.int64)
    return rows, cols


def _mean_probability(sums: NDArray[np.integer], n: int) -> F64:
    """Mean probability of n cells from the sum of their (unknown-as-1) values."""
    return MIN_PROBABILITY + (sums / n - 1.0) * (_SPAN / (MAX_VALUE - 1))


# -- local SLAM ----------------------------------------------------------------------------


def real_time_correlative_match(
    submap: Submap, points: F64, prediction: F64, options: RealTimeCorrelativeScanMatcher
) -> tuple[F64, float]:
    """The best candidate around `prediction` (local frame) and its score: the first in
    (heading, row, column) order among equals.

    The window's offsets go in blocks of up to 5 x 5 (one block for Cartographer's 0.1 m
    window at 5 cm cells), and every (heading, block) is bounded first: the points'
    maxima over the block (`_window_max` over the part of the grid the scan covers: one
    lookup a point, not one per offset) give a sum no offset in it exceeds, times the
    block's best cost factor. The best-bounded blocks are scored, then every block whose
    bound reaches the best score so far; the others cannot hold the best candidate (nor
    tie it)."""
    res = submap.lattice.resolution
    angles = _headings(
        float(prediction[2]), options.angular_search_window, angular_step(points, res)
    )
    n = math.ceil(options.linear_search_window / res)
    size = 2 * n + 1
    grid, r0, c0 = submap.scoring(max(size, 4))
    rows, cols = _point_cells(submap, points, prediction[:2], angles)
    h, w = grid.shape
    top = np.minimum(np.maximum(rows - n - r0, 0), h - size)
    left = np.minimum(np.maximum(cols - n - c0, 0), w - size)
    base = (top * w + left).astype(np.int32)  # (A, N)
    offsets = (np.arange(size) - n) * res
    dist = fmath.hypot(offsets[:, None], offsets[None, :])
    turn = np.abs(angles - prediction[2])
    cost = (
        dist[None, :, :] * options.translation_delta_cost_weight
        + turn[:, None, None] * options.rotation_delta_cost_weight
    )
    weight = fmath.exp(-(cost * cost))  # (A, dy, dx)
    score = np.full(weight.shape, -np.inf)
    # blocks: (heading, block row, block column), flat
    side = min(size, _BLOCK)
    nb = -(-size // side)
    edge = nb * side  # the blocks' extent, past the window by up to side - 1
    t0, l0 = int(top.min()), int(left.min())
    region = grid[t0 : int(top.max()) + edge, l0 : int(left.max()) + edge]
    want = (int(top.max()) - t0 + edge, int(left.max()) - l0 + edge)
    if region.shape != want:  # the last blocks reach past the grid: those cells read 0
        region = np.pad(region, [(0, want[0] - region.shape[0]), (0, want[1] - region.shape[1])])  # fmt: skip
    peak = _window_max(region, side)
    corner = (np.arange(nb) * side)[:, None] * peak.shape[1] + np.arange(nb) * side
    at = ((top - t0) * peak.shape[1] + (left - l0))[:, None, :] + corner.reshape(-1, 1)
    sums = np.take(peak.reshape(-1), at).sum(axis=-1, dtype=np.int32)  # (A, blocks)
    padded = np.full((len(angles), edge, edge), -np.inf)
    padded[:, :size, :size] = weight
    best_weight = padded.reshape(len(angles), nb, side, nb, side).max(axis=(2, 4))
    bound = (_mean_probability(sums.reshape(len(angles), -1), len(points)) * best_weight.reshape(len(angles), -1)).ravel()  # fmt: skip
    flat = grid.reshape(-1)

    def evaluate(pick: I64) -> None:
        heading, block = pick // (nb * nb), pick % (nb * nb)
        oy = (block // nb * side)[:, None] + np.arange(side)  # (K, side) window rows
        ox = (block % nb * side)[:, None] + np.arange(side)
        # offsets past the window read its last row or column and are not kept
        cy, cx = np.minimum(oy, size - 1), np.minimum(ox, size - 1)
        got = _score_blocks(base[heading], flat, w, cy, cx)  # (K, side, side)
        k, i, j = np.nonzero((oy < size)[:, :, None] & (ox < size)[:, None, :])
        a, y, x = heading[k], oy[k, i], ox[k, j]
        score[a, y, x] = got[k, i, j] * weight[a, y, x]

    first = np.sort(np.argsort(-bound, kind="stable")[:_FIRST_BLOCKS])
    evaluate(first)
    rest = bound >= score.max()
    rest[first] = False
    if rest.any():
        evaluate(np.flatnonzero(rest))
    a, i, j = np.unravel_index(int(np.argmax(score)), score.shape)
    pose = np.array([prediction[0] + offsets[j], prediction[1] + offsets[i], angles[a]])
    return pose, float(score[a, i, j])


def _score_blocks(base: NDArray[np.int32], flat: NDArray[np.uint16], w: int, oy: I64, ox: I64) -> F64:  # fmt: skip
    """Mean probabilities (K, rows, columns) of K blocks: the cells at window rows
    oy[k] and columns ox[k] from each point's `base[k]` index in the flat grid `w` wide."""
    k, side = oy.shape
    sums = np.empty((side, side, k), np.int32)  # (dy, dx, K): below 2^31
    for dy in range(side):  # temporaries of a few hundred kB, not 25 x K x N
        shift = (oy[:, dy] * w)[None, :, None] + ox.T[:, :, None]  # (dx, K, 1)
        sums[dy] = np.take(flat, base + shift.astype(np.int32)).sum(axis=2, dtype=np.int32)
    return _mean_probability(sums.transpose(2, 0, 1), base.shape[1])


def _window_max(grid: NDArray[np.uint16], size: int) -> NDArray[np.uint16]:
    """The maximum over each size x size window inside `grid`, at the window's first
    cell: (rows - size + 1, cols - size + 1). Windows doubled (log2 size passes an axis),
    the last two overlapping."""
    out = grid
    for axis in (0, 1):
        m = np.moveaxis(out, axis, 0)
        width, p = 1, m
        while 2 * width <= size:
            p = np.maximum(p[:-width], p[width:])
            width *= 2
        keep = m.shape[0] - size + 1
        out = np.moveaxis(np.maximum(p[:keep], p[size - width : size - width + keep]), 0, axis)
    return out


#: The real-time matcher's blocks of offsets: up to this many cells a side.
_BLOCK = 5
#: Blocks the real-time matcher scores first (the highest bounds), for a best score that
#: rules out the others.
_FIRST_BLOCKS = 4


#: Catmull-Rom weights of samples -1, 0, 1, 2 as cubics in t (rows: t^0, t^1, t^2, t^3).
_CUBIC = np.array(
    [[0.0, 1.0, 0.0, 0.0], [-0.5, 0.0, 0.5, 0.0], [1.0, -2.5, 2.0, -0.5], [-0.5, 1.5, -1.5, 0.5]]
)
_PROBABILITY_STEP = _SPAN / (MAX_VALUE - 1)


def _bicubic(submap: Submap, x: F64, y: F64) -> tuple[F64, F64]:
    """Probability at points (x, y) and its derivatives per metre (x, y, xx, xy, yy; rows
    of a (5, N) array): Catmull-Rom in both axes (ceres::BiCubicInterpolator's kernel);
    off the grid it is 0.1 and flat. Arrays are laid out (..., N) so every sum runs over
    rows (in the same order, one multiply-and-sum for all the weights at once)."""
    grid, r0, c0 = submap.scoring(4)
    lat = submap.lattice
    inv = 1.0 / lat.resolution
    # cell centres at whole numbers, counted from 4 cells outside the grid (the border
    # scoring guarantees; it may be wider: the lookups are moved into it after)
    b0, a0 = submap.row0 - 4, submap.col0 - 4
    u = (x - lat.x0) * inv - a0
    v = (y - lat.y0) * inv - b0
    j, i = np.floor(u), np.floor(v)
    tu, tv = u - j, v - i
    h, w = grid.shape
    top = np.minimum(np.maximum(i.astype(np.int64) - 1, 0), h - 2 * (b0 - r0) - 4) + (b0 - r0)
    left = np.minimum(np.maximum(j.astype(np.int64) - 1, 0), w - 2 * (a0 - c0) - 4) + (a0 - c0)
    flat = _NEIGHBOURS[w] if w in _NEIGHBOURS else _NEIGHBOURS.setdefault(w, (np.arange(4)[:, None] * w + np.arange(4)).reshape(16, 1))  # fmt: skip
    f = grid.reshape(-1)[flat + (top * w + left)] * _PROBABILITY_STEP
    f = f.reshape(4, 4, -1)  # (row, col, N), less a constant that the weights sum away
    k0, k1, k2, k3 = _CUBIC[:, :, None]
    # the weights of the columns (u) and rows (v): value, first and second derivative
    wu = np.empty((3, 4, len(x)))
    wv = np.empty((3, 4, len(x)))
    for t, out in ((tu, wu), (tv, wv)):
        out[0] = k0 + t * (k1 + t * (k2 + t * k3))
        out[1] = k1 + t * (2.0 * k2 + 3.0 * t * k3)
        out[2] = 2.0 * k2 + 6.0 * t * k3
    fu = (f[None] * wu[:, None]).sum(axis=2)  # (3, 4, N): each row interpolated in x
    # value, d/dx, d/dy, d2/dx2, d2/dxdy, d2/dy2
    m = (fu[_ROWS_U] * wv[_ROWS_V]).sum(axis=1)
    base = MIN_PROBABILITY - _PROBABILITY_STEP  # value 1 is probability 0.1
    inv2 = inv * inv
    grads = np.empty((5, len(x)))
    grads[:2] = m[1:3] * inv
    grads[2:] = m[3:] * inv2
    return m[0] + base, grads


#: Which x-weights (value, first, second derivative) and y-weights make the value and
#: each derivative of the bicubic surface.
_ROWS_U, _ROWS_V = np.array([0, 1, 0, 2, 1, 0]), np.array([0, 0, 1, 0, 1, 2])


_NEIGHBOURS: dict[int, I64] = {}


def ceres_match(
    submap: Submap, points: F64, target_xy: F64, initial: F64, w: CeresScanMatcher
) -> F64:
    """The pose (local frame) minimising Ceres's cost: sum over points of
    (occupied_space_weight / sqrt(N) (1 - P))^2 plus the weighted squared distance to
    `target_xy` and to `initial`'s heading. Minimised by damped Newton on the exact
    Hessian of the bicubic surface (Gauss-Newton, Ceres's choice, oscillates on a surface
    this curved and needs its 20 iterations); stops at Ceres's function tolerance."""
    if len(points) == 0:
        return np.asarray(initial, float).copy()
    a = w.occupied_space_weight / math.sqrt(len(points))
    target = np.array([float(target_xy[0]), float(target_xy[1]), float(initial[2])])
    pw = np.array([w.translation_weight, w.translation_weight, w.rotation_weight])
    px, py = points[:, 0], points[:, 1]
    prior_hess = np.diag(pw * pw)

    def evaluate(x: F64) -> tuple[float, F64, F64]:
        s, c = fmath.sincos(float(x[2]))
        rx, ry = c * px - s * py, s * px + c * py  # the points turned, before the shift
        p, (gx, gy, gxx, gxy, gyy) = _bicubic(submap, rx + x[0], ry + x[1])
        r = a * (1.0 - p)
        prior = pw * (x - target)
        cost = float((r * r).sum()) + float((prior * prior).sum())
        tx, ty = -ry, rx  # d(point)/d(theta)
        jac = np.empty((3, len(r)))
        jac[0], jac[1], jac[2] = -a * gx, -a * gy, -a * (gx * tx + gy * ty)
        # r d2r: -a r times the second derivative of P along the pose's parameters
        second = np.empty((6, len(r)))  # the Hessian's upper triangle, row by row
        second[0], second[1], second[3] = gxx, gxy, gyy
        second[2], second[4] = gxx * tx + gxy * ty, gxy * tx + gyy * ty
        second[5] = gxx * tx * tx + 2.0 * gxy * tx * ty + gyy * ty * ty - gx * rx - gy * ry
        terms = jac[_UPPER_K] * jac[_UPPER_M]
        terms += (-a * r) * second
        upper = terms.sum(axis=1)
        hess = upper[_SYMMETRIC] + prior_hess
        grad = (jac * r).sum(axis=1) + prior * pw
        return cost, hess, grad

    x = np.asarray(initial, float).copy()
    cost, hess, grad = evaluate(x)
    mu = 0.0
    for _ in range(w.max_num_iterations):
        damped = hess.copy()  # hess + mu diag(|diag(hess)|)
        damped[_K3, _K3] += mu * np.abs(hess[_K3, _K3])
        step = _solve3(damped, -grad)
        if step is None:
            mu = max(10.0 * mu, 1e-3)
            continue
        trial = evaluate(x + step)  # the derivatives come with the cost: no extra pass
        if trial[0] < cost:
            done = cost - trial[0] <= 1e-6 * cost
            x = x + step
            cost, hess, grad = trial
            mu = mu / 10.0 if mu > 1e-6 else 0.0
            if done:
                break
        else:
            mu = max(10.0 * mu, 1e-3)
    return x


#: The Hessian's upper triangle (0,0) (0,1) (0,2) (1,1) (1,2) (2,2), and the full 3 x 3
#: from it.
_UPPER_K, _UPPER_M = np.array([0, 0, 0, 1, 1, 2]), np.array([0, 1, 2, 1, 2, 2])
_SYMMETRIC = np.array([[0, 1, 2], [1, 3, 4], [2, 4, 5]])
_K3 = np.arange(3)


def _solve3(m: F64, b: F64) -> F64 | None:
    """m x = b for a symmetric 3 x 3 m by Cholesky in Python floats; None if m is not
    positive definite."""
    a = m.tolist()
    if a[0][0] <= 0.0:
        return None
    l00 = math.sqrt(a[0][0])
    l10, l20 = a[1][0] / l00, a[2][0] / l00
    d1 = a[1][1] - l10 * l10
    if d1 <= 0.0:
        return None
    l11 = math.sqrt(d1)
    l21 = (a[2][1] - l20 * l10) / l11
    d2 = a[2][2] - l20 * l20 - l21 * l21
    if d2 <= 0.0:
        return None
    l22 = math.sqrt(d2)
    y0 = b[0] / l00
    y1 = (b[1] - l10 * y0) / l11
    y2 = (b[2] - l20 * y0 - l21 * y1) / l22
    x2 = y2 / l22
    x1 = (y1 - l21 * x2) / l11
    x0 = (y0 - l10 * x1 - l20 * x2) / l00
    return np.array([x0, x1, x2])
