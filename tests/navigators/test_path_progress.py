"""bt_navigator's distance_remaining (navigators/path_progress.py) against Nav2's plain
computation: the first closest pose within `search_window` metres along the path of
the last closest one (numpy's argmin of squared distances, cumsum + searchsorted for
the window), then the length left from it. The fast scan must find the same index and
the same length, ties and grid paths included."""

from __future__ import annotations

import numpy as np
import pytest

from btnav.core import fmath
from btnav.core.messages import Path
from btnav.navigators.path_progress import PathProgress


def nav2_remaining(poses: np.ndarray, start: int, window: float, x: float, y: float):
    seg = fmath.hypot(*np.diff(poses[:, :2], axis=0).T)
    end = start + 1 + int(np.searchsorted(np.cumsum(seg[start:]), window))
    stop = min(end + 1, len(poses))
    d = (poses[start:stop, 0] - x) ** 2 + (poses[start:stop, 1] - y) ** 2
    closest = start + int(d.argmin())
    return closest, float(seg[closest:].sum())


def grid_path(rng: np.random.Generator) -> np.ndarray:
    """A NavFn-like path: half-cell steps along a random walk of straight legs."""
    steps = rng.choice([-1, 0, 1], size=(rng.integers(20, 200), 2)) * 0.025
    steps = np.repeat(steps, rng.integers(1, 8, len(steps)), axis=0)
    xy = np.cumsum(steps, axis=0) + 1.0
    return np.concatenate([xy, np.zeros((len(xy), 1))], axis=1)


def wavy_path(rng: np.random.Generator) -> np.ndarray:
    t = np.sort(rng.uniform(0, 10, rng.integers(5, 300)))
    xy = np.stack([t, np.sin(t * rng.uniform(0.5, 3))], -1)
    return np.concatenate([xy, np.zeros((len(xy), 1))], axis=1)


@pytest.mark.parametrize("make", [grid_path, wavy_path])
def test_same_closest_pose_and_length_as_nav2s_computation(make):
    rng = np.random.default_rng(11)
    for _ in range(150):
        poses = make(rng)
        window = float(rng.choice([0.5, 1.0, 2.0, 0.025 * rng.integers(1, 40)]))
        progress = PathProgress(lambda w=window: w)
        path = Path(0.0, poses)
        start = 0
        for _ in range(20):
            k = rng.integers(len(poses))
            x, y = poses[k, 0] + rng.normal(0, 0.2), poses[k, 1] + rng.normal(0, 0.2)
            if rng.random() < 0.3:  # exactly on a pose: ties between equal distances
                x, y = float(poses[k, 0]), float(poses[k, 1])
            # the same position again (odometry at half the tree's rate) searches from
            # the pose the last search found, its window reaching further
            for _ in range(int(rng.integers(1, 4))):
                want = nav2_remaining(poses, start, window, x, y)
                got = progress.remaining(path, float(x), float(y))
                assert (progress.closest, got) == want
                start = progress.closest


def test_a_new_path_starts_from_its_first_pose():
    straight = np.stack([np.arange(0, 3, 0.05), np.zeros(60), np.zeros(60)], -1)
    progress = PathProgress(lambda: 2.0)
    progress.remaining(Path(0.0, straight), 1.5, 0.0)
    assert progress.closest == 30
    other = Path(0.0, straight.copy())
    assert progress.remaining(other, 2.9, 0.0) == pytest.approx(np.ptp(straight[40:, 0]))
    assert progress.closest == 40  # the window from pose 0 ends 2 m along
