"""core.fmath_kernels gives fmath's bits (and np.mod's) on every input."""

from __future__ import annotations

import math
import struct

import numpy as np
import pytest

from btnav.core import fmath
from btnav.core import fmath_kernels as fk

_BITS = struct.Struct("<d")


def bits(v: float) -> bytes:
    return _BITS.pack(v)


def same(a: float, b: float) -> bool:
    """The same bits (any NaN matches any NaN: payloads are not part of fmath's contract)."""
    if a != a and b != b:
        return True
    return bits(a) == bits(b)


SPECIAL = [
    0.0, -0.0, math.inf, -math.inf, math.nan, 1e308, -1e308, 1.7976931348623157e308,
    5e-324, -5e-324, 2.2250738585072014e-308, 1e-300, -1e-300, 1e-20, 1.0, -1.0, 0.5,
    3e6, -3e6, 1e6, 1e15, 1e300,
] + [k * math.pi / 2 for k in range(-16, 17)] + [
    math.nextafter(k * math.pi / 2, math.inf) for k in range(-8, 9)
] + [math.nextafter(k * math.pi / 4, -math.inf) for k in range(-8, 9)]  # fmt: skip


def random_values(n: int = 100_000, seed: int = 0) -> list[float]:
    """Values over many ranges: uniform near the unit, wide angles, and log-uniform
    magnitudes of both signs down to subnormals."""
    rng = np.random.default_rng(seed)
    k = n // 4
    parts = [
        rng.uniform(-4.0, 4.0, k),
        rng.uniform(-1e4, 1e4, k),
        rng.uniform(-800.0, 800.0, k),
        rng.choice([-1.0, 1.0], k) * 10.0 ** rng.uniform(-320, 308, k),
    ]
    return np.concatenate(parts).tolist()


def test_sincos_bits():
    for x in random_values() + SPECIAL:
        s, c = fk.sincos(x)
        s0, c0 = fmath.sincos(x)
        assert same(s, s0) and same(c, c0), x
        s, c = fk.sincos_steps(x)
        s1, c1 = fmath._sincos_py(x)
        assert same(s, s1) and same(c, c1), x


def test_sincos_steps_give_the_array_paths_bits():
    xs = np.array(random_values(20_000, seed=3) + SPECIAL)
    s, c = fmath.sincos(xs)
    got = np.array([fk.sincos_steps(x) for x in xs.tolist()])
    assert np.array_equal(got[:, 0], s, equal_nan=True)
    assert np.array_equal(got[:, 1], c, equal_nan=True)


def test_exp_and_log_bits():
    for x in random_values(seed=1) + SPECIAL + [-745.2, -746.0, 709.78, 710.0, -708.5]:
        assert same(fk.exp(x), fmath.exp(x)), x
        assert same(fk.log(x), fmath.log(x)), x


def test_arctan2_bits():
    ys = random_values(seed=4)
    xs = random_values(seed=5)
    rng = np.random.default_rng(6)
    xs = [xs[i] for i in rng.permutation(len(xs))]
    for y, x in zip(ys, xs, strict=True):
        assert same(fk.arctan2(y, x), fmath.arctan2(y, x)), (y, x)
    for y in SPECIAL:
        for x in SPECIAL:
            assert same(fk.arctan2(y, x), fmath.arctan2(y, x)), (y, x)


@pytest.mark.parametrize("b", [2.0 * math.pi, -2.0 * math.pi, 1.0, 0.0])
def test_remainder_is_numpys(b):
    xs = random_values(20_000, seed=9) + SPECIAL
    with np.errstate(invalid="ignore", divide="ignore"):
        want = np.mod(np.array(xs), b)
    got = np.array([fk.remainder(x, b) for x in xs])
    assert np.array_equal(got.view(np.uint64)[~np.isnan(got)], want.view(np.uint64)[~np.isnan(got)])
    assert np.array_equal(np.isnan(got), np.isnan(want))


def test_sincos_f32_gives_the_float32_paths_bits():
    """MPPI's headings are float32: the kernel's float32 path against fmath's on float32
    arrays (random over every range, and the float32 specials: zeros, infinities, NaN,
    subnormals, the largest float, multiples of pi/2 and their neighbours)."""
    with np.errstate(over="ignore", under="ignore"):
        xs = np.array(random_values(40_000, seed=11) + SPECIAL).astype(np.float32)
    f32 = np.finfo(np.float32)
    near = np.array([k * np.pi / 2 for k in range(-64, 65)], np.float32)
    extra = [f32.max, -f32.max, f32.tiny, -f32.tiny, f32.smallest_subnormal, np.float32(-0.0)]
    xs = np.concatenate([xs, near, np.nextafter(near, np.float32(np.inf)),
                         np.nextafter(near, np.float32(-np.inf)), np.array(extra, np.float32)])  # fmt: skip
    s, c = fmath.sincos(xs)
    assert s.dtype == np.float32 and c.dtype == np.float32
    got = np.array([fk.sincos_f32(x) for x in xs], np.float32)
    for want, col in ((s, got[:, 0]), (c, got[:, 1])):
        nan = np.isnan(want)
        assert np.array_equal(nan, np.isnan(col))
        assert np.array_equal(want.view(np.uint32)[~nan], col.view(np.uint32)[~nan])
