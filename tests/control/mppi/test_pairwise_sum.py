"""pairwise_sum.py keeps its documented order (numpy's pairwise summation): against a
plain Python transcription of that order on lengths 0 to 300 and beyond, odd strides and
magnitudes, against np.sum up to numpy's 8192-value buffer, and a -0 sum comes out +0."""

from __future__ import annotations

import numba as nb
import numpy as np

from btnav.control.mppi.pairwise_sum import pairwise_sum

F = np.float32


def documented_order(a: np.ndarray) -> np.float32:
    """The module docstring's order, in Python float32 steps."""

    def tree(v: list[np.float32]) -> np.float32:
        n = len(v)
        if n < 8:
            res = F(0.0)
            for x in v:
                res = F(res + x)
            return res
        if n <= 128:
            r = list(v[:8])
            i = 8
            while i < n - n % 8:
                for j in range(8):
                    r[j] = F(r[j] + v[i + j])
                i += 8
            res = F(F(F(r[0] + r[1]) + F(r[2] + r[3])) + F(F(r[4] + r[5]) + F(r[6] + r[7])))
            for x in v[i:]:
                res = F(res + x)
            return res
        n2 = n // 2
        n2 -= n2 % 8
        return F(tree(v[:n2]) + tree(v[n2:]))

    return F(F(0.0) + tree(list(a)))


def bits(x: float) -> int:
    return int(np.float32(x).view(np.int32))


def test_the_kernel_adds_in_the_documented_order():
    rng = np.random.default_rng(7)
    for n in [*range(0, 301), 1000, 2000, 2001, 4099]:
        scale = rng.choice([1e-3, 1.0, 1e5])
        a = (rng.standard_normal(3 * n + 1) * scale).astype(np.float32)
        for view in (a[:n], a[1::3][:n], a[::2][: n // 2 + 1]):
            assert bits(pairwise_sum(view)) == bits(documented_order(view)), len(view)


def test_which_is_numpys_sum_up_to_its_buffer():
    rng = np.random.default_rng(8)
    for n in [*range(0, 300), 2000, 8191, 8192]:
        a = (rng.random(2 * n) * rng.choice([1e-2, 1.0, 1e4]) - 0.3).astype(np.float32)
        for view in (a[:n], a[::2]):
            assert bits(pairwise_sum(view)) == bits(view.sum()), n


def test_rows_of_a_batch_sum_as_numpys_rows():
    @nb.njit
    def row_sums(a):  # type: ignore[no-untyped-def]
        out = np.empty(a.shape[0], np.float32)
        for b in range(a.shape[0]):
            out[b] = pairwise_sum(a[b])
        return out

    rng = np.random.default_rng(5)
    for n in (7, 55, 129, 2000):
        a = (rng.random((8, n)) * rng.choice([1e-3, 1.0, 1e4], (8, 1))).astype(np.float32)
        assert (row_sums(a).view(np.int32) == a.sum(axis=1).view(np.int32)).all()


def test_a_negative_zero_sum_is_positive_zero_as_numpys():
    for n in (3, 8, 200):
        a = np.full(n, -0.0, np.float32)
        assert bits(pairwise_sum(a)) == bits(a.sum()) == 0
