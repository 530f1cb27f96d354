"""PathAlignCritic's compiled scoring (path_align_kernel.py) gives the numpy path's float32
cost bits: random batches with and without blocked path points, with and without
use_path_orientations, short paths (down to one reached point), rollouts that travel
far beyond the reached part of the path, and whole controller cycles."""

from __future__ import annotations

import numpy as np
import pytest

from btnav.control.mppi.critic_data import DEFAULT_METHOD
from btnav.control.mppi.critics import PathAlignCritic, path_align_critic

from .batch import make_data, straight_path
from .test_rollout_kernel import controller, same_bits, step_cycle

T, B = 56, 400


def spy(monkeypatch: pytest.MonkeyPatch) -> list[int]:
    """A list that grows by one per call of the kernel from the critic."""
    calls: list[int] = []
    kernel = path_align_critic.path_align_costs

    def counted(*args):  # type: ignore[no-untyped-def]
        calls.append(1)
        return kernel(*args)

    monkeypatch.setattr(path_align_critic, "path_align_costs", counted)
    return calls


def random_path(rng: np.random.Generator, n: int) -> np.ndarray:
    """n points about 5 cm apart along a wandering curve from the robot; noisy yaws
    (some beyond +-pi) and a few repeated points (segments of length 0)."""
    heading = np.cumsum(rng.normal(0.0, 0.15, n))
    step = rng.uniform(0.03, 0.07, n)
    step[0] = 0.0
    step[rng.integers(1, n, n // 10)] = 0.0
    x, y = np.cumsum(step * np.cos(heading)), np.cumsum(step * np.sin(heading))
    yaw = heading + rng.normal(0.0, 0.5, n) + 2 * np.pi * rng.integers(-1, 2, n)
    return np.stack([x, y, yaw], axis=-1)


def random_rollouts(rng: np.random.Generator) -> np.ndarray:
    """(B, T, 3) random walks from the origin: most at path-like speeds, a quarter
    zigzagging fast (11 m travelled, far beyond any reached part of the path), some
    standing still."""
    heading = np.cumsum(rng.normal(0.0, 0.2, (B, T)), axis=1)
    speed = rng.uniform(0.0, 0.12, (B, 1)) * rng.uniform(0.5, 1.5, (B, T))
    zig = rng.random(B) < 0.25
    heading[zig] = np.where(np.arange(T) % 2, 1.4, -1.4)
    speed[zig] = 0.2
    speed[rng.random(B) < 0.05] = 0.0
    speed[:, 0] = 0.0
    x = np.cumsum(speed * np.cos(heading), axis=1)
    y = np.cumsum(speed * np.sin(heading), axis=1)
    yaw = heading + rng.normal(0.0, 0.3, (B, T))
    return np.stack([x, y, yaw], axis=-1)


def costs(method: str, trajs: np.ndarray, path: np.ndarray, blocked: float, **params) -> np.ndarray:
    c = PathAlignCritic(
        "PathAlignCritic",
        PathAlignCritic.Params(
            threshold_to_consider=0.0,
            offset_from_furthest=1,
            max_path_occupancy_ratio=1.0,
            **params,
        ),
    )
    c.method = method  # type: ignore[assignment]
    data = make_data(list(trajs), path=path)
    valid = np.random.default_rng(len(path)).random(len(path)) >= blocked
    valid[-1] = True
    data._valid = valid
    c.score(data)
    return data.costs


@pytest.mark.parametrize("orientations", [False, True])
@pytest.mark.parametrize("blocked", [0.0, 0.2, 0.9])
@pytest.mark.parametrize("n_path", [2, 3, 17, 80])
@pytest.mark.parametrize("step", [1, 4, 7])
def test_kernel_costs_give_the_numpy_bits(orientations, blocked, n_path, step, monkeypatch):
    calls = spy(monkeypatch)
    rng = np.random.default_rng(1000 * n_path + 10 * step + int(10 * blocked))
    trajs, path = random_rollouts(rng), random_path(rng, n_path)
    kw = {"use_path_orientations": orientations, "trajectory_point_step": step}
    a, b = costs("numpy", trajs, path, blocked, **kw), costs("kernel", trajs, path, blocked, **kw)
    assert same_bits(a, b)
    assert calls  # the critic scored, not gated out
    if blocked < 0.5:
        assert np.count_nonzero(a) > B // 4


def test_a_path_of_no_length_and_too_few_samples(monkeypatch):
    """A reached part of no length (the robot's point three times, then the path: every
    rollout compares with the first point), and rollouts of fewer steps than the stride
    (no sampled point after the first: cost 0)."""
    calls = spy(monkeypatch)
    rng = np.random.default_rng(7)
    path = np.concatenate([np.zeros((3, 3)), straight_path(1.0)[1:]])
    x = np.linspace(0.0, 0.06, T)[None, :] * rng.uniform(1.0, 1.2, (B, 1))
    slow = np.stack([x, np.zeros_like(x), rng.normal(0.0, 1.0, (B, T))], axis=-1)
    for orientations in (False, True):
        kw = {"use_path_orientations": orientations}
        a = costs("numpy", slow, path, 0.0, **kw)
        assert same_bits(a, costs("kernel", slow, path, 0.0, **kw))
        assert a.all()
    assert len(calls) == 2
    trajs = random_rollouts(rng)
    short = trajs[:, :3]
    path = random_path(rng, 40)
    a = costs("numpy", short, path, 0.0, trajectory_point_step=4)
    assert same_bits(a, costs("kernel", short, path, 0.0, trajectory_point_step=4))
    assert not a.any()


def test_the_default_is_the_optimizer_switch():
    assert PathAlignCritic.method == DEFAULT_METHOD


def test_controller_cycles_give_the_same_commands_and_sequences(monkeypatch):
    calls = spy(monkeypatch)
    a, b = controller("diff_drive", "kernel"), controller("diff_drive", "kernel")
    for c, method in ((a, "numpy"), (b, "kernel")):
        (critic,) = [k for k in c.optimizer.critics if isinstance(k, PathAlignCritic)]
        critic.method = method  # type: ignore[assignment]
    for k in range(4):
        ca, cb = step_cycle(a, k), step_cycle(b, k)
        assert (ca.linear_x, ca.linear_y, ca.angular_z) == (cb.linear_x, cb.linear_y, cb.angular_z)
        assert same_bits(a.optimizer.control_sequence, b.optimizer.control_sequence)
    assert calls  # the compiled path ran (the critic was not gated out)
