"""PathAlignCritic's scoring compiled: one pass over the sampled rollout points, with the
numpy path's float32 bits.

The numpy path (`PathAlignCritic.score` after its gates) builds a dozen (K - 1, B)
temporaries: the strided points, their segment lengths and running sums, the arc-length
lookup, the gathered path points, the distances, the masks and the sums (0.26 ms at
2000 x 56; the rest of the critic's 1.05 ms was `CriticData.furthest_reached_path_point`,
compiled on its own in furthest_point_kernel.py). Here each sampled step is two loops over the batch:
the running length and its lookup bin (no branch: vectorised), then the path point, the
distance, the total and the count per rollout (0.09 ms in all).

Same bits as numpy (float32 operands only, no float64 literal meets them):

- segment lengths as fmath.hypot on float32 arrays: sqrt(dx*dx + dy*dy), the sum
  rounded to float32 before the (exact) float32 sqrt; the travelled distance adds each
  segment to the previous running value, as numpy's row loop does;
- the path point: `nearest_by_arc_length`'s table (built once in numpy by
  `arc_length_table`) read at int32(s * float32(1 / ds) + 0.5), capped at LOOKUP_BINS;
- the distance: hypot as above, or sqrt((dx*dx + dy*dy) + dyaw*dyaw) with
  use_path_orientations, dyaw as `angles.abs_angle_diff` (np.mod's fmod moved into
  [0, 2 pi), then min(d, 2 pi - d) with np.minimum's NaN rule);
- numpy sums axis 0 of a C-ordered (K - 1, B) array row after row (each step added to
  the running total in step order, no pairwise blocks: the reduced axis is the outer
  one), and a masked point adds numpy's +0.0, which leaves a total unchanged: so only
  valid points are added here, in step order;
- the mean: the float32 total divided by the integer count in float64 (numpy promotes
  float32 / intp to float64), then rounded to float32.

Determinism (issue 37): no libm transcendental (fmod and sqrt are exact), no fastmath
(no FMA contraction), no parallel loop; compiled once per install (`cache=True`).
"""

from __future__ import annotations

import numba as nb
import numpy as np
from numpy.typing import NDArray

from ...core.fmath_kernels import JIT
from .rollout_kernel import np_minimum

F32 = NDArray[np.float32]

_TWO_PI = np.float32(2 * np.pi)  # angles._TWO_PI


@nb.njit(**JIT)
def _abs_angle_diff(a: np.float32, b: np.float32) -> np.float32:
    """`angles.abs_angle_diff` on two float32 angles: |np.mod(a - b, 2 pi)|, then the
    shorter way round. np.mod by a positive divisor is fmod plus the divisor when fmod
    is negative (its signed zero is lost to the abs)."""
    two_pi = np.float32(_TWO_PI)
    d = np.fmod(a - b, two_pi)
    if d < 0:
        d = d + two_pi
    d = np.abs(d)
    return np_minimum(d, two_pi - d)


@nb.njit(**JIT)
def path_align_costs(
    xt: F32,
    yt: F32,
    yawt: F32,
    step: int,
    path: F32,
    valid: NDArray[np.bool_],
    table: NDArray[np.intp],
    inv_ds: np.float32,
    use_orientations: bool,
    out: F32,
) -> None:
    """Per rollout, the mean distance from every `step`-th point after the first to the
    path point at the same travelled distance, skipping path points not `valid` (0 where
    none counts); written into `out` (B,).

    xt, yt, yawt: (T, B) time-major rollout views (`data.x.T`, ...); path: the reached
    part of the path, (P, 3); table, inv_ds: `arc_length_table` of its lengths (inv_ds
    0: a path of no length, every point compares with the first path point).
    """
    T, B = xt.shape[0], xt.shape[1]
    half = np.float32(0.5)
    zero = np.float32(0.0)
    top = table.shape[0] - 1
    run = np.zeros(B, np.float32)
    total = np.zeros(B, np.float32)
    count = np.zeros(B, np.int64)
    bins = np.zeros(B, np.int32)
    prev = 0
    for t in range(step, T, step):
        # the running length and its lookup bin: no branch, LLVM vectorises it
        for b in range(B):
            sx, sy = xt[t, b] - xt[prev, b], yt[t, b] - yt[prev, b]
            s = run[b] + np.sqrt(sx * sx + sy * sy)  # 0 + first segment: the segment
            run[b] = s
            bins[b] = min(np.int32(s * inv_ds + half), top)
        for b in range(B):
            i = table[bins[b]] if inv_ds != zero else 0
            if valid[i]:
                dx, dy = xt[t, b] - path[i, 0], yt[t, b] - path[i, 1]
                dd = dx * dx + dy * dy
                if use_orientations:
                    dyaw = _abs_angle_diff(yawt[t, b], path[i, 2])
                    dd = dd + dyaw * dyaw
                total[b] = total[b] + np.sqrt(dd)
                count[b] += 1
        prev = t
    for b in range(B):
        n = count[b]
        out[b] = np.float32(np.float64(total[b]) / np.float64(n)) if n > 0 else zero


def arc_length_table(path_s: F32, bins: int) -> tuple[NDArray[np.intp], np.float32]:
    """`nearest_by_arc_length`'s lookup: per uniform bin of the path's length, the index
    of the path point nearest the bin's distance, and float32(1 / bin width); a path of
    no length gives a one-entry table and 0."""
    n = len(path_s)
    length = float(path_s[-1])
    if length <= 0.0:
        return np.zeros(1, np.intp), np.float32(0.0)
    ds = length / bins
    grid = np.arange(bins + 1, dtype=np.float64) * ds
    hi = np.minimum(np.maximum(np.searchsorted(path_s, grid), 1), n - 1)  # np.clip: ~20 us more
    lo = hi - 1
    table = np.where(grid - path_s[lo] < path_s[hi] - grid, lo, hi)
    return table, np.float32(1.0 / ds)
