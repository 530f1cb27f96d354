"""PathAlignCritic keeps rollouts on the path, point by point at equal distance travelled.

Nav2 (path_align_critic.cpp): skipped while state.local_path_length <
threshold_to_consider (0.5), while the furthest path point any rollout reaches is below
offset_from_furthest (20), and when more than max_path_occupancy_ratio (0.07, and more
than 2) of the path points up to that furthest one are in collision. Otherwise, for
every trajectory_point_step-th rollout point (4) after the first, the rollout's length
so far picks the path point at the same length along the path (path points in
collision are skipped); the rollout pays cost_weight (10) times the mean distance,
raised to cost_power. With use_path_orientations the distance is
sqrt(dx^2 + dy^2 + dyaw^2).
"""

from __future__ import annotations

import numpy as np
import pytest

from btnav.control.mppi.critics import PathAlignCritic
from btnav.costmap.cost_values import LETHAL_OBSTACLE

from .batch import costmap, line, make_data, paint, path_length, polyline, straight_path

T = 13  # points 0, 4, 8 and 12 are sampled: three samples after the start
PATH = straight_path(3.0)  # 61 points, 5 cm apart, along +x from the robot at the origin


def critic(**params) -> PathAlignCritic:
    return PathAlignCritic("PathAlignCritic", PathAlignCritic.Params(**params))


def rollouts():
    """Travelled distance at the samples is 0.4, 0.8, 1.2 m for all but the last."""
    a = line(0.0, 0.0, 0.0, 0.1, T)  # on the path
    b = line(0.0, 0.2, 0.0, 0.1, T)  # parallel, 0.2 m to the left
    c = line(0.0, 0.0, np.arctan2(0.06, 0.08), 0.1, T)  # veering off at 36.9 degrees
    f = line(0.0, 0.0, 0.0, 0.1, T)  # on the path to x = 0.8, then 0.4 m straight left
    f[9:, 0], f[9:, 1] = 0.8, 0.1 * np.arange(1, 5)
    d = line(0.0, 0.0, 0.0, 0.15, T)  # on the path, faster: reaches x = 1.8 (point 36)
    return [a, b, c, f, d]


# Mean distance to the path point at equal length, at 0.4, 0.8 and 1.2 m travelled:
# c: (0.32, 0.24), (0.64, 0.48), (0.96, 0.72) against x = 0.4, 0.8, 1.2: 0.253, 0.506, 0.759
# f: 0, 0, |(0.8, 0.4) - (1.2, 0)| = 0.566
C_DISTS = [np.hypot(0.08, 0.24), np.hypot(0.16, 0.48), np.hypot(0.24, 0.72)]
F_LAST = np.hypot(0.4, 0.4)
EXPECTED = [0.0, 10 * 0.2, 10 * np.mean(C_DISTS), 10 * F_LAST / 3]  # a, b, c, f


def scored(trajs=None, cm=None, path=PATH, **params):
    data = make_data(rollouts() if trajs is None else trajs, path=path, cm=cm)
    critic(**params).score(data)
    return data


def test_defaults_are_nav2s():
    p = PathAlignCritic.Params()
    assert (p.cost_weight, p.cost_power, p.threshold_to_consider) == (10.0, 1, 0.5)
    assert (p.offset_from_furthest, p.trajectory_point_step) == (20, 4)
    assert p.max_path_occupancy_ratio == 0.07 and p.use_path_orientations is False


def test_mean_distance_to_the_path_at_equal_distance_travelled():
    data = scored()
    assert data.costs[:4] == pytest.approx(EXPECTED, abs=1e-4)  # 0, 2.0, 5.06, 1.886
    assert data.costs[0] == pytest.approx(0.0, abs=1e-5)
    assert np.argmax(data.costs) == 2


def test_weight_and_power():
    data = scored(cost_weight=5.0, cost_power=2)
    assert data.costs[:4] == pytest.approx([(e / 2) ** 2 for e in EXPECTED], abs=1e-3)
    assert (scored(enabled=False).costs == 0).all()


def test_trajectory_point_step_picks_the_samples():
    # Every 6th point: samples at 0.6 and 1.2 m travelled; c is 0.38 and 0.76 m off there.
    data = scored(trajectory_point_step=6)
    c = [np.hypot(0.12, 0.36), np.hypot(0.24, 0.72)]
    assert data.costs[2] == pytest.approx(10 * np.mean(c), abs=1e-4)


def test_near_the_goal_it_is_off():
    data = scored(path=straight_path(0.45))
    assert (data.costs == 0).all()


def test_off_until_the_rollouts_reach_offset_from_furthest():
    short = [line(0.0, 0.2, 0.0, 0.05, T)]  # reaches x = 0.6 (point 12) only
    assert (scored(short).costs == 0).all()
    # Aligned with points 0-11 only (those before the furthest): 0.2, 0.2, then 0.2 m
    # beside and 5 cm past point 11 (0.55, 0).
    expected = 10 * (0.2 + 0.2 + np.hypot(0.05, 0.2)) / 3
    assert scored(short, offset_from_furthest=12).costs[0] == pytest.approx(expected, abs=1e-4)


def test_a_blocked_path_point_is_skipped():
    cm = paint(costmap(), [(0.8, 0.0)], LETHAL_OBSTACLE)  # path point 16, at 0.8 m
    data = scored(cm=cm)
    # f's sample at 0.8 m is dropped: mean of 0 and 0.566; the others' means are unchanged.
    expected = [0.0, 2.0, EXPECTED[2], 10 * F_LAST / 2]
    assert data.costs[:4] == pytest.approx(expected, abs=1e-4)


def test_off_when_the_path_is_blocked():
    # Six of the first 36 path points under an obstacle: the robot must leave the path.
    cm = paint(costmap(), [(0.05 * i, 0.0) for i in range(5, 11)], LETHAL_OBSTACLE)
    assert (scored(cm=cm).costs == 0).all()
    # Two blocked points are tolerated whatever the ratio.
    cm = paint(costmap(), [(0.05 * i, 0.0) for i in range(5, 7)], LETHAL_OBSTACLE)
    assert scored(cm=cm).costs[1] == pytest.approx(2.0, abs=1e-4)


def test_use_path_orientations_adds_the_heading_error():
    on_path_turned = line(0.0, 0.0, 0.0, 0.1, T, yaw=0.3)
    data = scored([on_path_turned, rollouts()[4]], use_path_orientations=True)
    assert data.costs[0] == pytest.approx(10 * 0.3, abs=1e-4)


def test_use_path_orientations_combines_as_a_euclidean_norm():
    offset_turned = line(0.0, 0.2, 0.0, 0.1, T, yaw=0.15)
    data = scored([offset_turned, rollouts()[4]], use_path_orientations=True)
    assert data.costs[0] == pytest.approx(10 * np.hypot(0.2, 0.15), abs=1e-4)  # 2.5


def test_alignment_uses_the_path_up_to_the_furthest_point():
    data = scored()
    # d travels 1.8 m: Nav2's path stops at point 35 (1.75 m), 5 cm short at the last sample.
    assert data.costs[4] == pytest.approx(10 * 0.05 / 3, abs=1e-4)


def test_obstacles_beyond_the_furthest_point_do_not_switch_it_off():
    # Eleven points blocked at 2.25-2.75 m, beyond the furthest reached point (1.8 m).
    cm = paint(costmap(), [(0.05 * i, 0.0) for i in range(45, 56)], LETHAL_OBSTACLE)
    assert scored(cm=cm).costs[1] == pytest.approx(2.0, abs=1e-4)


def test_switch_is_judged_by_the_path_length():
    # A U-turn: the goal is 0.3 m away in a straight line, 1.5 m along the path.
    path = polyline((0.0, 0.0), (0.6, 0.0), (0.6, 0.3), (0.0, 0.3))
    assert path_length(path) == pytest.approx(1.5)
    beside = line(0.0, -0.1, 0.0, 0.05, T)  # 0.1 m beside the first leg
    ahead = np.concatenate([line(0.0, 0.0, 0.0, 0.075, 9), line(0.6, 0.0375, np.pi / 2, 0.0375, 4)])
    data = make_data([beside, ahead], path=path)  # ahead reaches path point 15 (0.6, 0.15)
    critic(offset_from_furthest=0).score(data)
    assert data.costs[0] == pytest.approx(10 * 0.1, abs=1e-4)
