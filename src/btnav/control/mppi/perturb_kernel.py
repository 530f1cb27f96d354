"""MPPI's sampled controls compiled: the pool's noise, scaled and signed, plus the
control sequence, written in one pass (numpy: a multiply per channel into the controls,
then an add of the sequence over the whole (T, C, B) block; ~0.5 ms at 2000 x 56).

The same bits: u = noise * scale, then u + sequence, each a float32 operation as
numpy's (`scale` is numpy's own float32 product sign * std, made by the noise
generator for both paths). No libm call, no fastmath, no parallel; `cache=True`.
"""

from __future__ import annotations

import numba as nb
import numpy as np
from numpy.typing import NDArray

from ...core.fmath_kernels import JIT

F32 = NDArray[np.float32]


@nb.njit(**JIT)
def perturb(pool: F32, starts: NDArray[np.int64], scale: F32, sequence: F32, out: F32) -> None:
    """out[t, ch, b] = pool[ch, t, starts[ch] + b] * scale[ch, b] + sequence[t, ch].

    pool: (C, T, P) N(0, 1) draws; scale: (C, B); sequence: (T, C); out: (T, C, B)."""
    T, C, B = out.shape
    for t in range(T):
        for ch in range(C):
            noise = pool[ch, t, starts[ch] : starts[ch] + B]
            row = scale[ch]
            seq = sequence[t, ch]
            dst = out[t, ch]
            for b in range(B):
                dst[b] = noise[b] * row[b] + seq
