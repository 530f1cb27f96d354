"""The optimal sequence's velocity and acceleration limits compiled (Nav2's
applyControlSequenceConstraints): a Python loop of 56 steps per channel cost ~0.15 ms
a cycle, for a dozen float operations a step.

The same bits as `Optimizer._apply_sequence_constraints`' Python loop: float64 (the
loop's Python floats) with Python's `min` and `max` (the first argument unless the
second is strictly beyond it, so a NaN stays where Python keeps it), `clamp_by_accel`'s
branches, the result rounded to float32 at every step as the loop rounds it.
"""

from __future__ import annotations

import numba as nb
import numpy as np
from numpy.typing import NDArray

from ...core.fmath_kernels import JIT


@nb.njit(inline="always", **JIT)
def _py_max(a: float, b: float) -> float:
    return b if b > a else a


@nb.njit(inline="always", **JIT)
def _py_min(a: float, b: float) -> float:
    return b if b < a else a


@nb.njit(**JIT)
def limit_sequence(
    column: NDArray[np.float32],
    last: float,
    lo: float,
    hi: float,
    a_down: float,
    a_up: float,
    first_dt: float,
    dt: float,
) -> None:
    """One channel of the sequence in place: each step within [lo, hi], then within
    a_down * dt .. a_up * dt of the step before (of `last`, the speed now, for the first
    step, over `first_dt`), speeding up and slowing down as `clamp_by_accel` does."""
    step = first_dt
    for i in range(column.shape[0]):
        value = _py_min(hi, _py_max(np.float64(column[i]), lo))
        min_delta, max_delta = a_down * step, a_up * step
        if last >= 0.0:
            r = _py_min(last + max_delta, _py_max(value, last + min_delta))
        else:
            r = _py_min(last - min_delta, _py_max(value, last - max_delta))
        column[i] = np.float32(r)
        last = np.float64(column[i])
        step = dt
