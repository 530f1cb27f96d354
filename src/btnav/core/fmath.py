"""Deterministic elementwise math: the same bits on every CPU.

numpy's transcendental kernels (`np.sin`, `np.exp`, ...) and its BLAS sums (`@`, `np.dot`,
`np.einsum`) differ in the last bits between SIMD levels, and libm's `math.sin` between
FMA and non-FMA builds; a closed loop turns one ulp into a different trajectory. So the
simulation/navigation path computes with this module: sin, cos, sincos, exp, log, arctan2,
hypot and fixed-order sums built only from operations IEEE 754 rounds exactly (+ - * /,
comparisons, bit operations; fdlibm's coefficients), as numpy passes over blocks of
`_BLOCK` elements, and in pure Python for Python floats and arrays up to `_SMALL` elements.
float32 computes in float64 and rounds once. Algorithms, accuracy and speed:
docs/decisions/0051-same-bits-on-every-cpu.md.
"""

from __future__ import annotations

import math
import struct
import sys
from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

F64 = NDArray[np.float64]

__all__ = [
    "arctan2",
    "cos",
    "dot_rows",
    "exp",
    "hypot",
    "log",
    "matmul_k",
    "sin",
    "sincos",
    "weighted_sum",
]

#: Elements per block of whole-array passes (the temporaries stay in cache).
_BLOCK = 16384
#: Arrays up to this size go through the pure-Python kernels.
_SMALL = 24

#: 1.5 * 2**52: for |v| < 2**51, v + _MAGIC rounds v to the nearest integer n and its
#: bits are _MAGIC_BITS + n (two's complement in the low 52 bits).
_MAGIC = 6755399441055744.0
_MAGIC_BITS = 0x4338000000000000
_U64 = np.uint64
#: Index of a float64's low 32-bit word in its uint32 view (0 on x86-64 and arm64).
_LOW_WORD = 0 if sys.byteorder == "little" else 1

_F64_BITS = struct.Struct("<d")
_U64_BITS = struct.Struct("<Q")


def _bits(v: float) -> int:
    return _U64_BITS.unpack(_F64_BITS.pack(v))[0]


def _from_bits(b: int) -> float:
    return _F64_BITS.unpack(_U64_BITS.pack(b & 0xFFFFFFFFFFFFFFFF))[0]


# -- constants ----------------------------------------------------------------------

# range reduction by pi/2 in three parts: k * _PIO2_1 and k * _PIO2_2 exact for |k| < 2**21
_TWO_OVER_PI = 0.6366197723675814
_PIO2_1 = float.fromhex("0x1.921fb544p+0")  # 1.57079632673412561417e+00, 31 bits
_PIO2_2 = float.fromhex("0x1.0b4611a6p-34")  # 6.07710050630396597660e-11, 32 bits
_PIO2_2T = float.fromhex("0x1.3198a2e037073p-69")  # 2.02226624879595063154e-21 = pi/2 - both
_PIO2_2F = _PIO2_2 + _PIO2_2T  # pi/2 - _PIO2_1 to 53 bits (float32 results)

# sin(x) ~ x + x^3 (S1 + x^2 S2 + ... + x^10 S6) on [-pi/4, pi/4]
_S1 = -1.66666666666666324348e-01
_S2 = 8.33333333332248946124e-03
_S3 = -1.98412698298579493134e-04
_S4 = 2.75573137070700676789e-06
_S5 = -2.50507602534068634195e-08
_S6 = 1.58969099521155010221e-10
# cos(x) ~ 1 - x^2/2 + x^4 (C1 + x^2 C2 + ... + x^10 C6) on [-pi/4, pi/4]
_C1 = 4.16666666666666019037e-02
_C2 = -1.38888888888741095749e-03
_C3 = 2.48015872894767294178e-05
_C4 = -2.75573143513906633035e-07
_C5 = 2.08757232129817482790e-09
_C6 = -1.13596475577881948265e-11

# exp
_INV_LN2 = 1.4426950408889634
_LN2_HI = 6.93147180369123816490e-01  # 32 bits: k * _LN2_HI is exact for |k| < 2**21
_LN2_LO = 1.90821492927058770002e-10
# r coth(r/2) ~ 2 + r^2 (P1 + r^2 P2 + ... + r^8 P5) on [-ln2/2, ln2/2]
_P1 = 1.66666666666666019037e-01
_P2 = -2.77777777770155933842e-03
_P3 = 6.61375632143793436117e-05
_P4 = -1.65339022054652515390e-06
_P5 = 4.13813679705723846039e-08
_EXP_LO, _EXP_HI = -746.0, 710.0  # beyond: exp is 0 and inf

# log: 2 atanh(s) ~ 2s + s (s^2 Lg1 + s^4 Lg2 + ... + s^14 Lg7), s = f / (2 + f)
_LG = (
    6.666666666666735130e-01,
    3.999999999940941908e-01,
    2.857142874366239149e-01,
    2.222219843214978396e-01,
    1.818357216161805012e-01,
    1.531383769920937332e-01,
    1.479819860511658591e-01,
)
#: Adding _LOG_SHIFT to the bits moves the exponent's boundary to 0x3fe6a09e00000000
#: (just below sqrt(1/2)): the exponent field then gives k, and the mantissa plus those
#: bits 1 + f in [0.7071, 1.4142).
_LOG_SHIFT = 0x3FF0000000000000 - 0x3FE6A09E00000000
_SQRT_HALF_BITS = 0x3FE6A09E00000000
_MANT_MASK = 0x000FFFFFFFFFFFFF
_EXP_FLOAT_BITS = 0x4330000000000000  # bits | e, read as a double, is 2**52 + e
_K_BIAS = 4503599627371519.0  # 2**52 + 1023
_TINY = 2.2250738585072014e-308  # smallest normal double
_TWO54 = 18014398509481984.0

# atan on [-tan(pi/8), tan(pi/8)]: t - t^3 (aT0 + t^2 aT1 + ... + t^20 aT10)
_AT = (
    3.33333333333329318027e-01,
    -1.99999999998764832476e-01,
    1.42857142725034663711e-01,
    -1.11111104054623557880e-01,
    9.09088713343650656196e-02,
    -7.69187620504482999495e-02,
    6.66107313738753120669e-02,
    -5.83357013379057348645e-02,
    4.97687799461593236017e-02,
    -3.65315727442169155270e-02,
    1.62858201153657823623e-02,
)
_TAN_PI_8 = 0.41421356237309503
#: pi/4 to 50 bits (m * _PIO4_HI is exact for m <= 4) and the rest
_PIO4_HI = float.fromhex("0x1.921fb54442d18p-1")
_PIO4_LO = 3.061616997868383e-17
_TINIEST = 5e-324


# -- shapes and dtypes --------------------------------------------------------------


def _out_dtype(dt: np.dtype) -> np.dtype:
    if dt == np.float32 or dt == np.float16:
        return dt
    if dt.kind == "c":
        raise TypeError("fmath works on real numbers only")
    return np.dtype(np.float64)


def _is_py_scalar(v: Any) -> bool:
    return isinstance(v, float | int) and not isinstance(v, np.generic)


def _apply(
    vec: Callable[..., None],
    py: Callable[..., Any],
    nout: int,
    args: tuple[Any, ...],
) -> Any:
    """Run a kernel on broadcast inputs: `vec(*in_blocks, *out_blocks, f32)` over blocks
    of the flattened float64 inputs (float32 inputs as they are), or `py` per element."""
    if all(_is_py_scalar(a) for a in args):
        return py(*(float(a) for a in args))
    arrs = [np.asarray(a) for a in args]
    dt = _out_dtype(np.result_type(*args))
    if len(arrs) > 1:
        arrs = list(np.broadcast_arrays(*arrs))
    shape = arrs[0].shape
    f32 = dt != np.float64
    final = dt
    if dt == np.float16:
        dt = np.dtype(np.float32)
    work = np.float32 if (f32 and all(a.dtype == np.float32 for a in arrs)) else np.float64
    flat = [np.ascontiguousarray(a, dtype=work).reshape(-1) for a in arrs]
    n = flat[0].size
    if n <= _SMALL and not f32:
        vals = [py(*v) for v in zip(*(f.tolist() for f in flat), strict=True)]
        if nout == 1:
            outs = [np.array(vals, np.float64).reshape(shape)]
        else:
            outs = [np.array([v[i] for v in vals], np.float64).reshape(shape) for i in range(nout)]
    else:
        outs = [np.empty(n, dt) for _ in range(nout)]
        for lo in range(0, n, _BLOCK):
            hi = min(lo + _BLOCK, n)
            vec(*(f[lo:hi] for f in flat), *(o[lo:hi] for o in outs), f32)
        outs = [o.reshape(shape) for o in outs]
    if final != dt:
        outs = [o.astype(final) for o in outs]
    if not any(isinstance(a, np.ndarray) for a in args):  # scalars in, scalars out
        outs = [o[()] for o in outs]
    return outs[0] if nout == 1 else tuple(outs)


# -- sin / cos ----------------------------------------------------------------------


def _quadrant(s: NDArray[Any], c: NDArray[Any], q: NDArray[Any]) -> None:
    """Quadrant q (low bits of `q`, an unsigned array as wide as s and c): (sin, cos) =
    (s, c), (c, -s), (-s, -c), (-c, s), in place on the bits (exact, keeps -0 and NaN).
    `q` is overwritten."""
    ut = q.dtype.type
    top = ut(q.dtype.itemsize * 8 - 1)
    sb, cb = s.view(q.dtype), c.view(q.dtype)
    odd = np.left_shift(q, top)  # bit 0 at the sign: cos's extra flip in quadrants 1, 3
    it = np.dtype(q.dtype.str.replace("u", "i"))
    m = np.right_shift(odd.view(it), it.type(top)).view(q.dtype)  # all ones when odd
    d = sb ^ cb  # swapped where odd
    d &= m
    sb ^= d
    cb ^= d
    np.left_shift(q, top - ut(1), out=m)
    m &= ut(1) << top  # bit 1 at the sign: negative sin and cos in quadrants 2, 3
    sb ^= m
    m ^= odd  # negative cos in quadrants 1, 2
    cb ^= m


def _sincos_vec(x: NDArray[Any], s_out: NDArray[Any], c_out: NDArray[Any], f32: bool) -> None:
    with np.errstate(invalid="ignore", over="ignore"):
        if f32:
            # float32 results: r = (x - k p1) - k (pi/2 - p1), no tail; kernels without
            # their last term (error < 1e-11 before the rounding to float32). x is cast to
            # float64 once (exact; mixed-type ufunc calls are ~3x slower), and the
            # quadrant is read as uint32 from the low word of k + _MAGIC (little-endian).
            x = x.astype(np.float64, copy=False)
            k = np.multiply(x, _TWO_OVER_PI)
            k += _MAGIC
            q = k.view(np.uint32)[_LOW_WORD::2] & np.uint32(3)
            k -= _MAGIC  # round(x 2/pi); +0 for x = -0
            hi = np.multiply(k, -_PIO2_1)
            hi += x
            k *= _PIO2_2F
            hi -= k
            z = np.multiply(hi, hi, out=k)
            s = z * _S5
            for coef in (_S4, _S3, _S2, _S1):
                s += coef
                s *= z
            s *= hi
            s += hi
            s_out[...] = s
            c = np.multiply(z, _C5, out=s)
            for coef in (_C4, _C3, _C2, _C1, -0.5):
                c += coef
                c *= z
            c += 1.0
            c_out[...] = c
            _quadrant(s_out, c_out, q)
            return
        k = np.multiply(x, _TWO_OVER_PI, dtype=np.float64)
        k += _MAGIC
        q = k.view(_U64) & _U64(3)  # the quadrant, k mod 4
        k -= _MAGIC  # round(x 2/pi); +0 for x = -0
        # r = x - k pi/2 as hi + lo: x - k p1 is exact; its difference with k p2 (exact)
        # is the rounded r1 - w and its rounding error (exact, kept as -nlo); then - k p3,
        # and hi, lo renormalised (|lo| <= ulp(hi) / 2: the kernels take lo to first
        # order). Subtracting the tail (not adding it) keeps sin(-0) = -0.
        r1 = np.multiply(k, -_PIO2_1)
        r1 += x
        w = np.multiply(k, _PIO2_2)
        hi = r1 - w
        np.subtract(r1, hi, out=r1)
        nlo = np.subtract(w, r1, out=r1)
        np.multiply(k, _PIO2_2T, out=w)
        nlo += w
        head = np.subtract(hi, nlo, out=w)
        np.subtract(hi, head, out=hi)
        lo = np.subtract(hi, nlo, out=hi)
        hi = head
        z = np.multiply(hi, hi, out=k)
        tmp = nlo
        # sin(hi + lo) ~ hi + hi^3 S(z) + lo (1 - z/2):  hi - ((z (lo/2 - v r) - lo) - v S1)
        v = np.multiply(z, hi, out=s_out)
        r = z * _S6
        r += _S5
        for coef in (_S4, _S3, _S2):
            r *= z
            r += coef
        r *= v
        np.multiply(lo, 0.5, out=tmp)
        tmp -= r
        tmp *= z
        tmp -= lo
        v *= _S1
        tmp -= v
        np.subtract(hi, tmp, out=s_out)
        # cos(hi + lo) ~ (1 - z/2) + z^2 C(z) - hi lo, with 1 - z/2 rounded and its error
        np.multiply(z, _C6, out=r)
        for coef in (_C5, _C4, _C3, _C2, _C1):
            r += coef
            r *= z
        r *= z
        np.multiply(hi, lo, out=lo)
        r -= lo
        hz = np.multiply(z, 0.5, out=hi)
        np.subtract(1.0, hz, out=c_out)
        np.subtract(1.0, c_out, out=tmp)
        tmp -= hz
        tmp += r
        c_out += tmp
        _quadrant(s_out, c_out, q)


def _sincos_py(x: float) -> tuple[float, float]:
    """The float64 path of `_sincos_vec`, step for step on one Python float."""
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
    for coef in (_S4, _S3, _S2):
        r = r * z + coef
    r *= v
    s = hi - (((lo * 0.5 - r) * z - lo) - v * _S1)
    r = z * _C6
    for coef in (_C5, _C4, _C3, _C2, _C1):
        r = (r + coef) * z
    r = r * z - hi * lo
    hz = z * 0.5
    c = 1.0 - hz
    c += ((1.0 - c) - hz) + r
    if q & 1:
        s, c = c, s
    if q & 2:
        s = -s
    if (q + 1) & 2:
        c = -c
    return s, c


#: (sin, cos) of Python floats already seen (a pose's yaw is turned many times: frame
#: lookups, compositions, the robot and its odometry); emptied when it grows past
#: `_MEMO_MAX`. Zeros never reach it (0.0 and -0.0 are one key but differ in sin).
_SINCOS_MEMO: dict[float, tuple[float, float]] = {}
_MEMO_MAX = 4096


def sincos(x: ArrayLike) -> tuple[Any, Any]:
    """(sin(x), cos(x)) from one range reduction, deterministic (see the module docstring)."""
    if type(x) is float:  # the hot case: one Python float, remembered
        if x == 0.0:  # the yaw of most frames: sin keeps the zero's sign
            return x, 1.0
        found = _SINCOS_MEMO.get(x)
        if found is None:
            found = _sincos_py(x)
            if len(_SINCOS_MEMO) >= _MEMO_MAX:
                _SINCOS_MEMO.clear()
            _SINCOS_MEMO[x] = found
        return found
    return _apply(_sincos_vec, _sincos_py, 2, (x,))


def sin(x: ArrayLike) -> Any:
    """sin(x), deterministic (see the module docstring)."""
    return sincos(x)[0]


def cos(x: ArrayLike) -> Any:
    """cos(x), deterministic (see the module docstring)."""
    return sincos(x)[1]


# -- exp ----------------------------------------------------------------------------


def _exp_vec(x: NDArray[Any], out: NDArray[Any], f32: bool) -> None:
    with np.errstate(invalid="ignore", over="ignore", under="ignore"):
        xc = np.clip(x, _EXP_LO, _EXP_HI, dtype=np.float64)  # NaN stays NaN
        k = np.multiply(xc, _INV_LN2)
        k += _MAGIC
        kb = k.view(np.int64) - np.int64(_MAGIC_BITS)  # k as an integer
        k -= _MAGIC
        hi = np.multiply(k, -_LN2_HI)
        hi += xc  # exact
        lo = np.multiply(k, _LN2_LO, out=k)
        r = np.subtract(hi, lo, out=xc)
        z = r * r
        c = z * _P5
        for coef in (_P4, _P3, _P2, _P1):
            c += coef
            c *= z
        np.subtract(r, c, out=c)  # c = r - r^2 P(r^2)
        # exp(r) = 1 + 2r / (2 - c) = 1 - ((lo - r c / (2 - c)) - hi)
        den = np.subtract(2.0, c, out=z)
        c *= r
        c /= den
        np.subtract(lo, c, out=c)
        c -= hi
        y = np.subtract(1.0, c, out=c)
        kmin, kmax = int(kb.min()), int(kb.max())
        if kmin >= -1022 and kmax <= 1023:
            kb += np.int64(1023)
            kb <<= np.int64(52)
            y *= kb.view(np.float64)
        else:  # subnormal or overflowing results: 2**k as two normal factors
            k1 = kb >> np.int64(1)
            kb -= k1
            for part in (k1, kb):
                part += np.int64(1023)
                part <<= np.int64(52)
                y *= part.view(np.float64)
        out[...] = y


def _exp_py(x: float) -> float:
    """The path of `_exp_vec`, step for step on one Python float."""
    if x != x:
        return x
    x = min(max(x, _EXP_LO), _EXP_HI)
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
    for coef in (_P4, _P3, _P2, _P1):
        c = (c + coef) * z
    c = r - c
    y = 1.0 - ((lo - (c * r) / (2.0 - c)) - hi)
    k1 = kb >> 1  # scaling by two normal factors equals one exact scaling when normal
    y *= _from_bits((k1 + 1023) << 52)
    return y * _from_bits((kb - k1 + 1023) << 52)


def exp(x: ArrayLike) -> Any:
    """e**x, deterministic (see the module docstring)."""
    if type(x) is float:
        return _exp_py(x)
    return _apply(_exp_vec, _exp_py, 1, (x,))


# -- log ----------------------------------------------------------------------------


def _log_vec(x: NDArray[Any], out: NDArray[Any], f32: bool) -> None:
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        x = x.astype(np.float64, copy=False)
        special = not (x.min() >= _TINY and x.max() < np.inf)  # also for NaN
        x_in = x
        if special:  # subnormals scaled by 2**54 (k corrected below)
            sub = (x > 0) & (x < _TINY)
            x = np.where(sub, x * _TWO54, x)
        ix = x.view(_U64) + _U64(_LOG_SHIFT)
        e = ix >> _U64(52)
        e |= _U64(_EXP_FLOAT_BITS)
        dk = e.view(np.float64)
        dk -= _K_BIAS  # k
        ix &= _U64(_MANT_MASK)
        ix += _U64(_SQRT_HALF_BITS)
        f = ix.view(np.float64)
        f -= 1.0
        if special:
            dk -= np.where(sub, 54.0, 0.0)
        s = np.add(f, 2.0)
        np.divide(f, s, out=s)
        z = s * s
        r = z * _LG[6]
        for coef in _LG[5::-1]:
            r += coef
            r *= z
        hfsq = f * f
        hfsq *= 0.5
        r += hfsq
        r *= s  # s (hfsq + R)
        np.multiply(dk, _LN2_LO, out=z)
        r += z
        np.subtract(hfsq, r, out=r)
        r -= f
        dk *= _LN2_HI
        res = np.subtract(dk, r, out=dk)  # k ln2_hi - ((hfsq - (s (hfsq + R) + k ln2_lo)) - f)
        if special:
            res = np.where(x_in > 0, res, np.where(x_in == 0, -np.inf, np.nan))
            res = np.where(x_in == np.inf, np.inf, res)
        out[...] = res


def _log_py(x: float) -> float:
    """The path of `_log_vec`, step for step on one Python float."""
    if not x > 0 or x == math.inf:  # NaN, negative, zero, inf
        return x if x != x or x == math.inf else (-math.inf if x == 0 else math.nan)
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
    r = z * _LG[6]
    for coef in _LG[5::-1]:
        r = (r + coef) * z
    hfsq = f * f * 0.5
    return dk * _LN2_HI - ((hfsq - ((r + hfsq) * s + dk * _LN2_LO)) - f)


def log(x: ArrayLike) -> Any:
    """Natural logarithm, deterministic (see the module docstring); log(0) = -inf, NaN below."""
    if type(x) is float:
        return _log_py(x)
    return _apply(_log_vec, _log_py, 1, (x,))


# -- arctan2 ------------------------------------------------------------------------


def _atan2_vec(y: NDArray[Any], x: NDArray[Any], out: NDArray[Any], f32: bool) -> None:
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        a = np.abs(y).astype(np.float64, copy=False)
        b = np.abs(x).astype(np.float64, copy=False)
        mx = np.maximum(a, b)
        if not mx.max() < np.inf:  # infinities or NaN: atan2(inf, x) as atan2(1, 0), ...
            ia, ib = np.isinf(a), np.isinf(b)
            nan = np.isnan(mx)
            a, b = (
                np.where(nan, np.nan, np.where(ia, 1.0, np.where(ib, 0.0, a))),
                np.where(nan, np.nan, np.where(ib, 1.0, np.where(ia, 0.0, b))),
            )
            mx = np.maximum(a, b)
        mn = np.minimum(a, b)
        np.maximum(mx, _TINIEST, out=mx)  # 0 / 0 becomes 0 / tiny = 0
        t = np.multiply(mx, _TAN_PI_8)
        reg = mn > t  # above tan(pi/8): t = (mn - mx) / (mn + mx), plus pi/4
        # num / den with both roundings' errors (exact, as mx >= mn) folded back in:
        # t = num / den + (en - t ed) / den
        rf = reg.astype(np.float64)
        sub = np.multiply(rf, mx, out=t)
        num = mn - sub
        en = num + sub
        np.subtract(mn, en, out=en)
        rf *= mn
        den = rf + mx
        ed = np.subtract(den, mx, out=sub)
        np.subtract(rf, ed, out=ed)
        t = np.divide(num, den, out=num)
        np.multiply(t, ed, out=ed)
        np.subtract(en, ed, out=en)
        en /= den
        t += en
        z = np.multiply(t, t, out=rf)
        p = z * _AT[10]
        for coef in _AT[9::-1]:
            p += coef
            p *= z
        p *= t  # atan(t) = t - p
        # angle = m pi/4 +- (t - p): m = r, or 2 - m if |y| > |x|, or 4 - m if x < 0; the
        # sign flips with each of the two reflections. Summed as (m HI + t) + (m LO - p).
        swap = a > b
        negx = np.signbit(x)
        m = reg.view(np.int8).copy()
        sw8, nx8 = swap.view(np.int8), negx.view(np.int8)
        d8 = np.left_shift(sw8, np.int8(1))
        d8 -= m
        d8 -= m
        d8 *= sw8
        m += d8  # 2 - r when swapped
        np.left_shift(nx8, np.int8(2), out=d8)
        d8 -= m
        d8 -= m
        d8 *= nx8
        m += d8  # 4 - m when x < 0
        flip = np.not_equal(sw8, nx8).view(np.uint8).astype(_U64)
        flip <<= _U64(63)
        t.view(_U64)[...] ^= flip
        p.view(_U64)[...] ^= flip
        mf = m.astype(np.float64)
        np.multiply(mf, _PIO4_LO, out=z)
        z -= p
        mf *= _PIO4_HI
        mf += t
        np.add(mf, z, out=p)
        np.copysign(p, y, out=p)
        out[...] = p


def _atan2_py(y: float, x: float) -> float:
    """The path of `_atan2_vec`, step for step on Python floats."""
    a, b = abs(y), abs(x)
    if a != a or b != b:
        return math.nan
    if a == math.inf or b == math.inf:
        a, b = (
            (1.0 if a == math.inf else (0.0 if b == math.inf else a)),
            (1.0 if b == math.inf else (0.0 if a == math.inf else b)),
        )
    mn, mx = min(a, b), max(max(a, b), _TINIEST)
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
    p = z * _AT[10]
    for coef in _AT[9::-1]:
        p = (p + coef) * z
    p *= t
    swap, negx = a > b, math.copysign(1.0, x) < 0
    m = 1 if reg else 0
    if swap:
        m = 2 - m
    if negx:
        m = 4 - m
    if swap != negx:
        t, p = -t, -p
    return math.copysign((m * _PIO4_HI + t) + (m * _PIO4_LO - p), y)


def arctan2(y: ArrayLike, x: ArrayLike) -> Any:
    """The angle of (x, y) in [-pi, pi], deterministic; zeros, infinities as np.arctan2."""
    if type(y) is float and type(x) is float:
        return _atan2_py(y, x)
    return _apply(_atan2_vec, _atan2_py, 1, (y, x))


# -- hypot and products -------------------------------------------------------------


def hypot(x: ArrayLike, y: ArrayLike) -> Any:
    """sqrt(x*x + y*y) (np.hypot calls libm's hypot); float32 stays float32."""
    if _is_py_scalar(x) and _is_py_scalar(y):
        x, y = float(x), float(y)
        return math.sqrt(x * x + y * y)
    xa = x if type(x) is np.ndarray else np.asarray(x)
    ya = y if type(y) is np.ndarray else np.asarray(y)
    dt = xa.dtype
    if ya.dtype != dt or dt.kind != "f":
        dt = np.result_type(x, y)
        if dt.kind != "f":
            dt = np.dtype(np.float64)
        xa, ya = xa.astype(dt, copy=False), ya.astype(dt, copy=False)
    out = xa * xa
    yy = ya * ya
    if out.shape == yy.shape and out.ndim:
        out += yy
    else:
        out = out + yy
    return np.sqrt(out, out=out) if out.ndim else np.sqrt(out)


def dot_rows(a: ArrayLike, b: ArrayLike) -> NDArray[Any]:
    """The dot product along the last axis, `np.einsum("...k,...k->...", a, b)`, as k
    multiplies added in order (k is small: 2 or 3)."""
    a, b = np.asarray(a), np.asarray(b)
    k = a.shape[-1]
    if b.shape[-1] != k:
        raise ValueError(f"dot_rows: last axes differ ({k} and {b.shape[-1]})")
    out = a[..., 0] * b[..., 0]
    if k > 1:
        tmp = np.empty_like(out)
        for i in range(1, k):
            np.multiply(a[..., i], b[..., i], out=tmp)
            out += tmp
    return out


def matmul_k(
    a: ArrayLike,
    b: ArrayLike,
    out: NDArray[Any] | None = None,
    tmp: NDArray[Any] | None = None,
) -> NDArray[Any]:
    """`a @ b` for a small inner dimension K as K broadcast products added in order:
    (..., M, K) @ (..., K, N) -> (..., M, N); a 1-d operand is a row or a column vector
    as in np.matmul. `out`, if given, has the result's shape; `tmp`, if given, is
    scratch of the result's size (contiguous) for the products after the first."""
    a, b = np.asarray(a), np.asarray(b)
    a2 = a[None, :] if a.ndim == 1 else a
    b2 = b[:, None] if b.ndim == 1 else b
    K = a2.shape[-1]
    if b2.shape[-2] != K:
        raise ValueError(f"matmul_k: inner dimensions differ ({K} and {b2.shape[-2]})")
    shape = (*np.broadcast_shapes(a2.shape[:-2], b2.shape[:-2]), a2.shape[-2], b2.shape[-1])
    if out is None:
        dims = shape[:-2] + shape[-2:-1] * (a.ndim > 1) + shape[-1:] * (b.ndim > 1)
        out = np.empty(dims, np.result_type(a2, b2))
    full = out
    if b.ndim == 1:
        full = full[..., None]
    if a.ndim == 1:
        full = full[..., None, :]
    np.multiply(a2[..., :, 0:1], b2[..., 0:1, :], out=full)
    if K > 1:
        tmp = np.empty_like(full) if tmp is None else tmp.reshape(full.shape)
        for i in range(1, K):
            np.multiply(a2[..., :, i : i + 1], b2[..., i : i + 1, :], out=tmp)
            full += tmp
    return out


def weighted_sum(
    u: ArrayLike, w: ArrayLike, axis: int = -1, out: NDArray[Any] | None = None
) -> Any:
    """sum(u * w) along `axis`, w a vector along that axis (or broadcasting against u):
    e.g. the MPPI mean `u @ weights` as an elementwise product and numpy's pairwise sum."""
    u, w = np.asarray(u), np.asarray(w)
    if w.ndim == 1 and u.ndim > 1:
        w = w.reshape((-1,) + (1,) * (u.ndim - 1 - axis % u.ndim))
    return np.multiply(u, w).sum(axis=axis, out=out)
