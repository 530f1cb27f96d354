"""btnav.core.fmath: accurate, and the same bits whatever SIMD the CPU has."""

from __future__ import annotations

import hashlib
import math
import os
import platform
import subprocess
import sys

import numpy as np
import pytest

from btnav.core import fmath

RNG = np.random.default_rng(2024)


def ulps(got: np.ndarray, ref: np.ndarray) -> float:
    """Largest error in units of the reference's last place (equal NaNs and infs: 0)."""
    got, ref = np.asarray(got, float), np.asarray(ref, float)
    same = (got == ref) | (np.isnan(got) & np.isnan(ref))
    with np.errstate(invalid="ignore"):
        err = np.abs(got - ref) / np.spacing(np.abs(ref))
    return float(np.where(same, 0.0, err).max(initial=0.0))


def libm(f, *arrays: np.ndarray) -> np.ndarray:
    """The Python math function element by element (glibc: within an ulp, in practice
    correctly rounded): the reference, independent of numpy's SIMD kernels."""
    flat = [np.asarray(a, float).ravel().tolist() for a in arrays]
    return np.array([f(*v) for v in zip(*flat, strict=True)]).reshape(np.shape(arrays[0]))


def same_bits(a, b) -> bool:
    a, b = np.asarray(a), np.asarray(b)
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


# -- accuracy -------------------------------------------------------------------------


@pytest.mark.parametrize("scale", [math.pi / 4, 10.0, 1e3, 1e4, 1e6])
def test_sin_cos_within_an_ulp_and_a_half(scale):
    x = RNG.uniform(-scale, scale, 20000)
    s, c = fmath.sincos(x)
    assert ulps(s, libm(math.sin, x)) <= 1.5
    assert ulps(c, libm(math.cos, x)) <= 1.5
    assert same_bits(fmath.sin(x), s) and same_bits(fmath.cos(x), c)


def test_sin_cos_next_to_multiples_of_half_pi():
    k = np.arange(-6400, 6401, dtype=float)
    x = np.concatenate([k * (math.pi / 2), np.nextafter(k * (math.pi / 2), np.inf), k * math.pi])
    s, c = fmath.sincos(x)
    assert ulps(s, libm(math.sin, x)) <= 1.5
    assert ulps(c, libm(math.cos, x)) <= 1.5
    # exact values where they are exact
    assert fmath.sin(0.0) == 0.0 and fmath.cos(0.0) == 1.0
    assert fmath.sin(math.pi / 2) == 1.0 and fmath.cos(math.pi) == -1.0


def test_signed_zeros_infinities_and_nan():
    assert math.copysign(1.0, fmath.sin(-0.0)) == -1.0
    assert math.copysign(1.0, fmath.sin(0.0)) == 1.0
    s, c = fmath.sincos(np.array([-0.0, 0.0, np.inf, -np.inf, np.nan]))
    assert np.signbit(s[:2]).tolist() == [True, False] and c[:2].tolist() == [1.0, 1.0]
    assert np.isnan(s[2:]).all() and np.isnan(c[2:]).all()
    assert fmath.exp(-0.0) == 1.0 and fmath.log(1.0) == 0.0


def test_exp_over_its_whole_range():
    x = np.concatenate(
        [RNG.uniform(-708.0, 709.78, 20000), RNG.uniform(-1.0, 1.0, 5000), RNG.normal(0, 1e-9, 500)]
    )
    assert ulps(fmath.exp(x), libm(math.exp, x)) <= 1.5


def test_exp_overflow_and_underflow():
    big = np.nextafter(709.782712893384, 0.0)
    assert np.isfinite(fmath.exp(big)) and fmath.exp(709.79) == math.inf
    assert fmath.exp(np.inf) == math.inf and fmath.exp(-np.inf) == 0.0
    assert fmath.exp(-746.0) == 0.0 and fmath.exp(-745.1) == 5e-324
    sub = np.linspace(-744.0, -708.5, 2001)  # subnormal results: within a subnormal ulp
    assert np.abs(fmath.exp(sub) - libm(math.exp, sub)).max() <= 5e-324
    assert np.isnan(fmath.exp(np.nan))
    # one subnormal result in a block does not change the others' bits
    x = RNG.uniform(-5, 5, 1000)
    assert same_bits(fmath.exp(np.append(x, -740.0))[:-1], fmath.exp(x))


def test_log_of_every_magnitude():
    x = np.concatenate(
        [
            np.exp(RNG.uniform(-700, 700, 20000)),
            RNG.uniform(0.5, 2.0, 5000),
            1.0 + RNG.normal(0, 1e-7, 500),
            RNG.uniform(5e-324, 2e-308, 500),  # subnormals
            [5e-324, 2.2250738585072014e-308, 1.7976931348623157e308],
        ]
    )
    assert ulps(fmath.log(x), libm(math.log, x)) <= 1.5


def test_log_outside_its_domain():
    with np.errstate(divide="ignore", invalid="ignore"):
        ref = np.log(np.array([0.0, -0.0, -1.0, np.inf, np.nan, -np.inf]))
    got = fmath.log(np.array([0.0, -0.0, -1.0, np.inf, np.nan, -np.inf]))
    assert np.array_equal(got, ref, equal_nan=True)
    assert fmath.log(0.0) == -math.inf and math.isnan(fmath.log(-2.0))


def test_arctan2_in_every_octant_and_magnitude():
    n = 20000
    y = RNG.normal(size=n) * 10.0 ** RNG.uniform(-8, 8, n)
    x = RNG.normal(size=n) * 10.0 ** RNG.uniform(-8, 8, n)
    assert ulps(fmath.arctan2(y, x), libm(math.atan2, y, x)) <= 2.5
    y, x = RNG.normal(size=n), RNG.normal(size=n)
    assert ulps(fmath.arctan2(y, x), libm(math.atan2, y, x)) <= 2.5


def test_arctan2_zeros_infinities_and_nan_as_numpy():
    v = np.array([0.0, -0.0, 1.0, -1.0, 2.5, -2.5, np.inf, -np.inf, np.nan])
    y, x = (a.ravel() for a in np.meshgrid(v, v))
    ref = np.arctan2(y, x)
    got = fmath.arctan2(y, x)
    assert np.array_equal(np.isnan(got), np.isnan(ref))
    ok = ~np.isnan(ref)
    assert np.array_equal(np.signbit(got[ok]), np.signbit(ref[ok]))
    assert ulps(got[ok], ref[ok]) <= 1.0


def test_hypot():
    x, y = RNG.normal(size=(2, 1000)) * 100
    assert ulps(fmath.hypot(x, y), np.hypot(x, y)) <= 1.0
    assert fmath.hypot(3.0, 4.0) == 5.0 and type(fmath.hypot(3, 4)) is float
    f = fmath.hypot(x.astype(np.float32), np.float32(1.5))
    assert f.dtype == np.float32


# -- types, shapes and the two implementations -----------------------------------------


def test_float32_is_computed_in_float64_and_rounded_once():
    x = RNG.uniform(-10, 10, (2000, 56)).astype(np.float32)
    s, c = fmath.sincos(x)
    assert s.dtype == c.dtype == np.float32 and s.shape == x.shape
    s64, c64 = fmath.sincos(x.astype(np.float64))
    # rounding the float64 result gives the float32 one (all but a rare last-bit tie)
    assert (s != s64.astype(np.float32)).mean() < 1e-3
    assert (c != c64.astype(np.float32)).mean() < 1e-3
    assert np.abs(s - s64).max() <= 6e-8 and np.abs(c - c64).max() <= 6e-8
    for f in (fmath.exp, fmath.log):
        v = np.abs(x) + np.float32(0.01)
        got = f(v)
        assert got.dtype == np.float32
        assert np.array_equal(got, f(v.astype(np.float64)).astype(np.float32))
    got = fmath.arctan2(x, x[::-1])
    assert got.dtype == np.float32
    assert np.array_equal(
        got, fmath.arctan2(x.astype(float), x[::-1].astype(float)).astype(np.float32)
    )


def test_scalars_and_shapes():
    assert type(fmath.sin(1.0)) is float and type(fmath.exp(1)) is float
    assert type(fmath.arctan2(1.0, 2.0)) is float
    assert isinstance(fmath.sin(np.float32(1.0)), np.float32)
    assert fmath.sin(np.zeros((0, 3))).shape == (0, 3)
    assert fmath.arctan2(np.ones((4, 1)), np.ones(3)).shape == (4, 3)
    with pytest.raises(TypeError):
        fmath.sin(np.ones(3, complex))


SPECIAL = [0.0, -0.0, math.inf, -math.inf, math.nan, 5e-324, 1e-310, 1.0, -1.0, 709.78, -745.2]


@pytest.mark.parametrize(
    ("vec", "py", "make"),
    [
        (
            lambda x: fmath.sincos(x)[0],
            lambda x: fmath._sincos_py(x)[0],
            lambda: RNG.uniform(-1e4, 1e4, 3000),
        ),
        (
            lambda x: fmath.sincos(x)[1],
            lambda x: fmath._sincos_py(x)[1],
            lambda: RNG.uniform(-20, 20, 3000),
        ),
        (fmath.exp, fmath._exp_py, lambda: RNG.uniform(-750, 712, 3000)),
        (
            fmath.log,
            fmath._log_py,
            lambda: np.abs(RNG.normal(size=3000)) * 10.0 ** RNG.uniform(-320, 300, 3000),
        ),
    ],
)
def test_python_float_path_gives_the_array_path_bits(vec, py, make):
    """Python floats and small arrays take a pure-Python copy of the numpy passes."""
    x = np.concatenate([make(), SPECIAL])
    got = vec(x)
    ref = np.array([py(v) for v in x.tolist()])
    assert np.array_equal(got, ref, equal_nan=True)
    assert np.array_equal(np.signbit(got), np.signbit(ref)) or np.isnan(got).any()
    small = x[: fmath._SMALL]
    assert np.array_equal(vec(small), got[: fmath._SMALL], equal_nan=True)


def test_python_float_path_of_arctan2_gives_the_array_path_bits():
    v = np.array(SPECIAL)
    ey, ex = (a.ravel() for a in np.meshgrid(v, v))
    y = np.concatenate([RNG.normal(size=3000) * 10.0 ** RNG.uniform(-5, 5, 3000), ey])
    x = np.concatenate([RNG.normal(size=3000) * 10.0 ** RNG.uniform(-5, 5, 3000), ex])
    got = fmath.arctan2(y, x)
    ref = np.array([fmath._atan2_py(a, b) for a, b in zip(y.tolist(), x.tolist(), strict=True)])
    assert np.array_equal(got, ref, equal_nan=True)
    ok = ~np.isnan(ref)
    assert np.array_equal(np.signbit(got[ok]), np.signbit(ref[ok]))


def test_python_floats_take_the_same_path_and_sincos_remembers_them(monkeypatch):
    """The public functions on Python floats give the kernels' bits; sincos keeps what it
    has seen (zeros excepted: 0.0 and -0.0 are one key) and starts over when full."""
    monkeypatch.setattr(fmath, "_SINCOS_MEMO", {})
    monkeypatch.setattr(fmath, "_MEMO_MAX", 8)
    xs = [*np.random.default_rng(7).uniform(-10, 10, 20).tolist(), 0.0, -0.0, math.inf, math.nan]
    for x in xs + xs:  # the second pass is answered from the memo, then refilled
        assert same_bits(np.array(fmath.sincos(x)), np.array(fmath._sincos_py(x)))
        assert same_bits(np.array(fmath.sin(x)), np.array(fmath.sincos(np.array([x]))[0][0]))
        assert same_bits(np.array(fmath.exp(x)), np.array(fmath._exp_py(x)))
        assert same_bits(np.array(fmath.arctan2(x, 0.5)), np.array(fmath._atan2_py(x, 0.5)))
    assert 0 < len(fmath._SINCOS_MEMO) <= 8 and 0.0 not in fmath._SINCOS_MEMO
    assert math.copysign(1.0, fmath.sin(-0.0)) == -1.0
    assert math.copysign(1.0, fmath.sin(0.0)) == 1.0
    for x in xs[:8]:
        assert same_bits(np.array(fmath.log(abs(x))), np.array(fmath._log_py(abs(x))))


def test_blocks_do_not_change_the_bits():
    x = RNG.uniform(-50, 50, 3 * fmath._BLOCK + 17)
    whole = fmath.sincos(x)
    parts = [fmath.sincos(x[i : i + 1000]) for i in range(0, len(x), 1000)]
    assert same_bits(whole[0], np.concatenate([p[0] for p in parts]))
    assert same_bits(whole[1], np.concatenate([p[1] for p in parts]))


# -- products --------------------------------------------------------------------------


def test_dot_rows():
    a, b = RNG.normal(size=(2, 100, 3))
    got = fmath.dot_rows(a, b)
    assert same_bits(got, a[:, 0] * b[:, 0] + a[:, 1] * b[:, 1] + a[:, 2] * b[:, 2])
    assert np.allclose(got, np.einsum("ij,ij->i", a, b), rtol=0, atol=1e-14)
    assert fmath.dot_rows(a, np.array([1.0, 1.0, -1.0])).shape == (100,)


def test_matmul_k():
    a, b = RNG.normal(size=(7, 2)), RNG.normal(size=(2, 9))
    got = fmath.matmul_k(a, b)
    assert same_bits(got, a[:, 0:1] * b[0] + a[:, 1:2] * b[1])
    assert np.allclose(got, a @ b, rtol=1e-13, atol=1e-15)
    out, tmp = np.empty((7, 9)), np.empty(63)
    assert fmath.matmul_k(a, b, out=out, tmp=tmp) is out and same_bits(out, got)
    m, v = RNG.normal(size=(5, 4)), RNG.normal(size=4)
    assert fmath.matmul_k(m, v).shape == (5,) and np.allclose(fmath.matmul_k(m, v), m @ v)
    assert fmath.matmul_k(v, m.T).shape == (5,) and np.allclose(fmath.matmul_k(v, m.T), v @ m.T)
    with pytest.raises(ValueError):
        fmath.matmul_k(a, a)


def test_weighted_sum():
    u = RNG.normal(size=(56, 2, 2000)).astype(np.float32)
    w = RNG.random(2000).astype(np.float32)
    got = fmath.weighted_sum(u, w)
    assert got.shape == (56, 2) and got.dtype == np.float32
    assert same_bits(got, (u * w).sum(axis=-1))
    assert np.allclose(got, u @ w, rtol=1e-4, atol=1e-3)
    t = RNG.normal(size=56).astype(np.float32)
    assert same_bits(fmath.weighted_sum(u[:, 0], t, axis=0), (u[:, 0] * t[:, None]).sum(axis=0))


# -- the point: the same bits with and without the CPU's SIMD extensions ----------------

_SCRIPT = r"""
import hashlib, json, numpy as np
from numpy._core._multiarray_umath import __cpu_features__
from btnav.core import fmath
rng = np.random.default_rng(7)
out = {}
for dt in (np.float64, np.float32):
    x = rng.uniform(-1e3, 1e3, 50000).astype(dt)
    y = rng.normal(size=50000).astype(dt)
    p = np.abs(y) + dt(1e-3)
    arrays = [*fmath.sincos(x), fmath.exp(y * dt(50)), fmath.log(p), fmath.arctan2(y, x),
              fmath.hypot(x, y), fmath.dot_rows(np.stack([x, y], 1), np.stack([y, x], 1)),
              fmath.matmul_k(np.stack([x[:300], y[:300]], 1), np.stack([y[:500], x[:500]])),
              fmath.weighted_sum(x.reshape(50, 1000), p[:1000])]
    out[np.dtype(dt).name] = hashlib.sha256(b"".join(a.tobytes() for a in arrays)).hexdigest()
    x32 = x.astype(np.float32)
    out["numpy_" + np.dtype(dt).name] = hashlib.sha256(np.sin(x32).tobytes() + np.exp(x32 / 100).tobytes()).hexdigest()
out["x86_v3"] = bool(__cpu_features__.get("X86_V3", __cpu_features__.get("AVX2", False)))
print(json.dumps(out))
"""


def _run(env_extra: dict[str, str]) -> dict | None:
    env = {**os.environ, **env_extra}
    res = subprocess.run(
        [sys.executable, "-c", _SCRIPT], env=env, capture_output=True, text=True, timeout=120
    )
    if res.returncode != 0:
        if "NPY_DISABLE_CPU_FEATURES" in env_extra:
            return None  # the variable is refused (e.g. a feature of the baseline)
        raise AssertionError(res.stderr)
    import json

    return json.loads(res.stdout.strip().splitlines()[-1])


@pytest.mark.skipif(platform.machine().lower() not in ("x86_64", "amd64"), reason="x86-64 only")
def test_same_bits_without_avx2_and_with_generic_blas():
    base = _run({})
    assert base is not None
    if not base["x86_v3"]:
        pytest.skip("this CPU has no AVX2/FMA (X86_V3): nothing to disable")
    off = _run({"NPY_DISABLE_CPU_FEATURES": "X86_V3"})
    if off is None or off["x86_v3"]:
        pytest.skip("numpy refused or ignored NPY_DISABLE_CPU_FEATURES=X86_V3")
    generic = _run({"OPENBLAS_CORETYPE": "Prescott", "OPENBLAS_NUM_THREADS": "1"})
    # glibc's libm without its FMA variants (as on a CPU without FMA): fmath uses no libm
    no_fma = _run({"GLIBC_TUNABLES": "glibc.cpu.hwcaps=-AVX2,-FMA"})
    for key in ("float64", "float32"):
        assert off[key] == base[key], f"{key}: fmath's bits change without AVX2"
        assert generic[key] == base[key], f"{key}: fmath's bits change with generic BLAS"
        assert no_fma[key] == base[key], f"{key}: fmath's bits change with libm's variant"


def test_digest_helper_is_stable():
    """(The digests above hash raw bytes: equal arrays, equal digests.)"""
    a = fmath.sin(np.arange(10.0))
    assert hashlib.sha256(a.tobytes()).digest() == hashlib.sha256(a.copy().tobytes()).digest()
