"""The optimizer's compiled steps after the critics (softmax_kernel.py,
sequence_limits_kernel.py) and before them (perturb_kernel.py) give the numpy path's
bits: random samples and costs, channels without a control cost, speeds beyond the
limits and backwards, a NaN in the sequence, and the same noise draws."""

from __future__ import annotations

import numpy as np
import pytest

from btnav.control.mppi.noise import NoiseGenerator

from .test_rollout_kernel import controller, same_bits


def updated(method: str, motion_model: str, speed, seed: int, **params):
    c = controller(motion_model, "numpy", **params)
    opt = c.optimizer
    rng = np.random.default_rng(seed)
    opt.u[:] = rng.normal(0.0, 0.4, opt.u.shape).astype(np.float32)
    opt.control_sequence[:] = rng.normal(0.0, 0.6, opt.control_sequence.shape)
    opt.control_sequence[7, 0] = np.nan
    costs = (rng.random(opt.u.shape[2]) * 50).astype(np.float32)
    opt.method = method  # type: ignore[assignment]
    opt._update_control_sequence(costs, speed)
    return costs, opt.control_sequence.copy()


@pytest.mark.parametrize(
    ("motion_model", "params"),
    [("diff_drive", {}), ("omni", {"wz_std": 0.0}), ("diff_drive", {"gamma": 0.0})],
)
@pytest.mark.parametrize("speed", [(0.2, 0.0, 0.1), (-0.6, 0.3, -2.5)])
def test_softmax_and_sequence_limits_match_numpy(motion_model, params, speed):
    for seed in range(3):
        a = updated("numpy", motion_model, speed, seed, **params)
        k = updated("kernel", motion_model, speed, seed, **params)
        assert same_bits(a[0], k[0]) and same_bits(a[1], k[1])


@pytest.mark.parametrize("regenerate", [False, True])
@pytest.mark.parametrize("channels", [2, 3])
def test_compiled_sampling_is_the_noise_plus_the_sequence(regenerate, channels):
    T, B = 56, 500
    stds = (0.2, 0.4, 0.1)[:channels]
    gens = [NoiseGenerator(np.random.default_rng(3), B, T, stds, regenerate) for _ in range(2)]
    seq = np.random.default_rng(4).normal(0, 0.5, (T, channels)).astype(np.float32)
    for _ in range(3):
        a = np.empty((T, channels, B), np.float32)
        gens[0].sample(a)
        np.add(a, seq[:, :, None], out=a)
        k = np.empty_like(a)
        gens[1].sample_controls(k, seq)
        assert same_bits(a, k)
