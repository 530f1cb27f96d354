"""core.fmath's scalar functions as numba kernels: the same IEEE steps, the same bits.

A compiled loop (Hybrid-A*'s search, Reeds-Shepp's words, later MPPI's rollouts) cannot
call core.fmath: its scalar path is Python (~1.5 us a call) and its array path numpy.
These are `fmath._sincos_py`, `_atan2_py`, `_exp_py` and `_log_py` written again for
numba, step for step (and `sincos_f32`, the float32 path of `fmath._sincos_vec`): every + - * / in the same order, the same constants (read from
fmath, not repeated), bits reinterpreted where fmath reinterprets them. So each returns
the bits fmath returns on a Python float (tests/core/test_fmath_kernels.py compares them
on random values over every range and on zeros, infinities, NaN, subnormals and
multiples of pi/2).

One more scalar function whose bits compiled code must match, though it is not
fmath's: `remainder` is numpy's float `np.mod` (fmod, then the divisor's sign), which
the curves' angle wrapping uses.

Determinism (issue 37): no libm transcendental (fmod and sqrt are exact IEEE
operations), no fastmath (LLVM never contracts a*b + c into an FMA), no parallel;
`error_model="numpy"` so a division by zero is inf, as in Python's fmath steps (which
never divide by zero).
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from llvmlite import ir
from numba import types
from numba.extending import intrinsic

from . import fmath as _f

__all__ = ["arctan2", "exp", "log", "remainder", "sincos", "sincos_f32", "sincos_steps"]

JIT = {"cache": True, "nogil": True, "error_model": "numpy", "boundscheck": False}

# fmath's constants, bound here as globals numba freezes into the machine code
_MAGIC, _MAGIC_BITS = _f._MAGIC, _f._MAGIC_BITS
_TWO_OVER_PI, _PIO2_1, _PIO2_2, _PIO2_2T = _f._TWO_OVER_PI, _f._PIO2_1, _f._PIO2_2, _f._PIO2_2T
_PIO2_2F = _f._PIO2_2F
_S1, _S2, _S3, _S4, _S5, _S6 = _f._S1, _f._S2, _f._S3, _f._S4, _f._S5, _f._S6
_C1, _C2, _C3, _C4, _C5, _C6 = _f._C1, _f._C2, _f._C3, _f._C4, _f._C5, _f._C6
_INV_LN2, _LN2_HI, _LN2_LO = _f._INV_LN2, _f._LN2_HI, _f._LN2_LO
_P1, _P2, _P3, _P4, _P5 = _f._P1, _f._P2, _f._P3, _f._P4, _f._P5
_EXP_LO, _EXP_HI = _f._EXP_LO, _f._EXP_HI
_LG0, _LG1, _LG2, _LG3, _LG4, _LG5, _LG6 = _f._LG
_LOG_SHIFT, _SQRT_HALF_BITS, _MANT_MASK = _f._LOG_SHIFT, _f._SQRT_HALF_BITS, _f._MANT_MASK
_EXP_FLOAT_BITS, _K_BIAS, _TINY, _TWO54 = _f._EXP_FLOAT_BITS, _f._K_BIAS, _f._TINY, _f._TWO54
_AT0, _AT1, _AT2, _AT3, _AT4, _AT5, _AT6, _AT7, _AT8, _AT9, _AT10 = _f._AT
_TAN_PI_8, _PIO4_HI, _PIO4_LO, _TINIEST = _f._TAN_PI_8, _f._PIO4_HI, _f._PIO4_LO, _f._TINIEST
_INF = math.inf
_NAN = math.nan


# -- a float's bits -------------------------------------------------------------------


@intrinsic
def _bits(typingctx, x):  # type: ignore[no-untyped-def]
    """A float64's bits as an int64 (fmath's `_bits`, read as two's complement)."""
    if not isinstance(x, types.Float):
        return None

    def codegen(context, builder, signature, args):  # type: ignore[no-untyped-def]
        return builder.bitcast(args[0], ir.IntType(64))

    return types.int64(types.float64), codegen


@intrinsic
def _from_bits(typingctx, b):  # type: ignore[no-untyped-def]
    """The float64 with these bits (fmath's `_from_bits`)."""
    if not isinstance(b, types.Integer):
        return None

    def codegen(context, builder, signature, args):  # type: ignore[no-untyped-def]
        return builder.bitcast(args[0], ir.DoubleType())

    return types.float64(types.int64), codegen


# -- fmath's functions ----------------------------------------------------------------


@nb.njit(inline="always", **JIT)
def _quadrant(s, c, q):  # type: ignore[no-untyped-def]  # float64 or float32 alike
    """sin and cos on [-pi/4, pi/4] moved to quadrant q: a swap and signs (exact)."""
    if q & 1:
        s, c = c, s
    if q & 2:
        s = -s
    if (q + 1) & 2:
        c = -c
    return s, c


@nb.njit(**JIT)
def sincos_steps(x: float) -> tuple[float, float]:
    """`fmath._sincos_py`: what fmath.sincos gives each element of a small array."""
    k = x * _TWO_OVER_PI
    k += _MAGIC
    q = _bits(k) & 3
    k -= _MAGIC
    r1 = k * -_PIO2_1
    r1 += x
    w = k * _PIO2_2
    hi = r1 - w
    nlo = w - (r1 - hi)
    nlo += k * _PIO2_2T
    head = hi - nlo
    lo = (hi - head) - nlo
    hi = head
    z = hi * hi
    v = z * hi
    r = z * _S6 + _S5
    r = r * z + _S4
    r = r * z + _S3
    r = r * z + _S2
    r *= v
    s = hi - (((lo * 0.5 - r) * z - lo) - v * _S1)
    r = z * _C6
    r = (r + _C5) * z
    r = (r + _C4) * z
    r = (r + _C3) * z
    r = (r + _C2) * z
    r = (r + _C1) * z
    r = r * z - hi * lo
    hz = z * 0.5
    c = 1.0 - hz
    c += ((1.0 - c) - hz) + r
    return _quadrant(s, c, q)


@nb.njit(**JIT)
def sincos(x: float) -> tuple[float, float]:
    """`fmath.sincos` on a Python float: a zero keeps its sign in sin (fmath answers
    zeros without the steps; the steps give the same bits)."""
    if x == 0.0:
        return x, 1.0
    return sincos_steps(x)


@nb.njit(**JIT)
def sincos_f32(x: np.float32) -> tuple[np.float32, np.float32]:
    """`fmath.sincos` on float32 (`_sincos_vec` with f32=True): the float32 heading in
    float64 (exact), reduced without the tail, the kernels without their last term,
    each result rounded once to float32, then the quadrant's swap and signs (exact).
    MPPI's rollouts take their headings' sines and cosines from it."""
    xd = np.float64(x)
    k = xd * _TWO_OVER_PI
    k += _MAGIC
    q = _bits(k) & 3  # the low word's low bits, as fmath reads them
    k -= _MAGIC
    hi = k * -_PIO2_1
    hi += xd
    k *= _PIO2_2F
    hi -= k
    z = hi * hi
    s = z * _S5
    s = (s + _S4) * z
    s = (s + _S3) * z
    s = (s + _S2) * z
    s = (s + _S1) * z
    s *= hi
    s += hi
    c = z * _C5
    c = (c + _C4) * z
    c = (c + _C3) * z
    c = (c + _C2) * z
    c = (c + _C1) * z
    c = (c - 0.5) * z
    c += 1.0
    return _quadrant(np.float32(s), np.float32(c), q)


@nb.njit(**JIT)
def exp(x: float) -> float:
    """`fmath.exp` on a Python float (`_exp_py`)."""
    if x != x:
        return x
    # Python's min(max(x, lo), hi): the first argument unless the second is beyond it
    if x < _EXP_LO:
        x = _EXP_LO
    if x > _EXP_HI:
        x = _EXP_HI
    k = x * _INV_LN2
    k += _MAGIC
    kb = _bits(k) - _MAGIC_BITS
    k -= _MAGIC
    hi = k * -_LN2_HI
    hi += x
    lo = k * _LN2_LO
    r = hi - lo
    z = r * r
    c = z * _P5
    c = (c + _P4) * z
    c = (c + _P3) * z
    c = (c + _P2) * z
    c = (c + _P1) * z
    c = r - c
    y = 1.0 - ((lo - (c * r) / (2.0 - c)) - hi)
    k1 = kb >> 1
    y *= _from_bits((k1 + 1023) << 52)
    return y * _from_bits((kb - k1 + 1023) << 52)


@nb.njit(**JIT)
def log(x: float) -> float:
    """`fmath.log` on a Python float (`_log_py`): log(0) = -inf, NaN below zero."""
    if not x > 0 or x == _INF:
        if x != x or x == _INF:
            return x
        return -_INF if x == 0 else _NAN
    sub = x < _TINY
    if sub:
        x *= _TWO54
    ix = _bits(x) + _LOG_SHIFT
    dk = _from_bits((ix >> 52) | _EXP_FLOAT_BITS) - _K_BIAS
    f = _from_bits((ix & _MANT_MASK) + _SQRT_HALF_BITS) - 1.0
    if sub:
        dk -= 54.0
    s = f / (f + 2.0)
    z = s * s
    r = z * _LG6
    r = (r + _LG5) * z
    r = (r + _LG4) * z
    r = (r + _LG3) * z
    r = (r + _LG2) * z
    r = (r + _LG1) * z
    r = (r + _LG0) * z
    hfsq = f * f * 0.5
    return dk * _LN2_HI - ((hfsq - ((r + hfsq) * s + dk * _LN2_LO)) - f)


@nb.njit(**JIT)
def arctan2(y: float, x: float) -> float:
    """`fmath.arctan2` on Python floats (`_atan2_py`)."""
    a, b = abs(y), abs(x)
    if a != a or b != b:
        return _NAN
    if a == _INF or b == _INF:
        a, b = (
            (1.0 if a == _INF else (0.0 if b == _INF else a)),
            (1.0 if b == _INF else (0.0 if a == _INF else b)),
        )
    # Python's min(a, b) and max(...): the first argument unless the second is beyond
    mn = b if b < a else a
    mx = b if b > a else a
    if mx < _TINIEST:
        mx = _TINIEST
    reg = mn > mx * _TAN_PI_8
    sub = mx if reg else 0.0
    num = mn - sub
    en = mn - (num + sub)
    add = mn if reg else 0.0
    den = add + mx
    ed = add - (den - mx)
    t = num / den
    t += (en - t * ed) / den
    z = t * t
    p = z * _AT10
    p = (p + _AT9) * z
    p = (p + _AT8) * z
    p = (p + _AT7) * z
    p = (p + _AT6) * z
    p = (p + _AT5) * z
    p = (p + _AT4) * z
    p = (p + _AT3) * z
    p = (p + _AT2) * z
    p = (p + _AT1) * z
    p = (p + _AT0) * z
    p *= t
    swap = a > b
    negx = math.copysign(1.0, x) < 0
    m = 1 if reg else 0
    if swap:
        m = 2 - m
    if negx:
        m = 4 - m
    if swap != negx:
        t, p = -t, -p
    return math.copysign((m * _PIO4_HI + t) + (m * _PIO4_LO - p), y)


# -- not fmath's, but bits compiled code must match -------------------------------------


@nb.njit(**JIT)
def remainder(a: float, b: float) -> float:
    """numpy's `np.mod(a, b)` on floats (npy_divmod): C's fmod, moved into the divisor's
    sign, a zero result taking the divisor's sign."""
    mod = np.fmod(a, b)
    if b == 0.0:
        return mod
    if mod != 0.0:
        if (b < 0) != (mod < 0):
            mod += b
    else:
        mod = math.copysign(0.0, b)
    return mod
