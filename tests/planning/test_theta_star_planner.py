"""ThetaStarPlanner: any-angle paths as a Nav2 user sees them, on hand-made costmaps and
Nav2's benchmark map, against the 8-connected optimum of scipy's Dijkstra."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from btnav.core.errors import ParamsError
from btnav.core.geometry import Pose2D
from btnav.costmap.costmap_2d import Costmap2D
from btnav.params import load_params
from btnav.planning.exceptions import (
    ComputePathToPoseError,
    GoalOccupied,
    GoalOutsideMapBounds,
    NoValidPathCouldBeFound,
    PlannerCancelled,
    PlannerException,
    StartOutsideMapBounds,
)
from btnav.planning.theta_star_planner import ThetaStarGrid, ThetaStarPlanner
from btnav.plugins import lookup

from .conftest import inflate
from .test_smac_planner_2d import benchmark_pairs, cells_of, nav2_file_with, optimum

RES = 0.05

#: Theta*'s example in Nav2's configuration guide.
THETA_STAR_BLOCK = """\
    GridBased:
      plugin: "nav2_theta_star_planner::ThetaStarPlanner" # In Iron and older versions, "/" was used
      how_many_corners: 8
      w_euc_cost: 1.0
      w_traversal_cost: 2.0
      use_final_approach_orientation: false
      allow_unknown: true
"""


def planner(**params: object) -> ThetaStarPlanner:
    return ThetaStarPlanner("GridBased", ThetaStarPlanner.Params(**params))


def corners(path_xy: np.ndarray) -> np.ndarray:
    """The path's vertices: its ends and the points where its heading changes."""
    d = np.diff(path_xy, axis=0)
    heading = np.arctan2(d[:, 1], d[:, 0])
    turn = np.abs(np.angle(np.exp(1j * np.diff(heading)))) > 1e-9
    return np.vstack([path_xy[:1], path_xy[1:-1][turn], path_xy[-1:]])


def assert_clear(xy: np.ndarray, cm: Costmap2D) -> None:
    """No pose on an inscribed or lethal cell (Theta* never enters one)."""
    m = cells_of(xy, cm)
    assert cm.costs[m[:, 1], m[:, 0]].max() <= 252


@pytest.fixture(scope="module")
def inflated(benchmark_costmap: Costmap2D) -> Costmap2D:
    cm = benchmark_costmap.copy()
    cm.costs[:] = inflate(cm.costs, RES, 0.1, 0.55, 3.0)
    return cm


def test_registered_under_nav2_names() -> None:
    cls = ThetaStarPlanner
    assert lookup("planner", "nav2_theta_star_planner::ThetaStarPlanner") is cls
    assert lookup("planner", "nav2_theta_star_planner/ThetaStarPlanner") is cls


def test_defaults_are_nav2s() -> None:
    p = ThetaStarPlanner.Params()
    assert (p.how_many_corners, p.w_euc_cost, p.w_traversal_cost) == (8, 1.0, 2.0)
    assert (p.allow_unknown, p.terminal_checking_interval) == (True, 5000)
    assert p.use_final_approach_orientation is False


def test_free_space_diagonal_is_one_straight_segment() -> None:
    cm = Costmap2D.empty(120, 120, RES)
    start, goal = Pose2D(0.31, 0.31, 1.0), Pose2D(5.21, 2.11, 0.4)
    path = planner().create_plan(start, goal, cm)
    a, b = path.poses[0, :2], path.poses[-1, :2]
    assert a == pytest.approx([0.325, 0.325])  # the start cell's centre
    assert b == pytest.approx([5.225, 2.125])  # the goal cell's centre
    assert len(corners(path.poses[:, :2])) == 2
    assert path.length() == pytest.approx(math.dist(a, b))
    steps = np.hypot(*np.diff(path.poses[:, :2], axis=0).T)
    # points a resolution apart; the remainder (under two) is the last step, as in Nav2
    assert steps[:-1] == pytest.approx(RES) and RES <= steps[-1] < 2 * RES
    assert np.all(path.poses[:-1, 2] == 0.0) and path.poses[-1, 2] == pytest.approx(0.4)
    final = planner(use_final_approach_orientation=True).create_plan(start, goal, cm)
    assert final.poses[-1, 2] == pytest.approx(math.atan2(*(b - a)[::-1]))


def test_benchmark_map_paths_are_any_angle_clear_and_shorter_than_8_connected(
    inflated: Costmap2D,
) -> None:
    theta_star = planner()
    for start, goal in benchmark_pairs(inflated, 4):
        path = theta_star.create_plan(start, goal, inflated)
        assert_clear(path.poses[:, :2], inflated)
        assert path.poses[0, :2] == pytest.approx([start.x, start.y])
        assert path.poses[-1, :2] == pytest.approx([goal.x, goal.y])  # both on cell centres
        assert path.poses[-1, 2] == goal.yaw
        # shorter than the shortest 8-connected path between the same cells
        ends = cells_of(path.poses[[0, -1], :2], inflated)
        shortest = optimum(inflated.costs, tuple(ends[0]), tuple(ends[1]), 0.0) * RES
        assert start.distance_to(goal) - 1e-9 <= path.length() < shortest
        # any-angle: a handful of straight segments where a grid path turns at every step
        assert len(corners(path.poses[:, :2])) <= 6


def test_four_connected_expansion_still_plans_any_angle() -> None:
    cm = Costmap2D.empty(100, 80, RES)
    cm.costs[20:80, 50] = 254
    cm.costs[:] = inflate(cm.costs, RES, 0.1, 0.3, 3.0)
    start, goal = Pose2D(0.5, 3.5), Pose2D(4.5, 0.5)
    four = planner(how_many_corners=4).create_plan(start, goal, cm)
    eight = planner().create_plan(start, goal, cm)
    for path in (four, eight):
        assert_clear(path.poses[:, :2], cm)
        assert path.poses[-1, :2] == pytest.approx([goal.x, goal.y], abs=RES)
        assert len(corners(path.poses[:, :2])) <= 5
    assert four.length() == pytest.approx(eight.length(), rel=0.05)


def test_w_traversal_cost_keeps_away_from_obstacles() -> None:
    cm = Costmap2D.empty(120, 80, RES)
    cm.costs[30:50, 55:65] = 254
    cm.costs[:] = inflate(cm.costs, RES, 0.1, 1.5, 1.5)
    start, goal = Pose2D(0.5, 2.0), Pose2D(5.5, 2.0)

    def peak(w: float) -> int:
        path = planner(w_traversal_cost=w).create_plan(start, goal, cm)
        m = cells_of(path.poses[:, :2], cm)
        return int(cm.costs[m[:, 1], m[:, 0]].max())

    assert peak(0.0) > peak(1.0) > peak(5.0)


def test_unknown_space_and_allow_unknown() -> None:
    cm = Costmap2D.empty(100, 60, RES)
    cm.costs[:, 50] = 255  # an unknown band across the map
    cm.costs[0:5, 50] = 0  # a gap at the bottom
    start, goal = Pose2D(1.0, 2.0), Pose2D(4.0, 2.0)
    through = planner(allow_unknown=True).create_plan(start, goal, cm)
    around = planner(allow_unknown=False).create_plan(start, goal, cm)
    m = cells_of(around.poses[:, :2], cm)
    assert (cm.costs[m[:, 1], m[:, 0]] != 255).all()
    assert through.length() < around.length()
    cm.costs[0:5, 50] = 255
    with pytest.raises(NoValidPathCouldBeFound):
        planner(allow_unknown=False).create_plan(start, goal, cm)


def test_start_in_an_obstacle_is_cleared_for_the_plan() -> None:
    """Nav2's clearStart: the robot's own cell never blocks its plan (its neighbours do)."""
    cm = Costmap2D.empty(60, 60, RES)
    cm.costs[30, 30] = 254
    before = cm.costs.copy()
    path = planner().create_plan(Pose2D(30.5 * RES, 30.5 * RES), Pose2D(2.525, 2.525), cm)
    assert path.poses[-1, :2] == pytest.approx([2.525, 2.525])
    assert_clear(path.poses[1:, :2], cm)
    assert np.array_equal(cm.costs, before)  # the costmap itself is left as it was


def test_start_and_goal_in_one_cell_is_one_pose_at_the_start() -> None:
    cm = Costmap2D.empty(40, 40, RES)
    start, goal = Pose2D(1.01, 1.01, 0.5), Pose2D(1.04, 1.03, 1.5)
    assert planner().create_plan(start, goal, cm).poses.tolist() == [[1.01, 1.01, 1.5]]
    p = planner(use_final_approach_orientation=True).create_plan(start, goal, cm)
    assert p.poses.tolist() == [[1.01, 1.01, 0.5]]


def test_failures_are_nav2s_exceptions_and_error_codes() -> None:
    cm = Costmap2D.empty(100, 80, RES)
    cm.costs[10:30, 10:30] = 253
    cm.costs[20, 20] = 254
    free = Pose2D(3.0, 3.0)
    p = planner()
    cases = [
        (Pose2D(-1.0, 0.5), free, StartOutsideMapBounds, 203),
        (free, Pose2D(9.0, 1.0), GoalOutsideMapBounds, 204),
        (free, Pose2D(20.5 * RES, 20.5 * RES), GoalOccupied, 206),  # a lethal goal cell
        # an inscribed goal cell: Nav2's plain PlannerException
        (free, Pose2D(15.5 * RES, 15.5 * RES), PlannerException, 200),
    ]
    for start, goal, exc, code in cases:
        with pytest.raises(exc) as info:
            p.create_plan(start, goal, cm)
        assert info.value.error_code == code == ComputePathToPoseError(code)
    walled = Costmap2D.empty(100, 80, RES)
    walled.costs[:, 50] = 254
    with pytest.raises(NoValidPathCouldBeFound) as info:
        p.create_plan(Pose2D(0.5, 0.5), Pose2D(4.5, 0.5), walled)
    assert info.value.error_code == 208
    calls = []
    with pytest.raises(PlannerCancelled) as info:
        planner(terminal_checking_interval=50).create_plan(
            Pose2D(0.5, 0.5), Pose2D(4.5, 0.5), walled, lambda: calls.append(1) or True
        )
    assert info.value.error_code == 207 and len(calls) == 1


def test_line_of_sight_sums_the_cells_it_leaves_and_never_cuts_a_corner() -> None:
    cm = Costmap2D.empty(20, 20, RES)
    grid = ThetaStarGrid(cm.costs, (0, 0), True, 2.0)
    w = grid.w

    def cell(x: int, y: int) -> int:
        return (y + 1) * w + x + 1

    free = 2.0 * 26.0**2 / 252.0**2  # Nav2's traversal cost of a free cell
    assert grid.line_of_sight(cell(2, 2), cell(12, 5)) == pytest.approx(10 * free)
    assert grid.line_of_sight(cell(2, 2), cell(2, 2)) == 0.0
    cm.costs[3, 3] = 254  # on the diagonal from (2, 2) to (6, 6)
    blocked = ThetaStarGrid(cm.costs, (0, 0), True, 2.0)
    assert blocked.line_of_sight(cell(2, 2), cell(6, 6)) == -1.0
    cm.costs[3, 3] = 0
    cm.costs[2, 3] = 253  # (3, 2): a corner the step (2, 2) -> (3, 3) would cut
    corner = ThetaStarGrid(cm.costs, (0, 0), True, 2.0)
    assert corner.line_of_sight(cell(2, 2), cell(6, 6)) == -1.0
    assert corner.line_of_sight(cell(6, 6), cell(3, 3)) == pytest.approx(3 * free)


def test_plans_are_deterministic(inflated: Costmap2D) -> None:
    start, goal = benchmark_pairs(inflated, 1)[0]
    a = planner().create_plan(start, goal, inflated)
    b = planner().create_plan(start, goal, inflated)
    assert a.poses.tobytes() == b.poses.tobytes()


def test_nav2s_documented_config_loads_and_plans_in_the_office(
    nav2_params_file: Path, tmp_path: Path
) -> None:
    from ..nav.navstack_helpers import office, plan

    path, _ = nav2_file_with(nav2_params_file, tmp_path, THETA_STAR_BLOCK)
    loaded = load_params(path)
    section = loaded.server("planner_server").plugins["GridBased"]
    assert section.cls is ThetaStarPlanner
    assert not {e.key for e in loaded.ignored if e.key.startswith("planner_server.GridBased")}

    _world, rt, stack = office(path)
    theta_star = stack.planner_server.plugins["GridBased"]
    assert isinstance(theta_star, ThetaStarPlanner)
    goal = Pose2D(10.0, 6.0, 0.0)
    handle = plan(rt, goal)
    assert handle.succeeded, handle.result
    poses = handle.result.value.poses
    assert math.hypot(poses[-1, 0] - goal.x, poses[-1, 1] - goal.y) <= RES
    assert theta_star.nodes_opened > 0
    assert_clear(poses[:, :2], stack.global_costmap.costmap)
    # through two doorways: straight legs bent where the inflation's costs bend them, not
    # a staircase of grid steps
    assert len(corners(poses[:, :2])) < len(poses) / 10


def test_misspelt_key_names_file_line_and_spelling(nav2_params_file: Path, tmp_path: Path) -> None:
    path, line = nav2_file_with(
        nav2_params_file, tmp_path, THETA_STAR_BLOCK, "w_euc_cost: 1.0", "w_euclid_cost: 1.0"
    )
    with pytest.raises(ParamsError) as info:
        load_params(path)
    err = info.value
    assert (err.file, err.line, err.key, err.suggestion) == (
        str(path),
        line,
        "planner_server.GridBased.w_euclid_cost",
        "w_euc_cost",
    )


def test_how_many_corners_other_than_4_or_8_is_an_error(
    nav2_params_file: Path, tmp_path: Path
) -> None:
    path, line = nav2_file_with(
        nav2_params_file, tmp_path, THETA_STAR_BLOCK, "how_many_corners: 8", "how_many_corners: 6"
    )
    with pytest.raises(ParamsError) as info:
        load_params(path)
    err = info.value
    assert (err.line, err.key) == (line, "planner_server.GridBased.how_many_corners")
    assert "4 or 8" in err.message
