"""numpy's float32 summation order, written out for the kernels that must match `np.sum`.

numpy sums a contiguous run (the reduced axis is the innermost one) pairwise: under
8 values left to right from 0; up to 128 in 8 interleaved accumulators (a[0..7], then
a[8..15] added to them, ...) joined as ((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7)),
the tail added after; above 128 split at n // 2 rounded down to a multiple of 8, each
half summed so and the halves added. The reduction starts from its identity, so the
result is 0 + that (a -0 sum comes out +0). This is numpy's order up to 8192 values
(numpy's buffer size; numpy 2.2 and later differ from older numpy above it), which is
the order these kernels keep whatever numpy does: the MPPI sums are 2000 long.

A sum over a strided axis (the batch contiguous, time across rows) numpy adds row by
row, left to right from 0: the kernels do that with a plain loop, no helper needed.
"""

from __future__ import annotations

import numba as nb
import numpy as np
from numpy.typing import NDArray

from ...core.fmath_kernels import JIT

#: numpy's PW_BLOCKSIZE: runs up to this long are summed in 8 accumulators.
BLOCK = 128


@nb.njit(**JIT)
def _block(a: NDArray[np.float32], lo: int, n: int) -> np.float32:
    """numpy's sum of a[lo:lo + n], n <= BLOCK: left to right under 8, else 8 accumulators."""
    if n < 8:
        res = np.float32(0.0)
        for i in range(lo, lo + n):
            res += a[i]
        return res
    r0, r1, r2, r3 = a[lo], a[lo + 1], a[lo + 2], a[lo + 3]
    r4, r5, r6, r7 = a[lo + 4], a[lo + 5], a[lo + 6], a[lo + 7]
    i = 8
    while i < n - n % 8:
        j = lo + i
        r0 += a[j]
        r1 += a[j + 1]
        r2 += a[j + 2]
        r3 += a[j + 3]
        r4 += a[j + 4]
        r5 += a[j + 5]
        r6 += a[j + 6]
        r7 += a[j + 7]
        i += 8
    res = ((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))
    while i < n:
        res += a[lo + i]
        i += 1
    return res


@nb.njit(**JIT)
def pairwise_sum(a: NDArray[np.float32]) -> np.float32:
    """`np.sum` of a 1-D float32 array (any stride) in numpy's pairwise order.

    numpy recurses; here the same tree is walked with a small stack (numba's cached
    kernels cannot call a recursive one): a range is split, its halves summed left
    then right, then added, so every addition is numpy's, in its order."""
    depth = 64  # ranges pending: 2 per level of a tree at most 2**40 values deep
    los = np.empty(depth, np.int64)
    ns = np.empty(depth, np.int64)
    joins = np.empty(depth, np.bool_)
    sums = np.empty(depth, np.float32)
    los[0], ns[0], joins[0] = 0, a.shape[0], False
    top, done = 1, 0
    while top > 0:
        top -= 1
        lo, n = los[top], ns[top]
        if joins[top]:  # both halves summed: add them
            done -= 1
            sums[done - 1] = sums[done - 1] + sums[done]
        elif n <= BLOCK:
            sums[done] = _block(a, lo, n)
            done += 1
        else:
            n2 = n // 2
            n2 -= n2 % 8
            los[top], ns[top], joins[top] = lo, n, True
            los[top + 1], ns[top + 1], joins[top + 1] = lo + n2, n - n2, False
            los[top + 2], ns[top + 2], joins[top + 2] = lo, n2, False
            top += 3
    return np.float32(0.0) + sums[0]
