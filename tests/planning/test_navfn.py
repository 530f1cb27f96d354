"""NavfnPlanner on hand-made costmaps and on Nav2's benchmark map."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

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
    StartOccupied,
    StartOutsideMapBounds,
)
from btnav.planning.navfn import POT_HIGH, navfn_costs
from btnav.planning.navfn_planner import NavfnPlanner
from btnav.plugins import lookup

from .conftest import inflate

RES = 0.05


def planner(**params: object) -> NavfnPlanner:
    return NavfnPlanner("GridBased", NavfnPlanner.Params(**params))


def free_map(nx: int = 100, ny: int = 60) -> Costmap2D:
    return Costmap2D.empty(nx, ny, RES)


def wall_with_door(door: tuple[int, int] = (40, 46)) -> Costmap2D:
    cm = free_map(100, 80)
    cm.costs[:, 50] = 254
    cm.costs[door[0] : door[1], 50] = 0
    return cm


def path_cost(path_xy: np.ndarray, cm: Costmap2D) -> float:
    """NavFn-cost integral along a path (mapped cost per metre)."""
    mid = (path_xy[1:] + path_xy[:-1]) / 2
    seg = np.hypot(*np.diff(path_xy, axis=0).T)
    c = navfn_costs(cm.costs, True)
    m, _ = cm.world_to_map(mid)
    return float(np.sum(seg * c[m[:, 1], m[:, 0]]))


def assert_clear(path_xy: np.ndarray, cm: Costmap2D, max_cost: int = 252) -> None:
    m, inside = cm.world_to_map(path_xy)
    assert inside.all()
    assert cm.costs[m[:, 1], m[:, 0]].max() <= max_cost


def test_registered_under_nav2_names() -> None:
    assert lookup("planner", "nav2_navfn_planner::NavfnPlanner") is NavfnPlanner
    assert lookup("planner", "nav2_navfn_planner/NavfnPlanner") is NavfnPlanner


def test_nav2_params_gridbased_section_validates(nav2_params_file: Path) -> None:
    section = load_params(nav2_params_file).server("planner_server").plugins["GridBased"]
    assert section.cls is NavfnPlanner
    p = section.params
    assert (p.tolerance, p.use_astar, p.allow_unknown, p.max_cycles_factor) == (0.5, False, True, 4)


def test_cost_mapping_is_navfns() -> None:
    costs = np.array(
        [[0, 0, 0, 0, 0, 0, 0]] * 2 + [[0, 100, 252, 253, 254, 255, 0]] + [[0] * 7] * 2, np.uint8
    )
    c = navfn_costs(costs, allow_unknown=True)
    assert c[2, 1:6].tolist() == [130, 251, 254, 254, 253]
    assert navfn_costs(costs, allow_unknown=False)[2, 5] == 254
    assert c[0].tolist() == [254] * 7 and c[:, 0].tolist() == [254] * 5  # border


@pytest.mark.parametrize("use_astar", [False, True])
def test_straight_line_in_free_space(use_astar: bool) -> None:
    cm = free_map()
    start, goal = Pose2D(0.5, 1.5, 0.0), Pose2D(4.0, 1.5, 0.7)
    path = planner(use_astar=use_astar).create_plan(start, goal, cm)
    assert path.frame_id == "map"
    assert path.length() == pytest.approx(3.5, abs=0.06)
    assert np.abs(path.poses[:, 1] - 1.5).max() < 0.05
    assert path.poses[0, :2] == pytest.approx([0.525, 1.525])  # the start cell's centre
    assert path.poses[-1] == pytest.approx([4.0, 1.5, 0.7])  # ends exactly at the goal
    assert np.all(path.poses[:-1, 2] == 0.0)  # Nav2 leaves intermediate orientations unset
    steps = np.hypot(*np.diff(path.poses[:, :2], axis=0).T)
    assert steps.max() <= RES * 1.5


def test_diagonal_length_close_to_euclidean() -> None:
    cm = free_map(100, 100)
    path = planner().create_plan(Pose2D(0.3, 0.3), Pose2D(4.6, 3.1), cm)
    assert path.length() == pytest.approx(math.hypot(4.3, 2.8), rel=0.03)


def test_around_a_wall_through_the_doorway() -> None:
    cm = wall_with_door()
    path = planner().create_plan(Pose2D(0.5, 0.5), Pose2D(4.5, 0.5), cm)
    assert_clear(path.poses[:, :2], cm)
    crossing = path.poses[np.argmin(np.abs(path.poses[:, 0] - 50.5 * RES)), 1]
    assert 40 * RES <= crossing <= 46 * RES
    # start -> door -> goal, no further
    door = np.array([50.5 * RES, 43 * RES])
    assert path.length() < 1.05 * 2 * np.hypot(*(door - (0.5, 0.5)))


@pytest.mark.parametrize("use_astar", [False, True])
def test_long_detour_beyond_the_first_search_bound(use_astar: bool) -> None:
    # the doorway is far off the straight line: the path is ~1.9x it, so the search
    # bound has to grow past its first detour allowance
    cm = wall_with_door((70, 76))
    path = planner(use_astar=use_astar).create_plan(Pose2D(0.5, 0.5), Pose2D(4.5, 0.5), cm)
    assert_clear(path.poses[:, :2], cm)
    crossing = path.poses[np.argmin(np.abs(path.poses[:, 0] - 50.5 * RES)), 1]
    assert 70 * RES <= crossing <= 76 * RES
    door = np.array([50.5 * RES, 73 * RES])
    assert path.length() < 1.05 * 2 * np.hypot(*(door - (0.5, 0.5)))


def test_avoids_inflated_cost_when_there_is_room() -> None:
    cm = free_map(120, 80)
    cm.costs[30:50, 55:65] = 254  # a block in the middle
    cm.costs[:] = inflate(cm.costs, RES, 0.1, 1.5, 3.0)
    start, goal = Pose2D(0.5, 2.0), Pose2D(5.5, 2.0)
    path = planner().create_plan(start, goal, cm)
    assert_clear(path.poses[:, :2], cm)
    # a path hugging the block would cross cells of cost > 200; NavFn keeps off them
    m, _ = cm.world_to_map(path.poses[:, :2])
    assert cm.costs[m[:, 1], m[:, 0]].max() < 200


def test_astar_path_cost_equals_dijkstra(benchmark_costmap: Costmap2D) -> None:
    cm = benchmark_costmap.copy()
    cm.costs[:] = inflate(cm.costs, RES, 0.1, 0.6, 3.0)
    rng = np.random.default_rng(5)
    free = np.argwhere(cm.costs[20:-20, 20:-20] < 100) + 20
    for _ in range(3):
        a, b = free[rng.choice(len(free), 2, replace=False)]
        s = Pose2D(*cm.map_to_world(a[::-1]))
        g = Pose2D(*cm.map_to_world(b[::-1]))
        dij = planner().create_plan(s, g, cm)
        ast = planner(use_astar=True).create_plan(s, g, cm)
        assert path_cost(ast.poses[:, :2], cm) == pytest.approx(
            path_cost(dij.poses[:, :2], cm), rel=0.02
        )


def test_astar_explores_less_than_dijkstra() -> None:
    cm = free_map(200, 200)
    d, a = planner(), planner(use_astar=True)
    d.create_plan(Pose2D(1.0, 5.0), Pose2D(2.0, 5.0), cm)
    a.create_plan(Pose2D(1.0, 5.0), Pose2D(2.0, 5.0), cm)
    assert (a.potential < POT_HIGH).sum() < 0.5 * (d.potential < POT_HIGH).sum()


def test_benchmark_map_realistic_plan(benchmark_costmap: Costmap2D) -> None:
    cm = benchmark_costmap
    free = np.argwhere(cm.costs == 0)
    m0 = free[np.argmin(np.hypot(*(free - (30, 30)).T))]
    m1 = free[np.argmin(np.hypot(*(free - (370, 370)).T))]
    s, g = Pose2D(*cm.map_to_world(m0[::-1])), Pose2D(*cm.map_to_world(m1[::-1]))
    path = planner().create_plan(s, g, cm)
    assert_clear(path.poses[:, :2], cm, max_cost=253)
    assert path.length() >= s.distance_to(g)
    assert path.length() < 1.6 * s.distance_to(g)


def test_error_codes() -> None:
    cm = wall_with_door()
    cm.costs[20, 20] = 254
    p0 = planner(tolerance=0.0)
    cases = [
        (Pose2D(-1.0, 0.5), Pose2D(1.5, 1.5), StartOutsideMapBounds, 203),
        (Pose2D(0.5, 0.5), Pose2D(9.0, 1.0), GoalOutsideMapBounds, 204),
        (Pose2D(20.5 * RES, 20.5 * RES), Pose2D(1.5, 1.5), StartOccupied, 205),
        (Pose2D(0.5, 0.5), Pose2D(20.5 * RES, 20.5 * RES), GoalOccupied, 206),
    ]
    for start, goal, exc, code in cases:
        with pytest.raises(exc) as info:
            p0.create_plan(start, goal, cm)
        assert info.value.error_code == code == ComputePathToPoseError(code)
        assert isinstance(info.value, PlannerException)
    closed = wall_with_door((0, 0))
    with pytest.raises(NoValidPathCouldBeFound) as info:
        p0.create_plan(Pose2D(0.5, 0.5), Pose2D(4.5, 0.5), closed)
    assert info.value.error_code == ComputePathToPoseError.NO_VALID_PATH == 208
    with pytest.raises(PlannerCancelled) as info:
        p0.create_plan(Pose2D(0.5, 0.5), Pose2D(4.5, 0.5), cm, cancel_checker=lambda: True)
    assert info.value.error_code == ComputePathToPoseError.TIMEOUT == 207


def test_tolerance_reaches_closest_point_to_an_unreachable_goal() -> None:
    cm = free_map(100, 60)
    cm.costs[20:40, 60:80] = 254  # the goal sits inside this block
    goal = Pose2D(62.5 * RES, 30.5 * RES, 1.0)
    with pytest.raises(NoValidPathCouldBeFound):
        planner(tolerance=0.05).create_plan(Pose2D(0.5, 1.5), goal, cm)
    path = planner(tolerance=0.3).create_plan(Pose2D(0.5, 1.5), goal, cm)
    end = path.poses[-1]
    assert end[2] == 1.0
    assert goal.x - end[0] == pytest.approx(3 * RES, abs=0.3 * RES)  # just left of the block
    assert end[1] == pytest.approx(goal.y, abs=0.5 * RES)
    assert_clear(path.poses[:, :2], cm)
    # a goal in lethal cost with tolerance > 0 is not GOAL_OCCUPIED (as Nav2)
    assert len(planner(tolerance=0.3).create_plan(Pose2D(0.5, 1.5), goal, cm)) > 0


def test_allow_unknown() -> None:
    cm = free_map(100, 60)
    cm.costs[:, 50] = 255
    start, goal = Pose2D(0.5, 1.5), Pose2D(4.5, 1.5)
    assert planner(allow_unknown=True).create_plan(start, goal, cm).length() == pytest.approx(
        4.0, abs=0.06
    )
    with pytest.raises(NoValidPathCouldBeFound):
        planner(allow_unknown=False, tolerance=0.0).create_plan(start, goal, cm)


def test_final_approach_orientation_and_start_equals_goal() -> None:
    cm = free_map()
    start, goal = Pose2D(0.5, 0.5, 0.3), Pose2D(3.0, 2.0, -2.0)
    path = planner(use_final_approach_orientation=True).create_plan(start, goal, cm)
    d = path.poses[-1, :2] - path.poses[-2, :2]
    assert path.poses[-1, 2] == pytest.approx(math.atan2(d[1], d[0]))
    assert 0.2 < path.poses[-1, 2] < 1.2
    same = Pose2D(0.5, 0.5, 1.0)
    one = planner().create_plan(start, same, cm)
    assert one.poses.tolist() == [[0.5, 0.5, 1.0]]
    one = planner(use_final_approach_orientation=True).create_plan(start, same, cm)
    assert one.poses.tolist() == [[0.5, 0.5, 0.3]]
