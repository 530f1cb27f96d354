"""SmacPlannerHybrid: paths a car can drive, judged by geometry on real and hand-made costmaps."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from btnav.core.geometry import Pose2D
from btnav.costmap.cost_values import INSCRIBED_INFLATED_OBSTACLE
from btnav.costmap.costmap_2d import Costmap2D
from btnav.maps import load_map
from btnav.planning.exceptions import (
    GoalOccupied,
    NoValidPathCouldBeFound,
    PlannerCancelled,
    PlannerTimedOut,
    StartOccupied,
    StartOutsideMapBounds,
)
from btnav.planning.smac_common import GridCollisionChecker
from btnav.planning.smac_planner_hybrid import SmacPlannerHybrid, max_curvature

from .conftest import inflate

REPO = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def office() -> Costmap2D:
    """btnav's small office map, inflated as Nav2's default inflation layer would."""
    grid = load_map(REPO / "maps" / "small_office.yaml")
    costs = np.where(grid.data >= 65, 254, np.where(grid.data < 0, 255, 0)).astype(np.uint8)
    costs = inflate(costs, grid.resolution, 0.22, 0.55, 3.0)
    return Costmap2D(costs, grid.resolution, grid.origin.x, grid.origin.y)


def corridor(width_m: float = 0.8) -> Costmap2D:
    """A straight corridor along x, too narrow for a car of radius 0.5 m to turn round in."""
    res = 0.05
    costs = np.full((60, 200), 254, np.uint8)
    half = int(width_m / res / 2)
    costs[30 - half : 30 + half, 2:198] = 0
    return Costmap2D(costs, res, 0.0, 0.0)


def planner(**params) -> SmacPlannerHybrid:
    return SmacPlannerHybrid("GridBased", SmacPlannerHybrid.Params(**params))


def assert_drivable(path, costmap: Costmap2D, goal: Pose2D, radius: float) -> None:
    poses = path.poses
    assert np.all(costmap.cost_at(poses[:, :2]) < INSCRIBED_INFLATED_OBSTACLE)
    assert np.hypot(*(poses[-1, :2] - (goal.x, goal.y))) < 1e-6
    assert abs(np.angle(np.exp(1j * (poses[-1, 2] - goal.yaw)))) < 1e-6
    # No turn tighter than the radius (the smoother's result is kept only if so).
    assert max_curvature(poses) <= 1.0 / radius * 1.05


@pytest.mark.parametrize("model", ["DUBIN", "REEDS_SHEPP"])
@pytest.mark.parametrize(("start", "goal"), [((1, 1, 0), (6, 3, 3.14)), ((1, 1, 0), (10, 6, 1.57))])
def test_office_paths_are_collision_free_end_on_the_goal_and_respect_the_turning_radius(
    office, model, start, goal
):
    p = planner(motion_model_for_search=model, minimum_turning_radius=0.4)
    path = p.create_plan(Pose2D(*start), Pose2D(*goal), office)
    assert_drivable(path, office, Pose2D(*goal), 0.4)
    length = np.hypot(*np.diff(path.poses[:, :2], axis=0).T).sum()
    assert length >= np.hypot(goal[0] - start[0], goal[1] - start[1])


def test_reeds_shepp_backs_into_a_goal_behind_where_a_dubins_car_cannot_turn():
    cm = corridor()
    start, goal = Pose2D(6.0, 1.5, 0.0), Pose2D(3.0, 1.5, 0.0)  # 3 m straight behind
    path = planner(motion_model_for_search="REEDS_SHEPP", minimum_turning_radius=0.5).create_plan(
        start, goal, cm
    )
    assert_drivable(path, cm, goal, 0.5)
    heading = np.stack([np.cos(path.poses[:-1, 2]), np.sin(path.poses[:-1, 2])], axis=1)
    motion = np.diff(path.poses[:, :2], axis=0)
    assert np.all(np.sum(heading * motion, axis=1) <= 1e-9)  # it backs all the way
    with pytest.raises(NoValidPathCouldBeFound):  # a forward-only car has no way back
        planner(minimum_turning_radius=0.5, max_iterations=20000).create_plan(start, goal, cm)


def test_a_polygon_footprint_from_the_costmap_server_is_checked_not_just_its_centre():
    cm = corridor(width_m=1.0)
    start, goal = Pose2D(2.0, 1.5, 0.0), Pose2D(8.0, 1.5, 0.0)
    wide = np.array([[-0.2, -0.6], [0.6, -0.6], [0.6, 0.6], [-0.2, 0.6]])  # 1.2 m wide
    p = planner()
    p.configure(SimpleNamespace(use_radius=False, footprint=wide, circumscribed_cost=lambda: 0.0))
    with pytest.raises(StartOccupied):
        p.create_plan(start, goal, cm)
    narrow = wide * [1.0, 0.5]  # 0.6 m wide: fits
    p.configure(SimpleNamespace(use_radius=False, footprint=narrow, circumscribed_cost=lambda: 0.0))
    assert_drivable(p.create_plan(start, goal, cm), cm, goal, 0.4)


def test_start_and_goal_problems_are_nav2s_error_codes():
    cm = corridor()
    p = planner()
    with pytest.raises(StartOutsideMapBounds):
        p.create_plan(Pose2D(-1.0, 1.5, 0.0), Pose2D(3.0, 1.5, 0.0), cm)
    with pytest.raises(GoalOccupied):
        p.create_plan(Pose2D(3.0, 1.5, 0.0), Pose2D(3.0, 0.2, 0.0), cm)


def test_the_same_request_gives_the_same_path_bit_for_bit(office):
    a = planner().create_plan(Pose2D(1, 1, 0), Pose2D(6, 3, 3.14), office)
    b = planner().create_plan(Pose2D(1, 1, 0), Pose2D(6, 3, 3.14), office)
    assert a.poses.tobytes() == b.poses.tobytes()


def test_a_polygon_start_on_an_inscribed_cell_still_plans():
    """A polygon footprint may start on an inscribed cell, where the obstacle heuristic
    (inscribed cells are its walls) cannot reach: the search must still run."""
    costs = np.zeros((40, 120), np.uint8)
    costs[24:, :] = 254
    costs[20:24, :] = INSCRIBED_INFLATED_OBSTACLE  # a band along the wall
    cm = Costmap2D(costs, 0.05, 0.0, 0.0)
    small = np.array([[-0.04, -0.04], [0.04, -0.04], [0.04, 0.04], [-0.04, 0.04]])
    p = planner()
    p.configure(
        SimpleNamespace(use_radius=False, footprint=small, circumscribed_cost=lambda: 253.0)
    )
    start, goal = Pose2D(1.0, 1.11, 0.0), Pose2D(4.0, 0.5, 0.0)
    assert cm.cost_at(np.array([[start.x, start.y]]))[0] == INSCRIBED_INFLATED_OBSTACLE
    path = p.create_plan(start, goal, cm)
    assert np.hypot(*(path.poses[-1, :2] - (goal.x, goal.y))) < 1e-6
    assert max_curvature(path.poses) <= 1.0 / 0.4 * 1.05


def test_max_iterations_is_nav2s_timeout_and_a_cancel_stops_the_search(office):
    start, goal = Pose2D(1, 1, 0), Pose2D(10, 6, 1.57)
    with pytest.raises(PlannerTimedOut) as err:
        planner(max_iterations=100).create_plan(start, goal, office)
    assert err.value.error_code == 207  # ComputePathToPose's TIMEOUT, as Nav2 throws
    with pytest.raises(PlannerCancelled):
        planner().create_plan(start, goal, office, cancel_checker=lambda: True)


def test_a_replan_after_the_costmap_changed_sees_the_change():
    """The obstacle heuristic is reused between plans only while the costmap is the same."""
    cm = Costmap2D(np.zeros((80, 160), np.uint8), 0.05, 0.0, 0.0)
    p = planner()
    start, goal = Pose2D(1.0, 2.0, 0.0), Pose2D(7.0, 2.0, 0.0)
    first = p.create_plan(start, goal, cm)
    assert np.ptp(first.poses[:, 1]) < 0.05  # straight along the middle
    cm.costs[10:70, 78:84] = 254  # a wall across the middle, open at both ends
    second = p.create_plan(start, goal, cm)
    assert_drivable(second, cm, goal, 0.4)
    assert second.length() > first.length() + 0.5  # round the end of the wall
    # the very plan a planner that never saw the old costmap makes (no stale heuristic)
    assert second.poses.tobytes() == planner().create_plan(start, goal, cm).poses.tobytes()


@pytest.mark.parametrize("allow_unknown", [True, False])
def test_a_footprint_checked_per_cell_and_bin_is_the_footprint_laid_on_the_cells_centre(
    allow_unknown,
):
    """The search checks a polygon once per (cell, heading bin), at the cell's centre, as
    Nav2 does; each answer must be what laying the turned outline there gives, edge of
    the map (a vertex off it collides) and unknown cells included."""
    rng = np.random.default_rng(5)
    costs = np.where(rng.random((50, 70)) < 0.03, 254, 0).astype(np.uint8)
    costs[rng.random((50, 70)) < 0.02] = 255
    cm = Costmap2D(costs, 0.05, -1.3, 0.7)
    car = np.array([[-0.12, -0.15], [0.45, -0.15], [0.45, 0.15], [-0.12, 0.15]])
    for footprint, bins in ((car, 72), (rng.uniform(-0.3, 0.3, (5, 2)), 16)):
        ros = SimpleNamespace(use_radius=False, footprint=footprint, circumscribed_cost=lambda: 0.0)
        checker = GridCollisionChecker(cm, ros, allow_unknown, bins)
        cells = rng.integers(0, 50 * 70, 3000)
        b = rng.integers(0, bins, 3000)
        laid = checker.outline_hits(
            list(cells % 70 + 0.5), list(cells // 70 + 0.5), list(b * (2 * np.pi / bins))
        )
        table = [
            checker.footprint_hit(int(c) * bins + int(k)) for c, k in zip(cells, b, strict=True)
        ]
        assert table == laid
        assert 0 < sum(laid) < len(laid)  # both answers occur
