"""CriticData.furthest_reached_path_point's compiled search (furthest_point_kernel.py)
returns numpy's integer: random batches against paths of 2 to 100 points, rollouts that
stand still, crawl or travel far beyond the path, exact ties (rollouts ending on a path
point's mirror, repeated path points), the early exit at the path's end, a NaN, and whole controller cycles."""

from __future__ import annotations

import numpy as np
import pytest

from btnav.control.mppi.critic_data import DEFAULT_METHOD, CriticData

from .batch import make_data
from .test_path_align_kernel import random_path
from .test_rollout_kernel import controller, same_bits, step_cycle


def both(trajs: np.ndarray, path: np.ndarray, monkeypatch: pytest.MonkeyPatch) -> tuple[int, int]:
    out = []
    for method in ("numpy", "kernel"):
        monkeypatch.setattr(CriticData, "method", method)
        out.append(make_data(list(trajs), path=path).furthest_reached_path_point())
    return out[0], out[1]


def rollouts(rng: np.random.Generator, b: int, t: int, speed: float) -> np.ndarray:
    """(b, t, 3) random walks from the origin, some standing still, some zigzagging."""
    heading = np.cumsum(rng.normal(0.0, 0.3, (b, t)), axis=1)
    v = rng.uniform(0.0, speed, (b, 1)) * rng.uniform(0.5, 1.5, (b, t))
    v[rng.random(b) < 0.1] = 0.0
    zig = rng.random(b) < 0.2
    heading[zig] = np.where(np.arange(t) % 2, 1.4, -1.4)
    v[:, 0] = 0.0
    x, y = np.cumsum(v * np.cos(heading), axis=1), np.cumsum(v * np.sin(heading), axis=1)
    return np.stack([x, y, heading], axis=-1)


@pytest.mark.parametrize("seed", range(60))
def test_random_batches_give_numpy_s_index(seed, monkeypatch):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(2, 101))
    t = int(rng.choice([1, 2, 5, 9, 56, 130, 300]))
    b = int(rng.choice([1, 7, 200]))
    path = random_path(rng, n)
    if seed % 3 == 0:  # coarse, grid-like: exact ties in lengths and distances
        path = np.round(path * 20) / 20
    trajs = rollouts(rng, b, t, float(rng.choice([0.005, 0.05, 0.3])))
    if seed % 4 == 0:
        trajs[..., :2] = np.round(trajs[..., :2] * 20) / 20
    a, k = both(trajs, path, monkeypatch)
    assert a == k


def test_ties_take_the_first_point(monkeypatch):
    """Rollouts ending midway between points (equal distances) and on repeated points:
    numpy's argmin keeps the first."""
    path = np.zeros((9, 3))
    path[:, 0] = [0.0, 0.1, 0.1, 0.2, 0.3, 0.3, 0.3, 0.4, 0.5]
    ends = [0.05, 0.1, 0.15, 0.25, 0.3, 0.35, 0.45]
    for end in ends:
        x = np.linspace(0.0, end, 10)
        trajs = np.stack([x, np.zeros(10), np.zeros(10)], axis=-1)[None]
        a, k = both(np.concatenate([trajs, trajs[:, ::-1] * 0]), path, monkeypatch)
        assert a == k


def test_the_path_s_end_ends_the_search(monkeypatch):
    """A rollout reaching the last point first: the rest of the batch is not scanned,
    and the answer is still numpy's."""
    rng = np.random.default_rng(3)
    path = random_path(rng, 30)
    trajs = rollouts(rng, 50, 56, 0.05)
    trajs[0, :, 0] = np.linspace(0.0, 5.0, 56)  # travels past the path's length
    trajs[0, -1, :2] = path[-1, :2]
    a, k = both(trajs, path, monkeypatch)
    assert a == k == len(path) - 1


def test_a_nan_and_a_two_point_path(monkeypatch):
    rng = np.random.default_rng(4)
    path = random_path(rng, 2)
    trajs = rollouts(rng, 20, 56, 0.3)
    assert both(trajs, path, monkeypatch)[0] == both(trajs, path, monkeypatch)[1]
    trajs[3, -1, 0] = np.nan
    trajs[5, 10, 1] = np.nan
    a, k = both(trajs, random_path(rng, 40), monkeypatch)
    assert a == k


def test_the_default_is_the_optimizer_switch():
    assert CriticData.method == DEFAULT_METHOD


def test_controller_cycles_give_the_same_commands_and_sequences(monkeypatch):
    a, b = controller("diff_drive", "kernel"), controller("diff_drive", "kernel")
    for k in range(4):
        monkeypatch.setattr(CriticData, "method", "numpy")
        ca = step_cycle(a, k)
        monkeypatch.setattr(CriticData, "method", "kernel")
        cb = step_cycle(b, k)
        assert (ca.linear_x, ca.linear_y, ca.angular_z) == (cb.linear_x, cb.linear_y, cb.angular_z)
        assert same_bits(a.optimizer.control_sequence, b.optimizer.control_sequence)
