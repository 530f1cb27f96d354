"""FeasiblePathHandler prunes the plan around the robot as nav2_controller's does."""

from __future__ import annotations

import math

import numpy as np
import pytest

from btnav.control.exceptions import InvalidPath
from btnav.control.path_handler import FeasiblePathHandler, first_path_constraint
from btnav.core.geometry import Pose2D
from btnav.core.messages import Path
from btnav.costmap.costmap_2d import Costmap2D


def line(n=201, step=0.05):
    x = np.arange(n) * step
    return Path(0.0, np.stack([x, np.zeros(n), np.zeros(n)], axis=-1), "map")


def big_costmap():
    return Costmap2D.empty(400, 400, 0.05, -10.0, -10.0, frame_id="odom")


def test_prunes_behind_and_beyond_prune_distance():
    ph = FeasiblePathHandler()
    ph.set_plan(line())
    local = ph.transform_global_plan(Pose2D(3.02, 0.1, 0.0), big_costmap())
    assert local.poses[0, 0] == pytest.approx(3.0)
    assert local.length() == pytest.approx(2.0, abs=0.06)  # prune_distance 2.0
    # Poses behind the robot are gone for good.
    local = ph.transform_global_plan(Pose2D(0.0, 0.0, 0.0), big_costmap())
    assert local.poses[0, 0] == pytest.approx(3.0)
    assert local.frame_id == "odom"


def test_transform_into_costmap_frame_and_cut_at_costmap_edge():
    ph = FeasiblePathHandler()
    ph.set_plan(line())
    small = Costmap2D.empty(40, 40, 0.05, 0.0, -1.0)  # 2 m x 2 m
    odom_T_map = Pose2D(0.5, 0.0, 0.0)
    local = ph.transform_global_plan(Pose2D(0.0, 0.0, 0.0), small, odom_T_map)
    assert local.poses[0, 0] == pytest.approx(0.5)
    assert local.poses[-1, 0] < 2.0
    goal = ph.transformed_goal(odom_T_map)
    assert goal.x == pytest.approx(10.5)


def test_near_goal_keeps_two_poses_and_empty_plans_fail():
    ph = FeasiblePathHandler()
    ph.set_plan(line(5))
    local = ph.transform_global_plan(Pose2D(1.0, 0.0, 0.0), big_costmap())
    assert len(local) == 2
    ph.set_plan(Path(0.0, np.zeros((0, 3))))
    with pytest.raises(InvalidPath) as err:
        ph.transform_global_plan(Pose2D(), big_costmap())
    assert err.value.error_code == 103
    ph = FeasiblePathHandler(params=FeasiblePathHandler.Params(reject_unit_path=True))
    ph.set_plan(Path(0.0, np.zeros((1, 3))))
    with pytest.raises(InvalidPath):
        ph.transform_global_plan(Pose2D(), big_costmap())


def test_path_inversion_is_enforced():
    fwd = np.stack([np.arange(0, 2.01, 0.1), np.zeros(21), np.zeros(21)], axis=-1)
    back = fwd[::-1][1:].copy()
    back[:, 2] = 0.0
    plan = Path(0.0, np.concatenate([fwd, back]))
    ph = FeasiblePathHandler(params=FeasiblePathHandler.Params(enforce_path_inversion=True))
    ph.set_plan(plan)
    local = ph.transform_global_plan(Pose2D(0.0, 0.0, 0.0), big_costmap())
    assert local.poses[:, 0].max() == pytest.approx(2.0)
    assert len(local) == 21  # up to the cusp only
    # At the cusp the rest of the plan is released (from the next cycle on, as in Nav2).
    ph.transform_global_plan(Pose2D(2.0, 0.0, 0.0), big_costmap())
    local = ph.transform_global_plan(Pose2D(2.0, 0.0, 0.0), big_costmap())
    assert local.poses[-1, 0] < 1.0


def test_in_place_rotation_constraint():
    p = np.array([[0, 0, 0], [1, 0, 0], [1, 0, 0.5], [1, 0, 1.0], [2, 0, 1.0]], float)
    assert first_path_constraint(p, False, 0.785) == 3
    assert first_path_constraint(p, False, 0.0) == 5
    inv = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [1, 0, 0], [0, 0, 0]], float)
    assert first_path_constraint(inv, True, 0.0) == 3
    assert first_path_constraint(inv[:2], True, 0.0) == 2
    assert math.isfinite(first_path_constraint(inv, False, 0.0))
