"""bt_navigator's distance_remaining (navigators/path_progress.py) against Nav2's plain
computation: the first closest pose within `search_window` metres along the path of
the last closest one (numpy's argmin of squared distances, cumsum + searchsorted for
the window), then the length left from it (`calculate_path_length`'s loop). The fast
scan must find the same index, ties and grid paths included, and the same length up to
rounding (btnav sums each path once, from its end)."""

from __future__ import annotations

import numpy as np
import pytest

from btnav.core import fmath
from btnav.core.messages import Path
from btnav.core.path_utils import first_after_integrated_distance
from btnav.navigators.path_progress import PathProgress


def nav2_remaining(poses: np.ndarray, start: int, window: float, x: float, y: float):
    seg = fmath.hypot(*np.diff(poses[:, :2], axis=0).T)
    end = start + 1 + int(np.searchsorted(np.cumsum(seg[start:]), window))
    stop = min(end + 1, len(poses))
    d = (poses[start:stop, 0] - x) ** 2 + (poses[start:stop, 1] - y) ** 2
    closest = start + int(d.argmin())
    length = 0.0
    for s in seg[closest:].tolist():  # nav2_util::calculate_path_length
        length += s
    return closest, length


def searched_as_nav2(progress: PathProgress, path: Path, start: int, window: float, x, y) -> int:
    """One search from `start`: the closest pose and length left are Nav2's; returns the
    closest pose, where the next search starts."""
    got = progress.remaining(path, float(x), float(y))
    closest, length = nav2_remaining(path.poses, start, window, x, y)
    assert progress.closest == closest
    assert got == pytest.approx(length, rel=1e-13, abs=1e-13)
    return progress.closest


def grid_path(rng: np.random.Generator) -> np.ndarray:
    """A NavFn-like path: half-cell steps along a random walk of straight legs."""
    steps = rng.choice([-1, 0, 1], size=(rng.integers(20, 200), 2)) * 0.025
    steps = np.repeat(steps, rng.integers(1, 8, len(steps)), axis=0)
    xy = np.cumsum(steps, axis=0) + 1.0
    return np.concatenate([xy, np.zeros((len(xy), 1))], axis=1)


def cell_centre_path(rng: np.random.Generator) -> np.ndarray:
    """NavFn's path on a 5 cm grid: cell centres along axis-aligned legs, so a window a
    multiple of 5 cm ends in a tie within rounding from almost every start."""
    moves = rng.choice([[1, 0], [0, 1], [-1, 0], [0, -1]], size=int(rng.integers(3, 12)))
    cells = np.cumsum(np.repeat(moves, rng.integers(5, 60, len(moves)), axis=0), axis=0)
    xy = rng.uniform(-3.0, 3.0, 2) + (cells + 0.5) * 0.05
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
                start = searched_as_nav2(progress, path, start, window, x, y)


def test_a_new_path_starts_from_its_first_pose():
    straight = np.stack([np.arange(0, 3, 0.05), np.zeros(60), np.zeros(60)], -1)
    progress = PathProgress(lambda: 2.0)
    progress.remaining(Path(0.0, straight), 1.5, 0.0)
    assert progress.closest == 30
    other = Path(0.0, straight.copy())
    assert progress.remaining(other, 2.9, 0.0) == pytest.approx(np.ptp(straight[40:, 0]))
    assert progress.closest == 40  # the window from pose 0 ends 2 m along


@pytest.mark.parametrize("make", [grid_path, cell_centre_path, wavy_path])
def test_a_robot_moving_along_the_path_is_searched_as_nav2_does(make):
    """Small steps near the path (the searches a scan's certificate answers), now and then
    exactly on a pose or a midpoint between two (ties), now and then a jump; half of them
    searched twice (from where the first ended: the window may have moved on)."""
    rng = np.random.default_rng(5)
    for _ in range(60):
        poses = make(rng)
        window = float(rng.choice([0.5, 2.0, 0.025 * rng.integers(1, 40)]))
        progress = PathProgress(lambda w=window: w)
        path = Path(0.0, poses)
        start, k = 0, 0.0
        for _ in range(150):
            k = min(k + abs(rng.normal(0.3, 0.4)), len(poses) - 1.0)
            if rng.random() < 0.05:
                k = float(rng.integers(len(poses)))
            i = int(k)
            j = min(i + 1, len(poses) - 1)
            x, y = poses[i, :2] + (k - i) * (poses[j, :2] - poses[i, :2])
            x, y = float(x), float(y)
            roll = rng.random()
            if roll < 0.15:  # on a pose
                x, y = float(poses[i, 0]), float(poses[i, 1])
            elif roll < 0.3:  # halfway between two poses
                x, y = (
                    (float(poses[i, 0]) + poses[j, 0]) / 2,
                    (float(poses[i, 1]) + poses[j, 1]) / 2,
                )
            else:
                x, y = x + rng.normal(0, 0.01), y + rng.normal(0, 0.01)
            start = searched_as_nav2(progress, path, start, window, x, y)
            if rng.random() < 0.5:  # the robot where it was (odometry at half the rate)
                start = searched_as_nav2(progress, path, start, window, x, y)


def hairpin_path(rng: np.random.Generator) -> np.ndarray:
    """Out along y = 0 and back along y = gap, the legs a few centimetres apart (poses of
    the way back are near the robot while far along the path), the poses 1 to 12 cm apart
    (a sparse path: the next pose along can be further than the next leg)."""
    step, gap = rng.uniform(0.01, 0.12), rng.uniform(0.02, 0.12)
    out = np.arange(0.0, rng.uniform(0.3, 1.5), step)
    xy = np.concatenate([np.stack([out, 0 * out], -1), np.stack([out[::-1], gap + 0 * out], -1)])
    return np.concatenate([xy, np.zeros((len(xy), 1))], axis=1)


def zigzag_path(rng: np.random.Generator) -> np.ndarray:
    """Three to six legs to and fro a few centimetres apart, as `hairpin_path`: from a
    pose on one leg, the poses of the legs after the next lie far along the path but
    near the robot, past the end of a window that starts on the next leg."""
    step, gap = rng.uniform(0.01, 0.12), rng.uniform(0.02, 0.06)
    out = np.arange(0.0, rng.uniform(0.1, 0.6), step)
    legs = [
        np.stack([out if k % 2 == 0 else out[::-1], k * gap + 0 * out], -1)
        for k in range(int(rng.integers(3, 7)))
    ]
    xy = np.concatenate(legs)
    return np.concatenate([xy, np.zeros((len(xy), 1))], axis=1)


@pytest.mark.parametrize("make", [hairpin_path, zigzag_path])
def test_a_robot_between_the_legs_of_a_folded_path_is_searched_as_nav2_does(make):
    rng = np.random.default_rng(3)
    for _ in range(200):
        poses = make(rng)
        # a window of a leg or two, or of every leg
        window = float(rng.choice([0.25, 0.5, 2.0]))
        progress = PathProgress(lambda w=window: w)
        path = Path(0.0, poses)
        start = 0
        x, y = float(poses[0, 0]), 0.0
        for _ in range(100):
            # steps of a few cm in any direction, drifting along and across the legs
            x += float(rng.normal(0.008, 0.012))
            y = float(np.clip(y + rng.normal(0, 0.015), -0.05, 0.15))
            start = searched_as_nav2(progress, path, start, window, x, y)
            # the same spot again, from the pose just found: its window reaches further,
            # perhaps to the poses of a leg further on near the robot
            start = searched_as_nav2(progress, path, start, window, x, y)


def test_a_near_pose_left_behind_is_not_taken_for_the_closest():
    """A sparse path turning sharply: the robot steps 3 cm towards the second pose (it
    becomes the closest), then, still within 3 cm of where the search scanned, towards
    the third, which was just too far then to be among the near poses: the third is the
    closest now, though the second is nearer than the near poses' reach."""
    turn = np.radians(48.0)
    poses = np.array(
        [
            [0.0, 0.0, 0.0],
            [0.059, 0.0, 0.0],
            [0.0601 * np.cos(turn), 0.0601 * np.sin(turn), 0.0],
            [0.0, 1.0, 0.0],
        ]
    )
    progress = PathProgress(lambda: 2.0)
    path = Path(0.0, poses)
    start = 0
    steps = [(0.0, 0.0, 0), (0.0299, 0.0, 1), (0.0299 * np.cos(turn), 0.0299 * np.sin(turn), 2)]
    for x, y, closest in steps:
        start = searched_as_nav2(progress, path, start, 2.0, x, y)
        assert start == closest


def polyline_path(rng: np.random.Generator) -> np.ndarray:
    """Legs of 2 to 10 cm in random directions: sharp turns, poses far apart."""
    heading = np.cumsum(rng.uniform(-2.0, 2.0, rng.integers(5, 60)))
    step = rng.uniform(0.02, 0.1, len(heading))
    xy = np.cumsum(np.stack([step * np.cos(heading), step * np.sin(heading)], -1), axis=0)
    return np.concatenate([xy, np.zeros((len(xy), 1))], axis=1)


def test_a_robot_wandering_about_a_sparse_winding_path_is_searched_as_nav2_does():
    rng = np.random.default_rng(8)
    for _ in range(200):
        poses = polyline_path(rng)
        progress = PathProgress(lambda: 2.0)
        path = Path(0.0, poses)
        start = 0
        x, y = float(poses[0, 0]), float(poses[0, 1])
        for _ in range(60):
            # a step of up to a few cm, half of it towards the pose after the closest
            ahead = poses[min(start + 1, len(poses) - 1), :2]
            x += float(0.3 * (ahead[0] - x) + rng.normal(0, 0.012))
            y += float(0.3 * (ahead[1] - y) + rng.normal(0, 0.012))
            start = searched_as_nav2(progress, path, start, 2.0, x, y)


def test_a_changed_search_window_holds_from_the_next_path():
    straight = np.stack([np.arange(0, 3, 0.05), np.zeros(60), np.zeros(60)], -1)
    window = [2.0]
    progress = PathProgress(lambda: window[0])
    first = Path(0.0, straight)
    progress.remaining(first, 0.0, 0.0)
    window[0] = 0.5  # bt_navigator's params set again while a path is followed
    progress.remaining(first, 1.0, 0.0)
    progress.remaining(first, 2.9, 0.0)
    assert progress.closest == 58  # the path's windows all 2 m long, as when it came
    path = Path(0.0, straight.copy())
    want = nav2_remaining(straight, 0, 0.5, 2.9, 0.0)[1]
    assert progress.remaining(path, 2.9, 0.0) == pytest.approx(want, rel=1e-13)
    assert progress.closest == 10  # the next path's window from pose 0 ends 0.5 m along


@pytest.mark.parametrize("make", [grid_path, cell_centre_path, wavy_path])
def test_every_window_ends_where_nav2s_cumsum_and_searchsorted_end_it(make):
    """The window's end (core.path_utils, at or past `search_window`) is Nav2's, start by
    start: grid paths tie within rounding most."""
    rng = np.random.default_rng(13)
    for _ in range(200):
        poses = make(rng)
        window = float(rng.choice([0.5, 2.0, 0.025 * rng.integers(1, 40), 1e9]))
        seg = fmath.hypot(*np.diff(poses[:, :2], axis=0).T)
        for i in rng.permutation(len(poses))[:12].tolist():
            want = i + 1 + int(np.searchsorted(np.cumsum(seg[i:]), window))
            got = first_after_integrated_distance(seg, i, window, reaching=True)
            assert got == min(want, len(poses))


def tangled_path(rng: np.random.Generator) -> np.ndarray:
    """Poses scattered over a box of 5 to 40 cm, some in dense runs: the path crosses
    itself everywhere, so a pose far along it is often near the robot, past where a
    window that starts a few poses on reaches."""
    xy = rng.uniform(0.0, rng.uniform(0.05, 0.4), (int(rng.integers(10, 80)), 2))
    if rng.random() < 0.5:
        xy = np.repeat(xy, rng.integers(1, 6, len(xy)), axis=0)
        xy = xy + rng.normal(0.0, 0.01, xy.shape)
    return np.concatenate([xy, np.zeros((len(xy), 1))], axis=1)


def test_a_robot_wandering_about_a_tangled_path_is_searched_as_nav2_does():
    """Each spot searched twice, the second time from the pose the first found: the
    search kept from the first must be the one Nav2 makes from there."""
    rng = np.random.default_rng(2)
    for _ in range(150):
        poses = tangled_path(rng)
        window = float(rng.uniform(0.05, 1.5))
        progress = PathProgress(lambda w=window: w)
        path = Path(0.0, poses)
        start = 0
        x, y = float(poses[0, 0]), float(poses[0, 1])
        for _ in range(60):
            x += float(rng.normal(0, 0.01))
            y += float(rng.normal(0, 0.01))
            start = searched_as_nav2(progress, path, start, window, x, y)
            start = searched_as_nav2(progress, path, start, window, x, y)
