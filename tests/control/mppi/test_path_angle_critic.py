"""PathAngleCritic turns rollouts towards the path when the robot faces away from it.

Nav2 (path_angle_critic.cpp): skipped while state.local_path_length <
threshold_to_consider (0.5). The target is the path point offset_from_furthest (4) past
the furthest one any rollout reaches. Nothing is charged while the robot's own angle to
the target is under max_angle_to_furthest (0.785): in mode 0 its heading's angle to
it, in mode 1 (no directional preference) the smaller of that and its reverse's, in
mode 2 the heading's angle to the way the path's orientation says to drive there.
Otherwise each rollout pays cost_weight (2.2) times the angle between its last pose's
heading and the direction from its last point to the target (mode 1: or the reverse,
whichever is closer; mode 2: the direction flipped when it opposes the path's yaw),
raised to cost_power. Mode 1 falls back to mode 0 when vx_min is 0 (no reversing).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from btnav.control.mppi.critics import PathAngleCritic

from .batch import make_data, path_length, polyline

T = 5
TARGET = (-1.0, 4.0)  # up and behind-left of the robot at the origin facing +x
TO_TARGET = math.atan2(4.0, -1.0)  # 1.8158 rad from the robot's heading
W = 2.2


def critic(**params) -> PathAngleCritic:
    params.setdefault("offset_from_furthest", 4)
    return PathAngleCritic("PathAngleCritic", PathAngleCritic.Params(**params))


def path_towards(x: float, y: float, yaw: float | None = None, points: int = 9):
    """A straight path from the robot through (x, y) at its 5th point (index 4)."""
    i = np.arange(points)[:, None] / 4.0
    yaw = math.atan2(y, x) if yaw is None else yaw
    return np.concatenate([i * (x, y), np.full((points, 1), yaw)], axis=1)


def parked(yaw):
    yaws = np.broadcast_to(np.asarray(yaw, float), (T,))
    return np.stack([np.zeros(T), np.zeros(T), yaws], -1)


def scored(path=None, trajs=None, data_kw=None, **params):
    trajs = [parked(0.0), parked(TO_TARGET), parked(math.pi)] if trajs is None else trajs
    path = path_towards(*TARGET) if path is None else path
    data = make_data(trajs, path=path, **(data_kw or {}))
    critic(**params).score(data)
    return data


def test_defaults_are_nav2s_but_the_offset():
    p = PathAngleCritic.Params()
    assert (p.cost_weight, p.cost_power, p.threshold_to_consider) == (2.2, 1, 0.5)
    assert p.max_angle_to_furthest == 0.785398 and p.mode == 0


def test_default_offset_from_furthest_is_4():
    assert PathAngleCritic.Params().offset_from_furthest == 4


def test_facing_away_each_rollout_pays_its_heading_error_to_the_target():
    data = scored()
    # atan2(4, -1) = 1.816 rad * 2.2 = 3.995 (Nav2's own test number); facing it: 0;
    # facing back: pi - 1.816 = 1.326 rad * 2.2 = 2.917.
    expected = [W * TO_TARGET, 0.0, W * (math.pi - TO_TARGET)]
    assert data.costs == pytest.approx(expected, abs=1e-4)
    assert np.argmin(data.costs) == 1


def test_off_while_the_robot_already_faces_the_target():
    assert (scored(path=path_towards(1.0, 0.0)).costs == 0).all()
    # 0.7 rad off is inside max_angle_to_furthest (0.785) ...
    assert (scored(path=path_towards(math.cos(0.7), math.sin(0.7))).costs == 0).all()
    # ... 0.9 rad is not.
    assert scored(path=path_towards(math.cos(0.9), math.sin(0.9))).costs[0] == pytest.approx(
        W * 0.9, abs=1e-4
    )


def test_off_near_the_goal():
    short = path_towards(-0.1, 0.4, points=5)  # 0.41 m of path
    assert (scored(path=short).costs == 0).all()
    assert scored(path=path_towards(-0.1, 0.4, points=7)).costs[0] > 0  # 0.62 m


def test_offset_from_furthest_picks_the_target():
    # Target at point 2 of the path instead: (-0.5, 2), in the same direction.
    data = scored(offset_from_furthest=2)
    assert data.costs[0] == pytest.approx(W * TO_TARGET, abs=1e-4)
    # Past the path's end, the last point.
    data = scored(path=path_towards(1.0, 2.0, points=3), offset_from_furthest=10)
    assert data.costs[0] == pytest.approx(W * math.atan2(1.0, 0.5), abs=1e-4)


def test_no_directional_preference_accepts_driving_there_backwards():
    data = scored(mode=1)
    # Facing 0: the reverse heading is 1.326 rad from the target (Nav2's test: 2.9167).
    expected = [W * (math.pi - TO_TARGET), 0.0, W * (math.pi - TO_TARGET)]
    assert data.costs == pytest.approx(expected, abs=1e-4)
    # A target straight behind is no reason to turn without a preference (Nav2's test) ...
    assert (scored(path=path_towards(-1.0, 0.0), mode=1).costs == 0).all()
    # ... but is with forward preference.
    assert scored(path=path_towards(-1.0, 0.0)).costs[0] == pytest.approx(W * math.pi, abs=1e-4)


def test_feasible_path_orientations_follow_the_paths_direction():
    # The path's poses face the way it leads: as forward preference.
    forward = scored(mode=2)
    assert forward.costs == pytest.approx([W * TO_TARGET, 0.0, W * (math.pi - TO_TARGET)], abs=1e-4)
    # The path's poses face back towards the robot: it is to be driven in reverse.
    reverse = scored(path=path_towards(*TARGET, yaw=TO_TARGET - math.pi), mode=2)
    expected = [W * (math.pi - TO_TARGET), W * math.pi, W * TO_TARGET]
    assert reverse.costs == pytest.approx(expected, abs=1e-4)


def test_weight_and_power():
    data = scored(cost_weight=1.0, cost_power=2)
    assert data.costs == pytest.approx([TO_TARGET**2, 0.0, (math.pi - TO_TARGET) ** 2], abs=1e-4)
    assert (scored(enabled=False).costs == 0).all()


def test_only_the_last_pose_is_scored():
    turning = np.stack([np.zeros(T), np.zeros(T), np.linspace(0.0, TO_TARGET, T)], -1)
    data = scored(trajs=[turning])
    assert data.costs[0] == pytest.approx(0.0, abs=1e-5)


def test_no_directional_preference_without_reversing_is_forward_preference():
    data = scored(mode=1, data_kw={"vx_min": 0.0})
    assert data.costs[0] == pytest.approx(W * TO_TARGET, abs=1e-4)


def test_switch_is_judged_by_the_path_length():
    # Round a corner: the goal is 0.22 m away in a straight line, 0.7 m along the path.
    path = polyline((0.0, 0.0), (0.0, 0.3), (-0.2, 0.3), (-0.2, 0.1))
    assert path_length(path) == pytest.approx(0.7)
    data = scored(path=path, trajs=[parked(0.0)])  # target: point 4, (0, 0.2), 90 degrees
    assert data.costs[0] == pytest.approx(W * math.pi / 2, abs=1e-4)
