"""NavFn through unknown space (`allow_unknown: true`), as on the growing map of SLAM.

A SLAM map is mostly unknown ahead of the robot, and its frontier is ragged: single
unknown cells (COST_OBS - 1 for NavFn) scattered through free space. Nav2's NavFn plans
through them; these tests hold btnav's to the same.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from btnav.core.geometry import Pose2D
from btnav.costmap.cost_values import INSCRIBED_INFLATED_OBSTACLE, NO_INFORMATION
from btnav.costmap.costmap_2d import Costmap2D
from btnav.planning.exceptions import NoValidPathCouldBeFound
from btnav.planning.navfn_planner import NavfnPlanner
from btnav.plugins import lookup

from .conftest import inflate

RES = 0.05
DATA = Path(__file__).parent / "data"


def planner(**params: object) -> NavfnPlanner:
    # nav2_params.yaml's GridBased section: tolerance 0.5, use_astar false, allow_unknown true
    params = {"tolerance": 0.5, **params}
    return NavfnPlanner("GridBased", NavfnPlanner.Params(**params))


def cells_of(path_xy: np.ndarray, cm: Costmap2D) -> np.ndarray:
    m, inside = cm.world_to_map(path_xy)
    assert inside.all()
    return m


def assert_no_jumps(path_xy: np.ndarray) -> None:
    """Gradient steps are half a cell; where NavFn follows the grid it goes from its
    position (within a cell of its cell) to a neighbour's centre: under 2 sqrt(2) cells."""
    assert np.all(np.hypot(*np.diff(path_xy, axis=0).T) < 2 * np.sqrt(2) * RES)


def corridor(fringe_seed: int | None) -> Costmap2D:
    """A 12 m corridor (walls at y 0.5 m and 2.35 m) whose far half SLAM has not seen.

    With a seed, the frontier is ragged as a scan's fringe is: from x = 4.5 m to 6.5 m
    ever more cells are unknown; without, everything past x = 6 m is unknown."""
    ny, nx = 60, 240
    c = np.zeros((ny, nx), dtype=np.uint8)
    c[10:13] = 254
    c[47:50] = 254
    c = inflate(c, RES, 0.22, 0.55, 3.0)
    c[:10] = c[50:] = NO_INFORMATION  # behind the walls
    if fringe_seed is None:
        c[:, 120:] = NO_INFORMATION
    else:
        rng = np.random.default_rng(fringe_seed)
        unknown_share = np.clip((np.arange(nx) - 90) / 40.0, 0.0, 1.0)
        c[rng.random((ny, nx)) < unknown_share] = NO_INFORMATION
    return Costmap2D(c, RES)


@pytest.mark.parametrize("fringe_seed", [None, 0, 1, 2, 3])
@pytest.mark.parametrize("goal_row", [20, 30, 40])
def test_corridor_whose_far_half_is_unknown(fringe_seed: int | None, goal_row: int) -> None:
    cm = corridor(fringe_seed)
    start, goal = Pose2D(0.5, 1.5, 0.0), Pose2D(11.3, (goal_row + 0.5) * RES, 0.3)
    path = planner().create_plan(start, goal, cm)
    xy = path.poses[:, :2]
    assert xy[0] == pytest.approx([0.525, 1.525])  # the robot's cell centre
    assert xy[-1] == pytest.approx([goal.x, goal.y]) and path.poses[-1, 2] == 0.3
    assert_no_jumps(xy)
    m = cells_of(xy, cm)
    costs = cm.costs[m[:, 1], m[:, 0]]
    known = costs != NO_INFORMATION
    # where the corridor is known, the path keeps to its free cells, between the walls
    assert costs[known].max() < INSCRIBED_INFLATED_OBSTACLE
    assert np.all((m[:, 1] > 12) & (m[:, 1] < 47))
    # no way round: NavFn's gradient wanders among scattered unknown cells (Nav2's path
    # is up to a third longer than the straight line on these), but it keeps going
    assert path.length() < 1.7 * np.hypot(goal.x - start.x, goal.y - start.y)


def test_unknown_is_an_obstacle_without_allow_unknown() -> None:
    cm = corridor(None)
    with pytest.raises(NoValidPathCouldBeFound):
        planner(allow_unknown=False).create_plan(Pose2D(0.5, 1.5), Pose2D(11.3, 1.5), cm)


def test_slam_map_of_corridor_loop_mission() -> None:
    """The global costmap of missions/corridor_loop_slam.yaml when NavFn failed the goal
    (16.0, 1.2): the goal lies in unknown space past a ragged frontier.

    The fixture is a 6 m x 2.4 m crop of that costmap (costs in Nav2's values, row 0 at
    `origin`); `nav2_path` is the path, in cells, that Nav2's navfn.cpp (setCostmap,
    calcNavFnDijkstra, calcPath; compiled on its own) finds on these costs."""
    d = np.load(DATA / "navfn_slam_unknown.npz")
    cm = Costmap2D(d["costs"], float(d["resolution"]), *map(float, d["origin"]))
    start, goal = Pose2D(*d["start"]), Pose2D(*d["goal"])
    navfn = lookup("planner", "nav2_navfn_planner/NavfnPlanner")
    plan = navfn("GridBased", navfn.Params(tolerance=0.5)).create_plan(start, goal, cm)
    xy = plan.poses[:, :2]
    assert xy[-1] == pytest.approx([goal.x, goal.y])
    assert np.hypot(*(xy[0] - [start.x, start.y])) < RES
    m = cells_of(xy, cm)
    assert cm.costs[m[:, 1], m[:, 0]].max() == NO_INFORMATION  # it did go through unknown
    known = cm.costs[m[:, 1], m[:, 0]] != NO_INFORMATION
    assert cm.costs[m[:, 1], m[:, 0]][known].max() < INSCRIBED_INFLATED_OBSTACLE
    # the path Nav2 finds, within four cells (btnav's potential is not NavFn's planar wave,
    # and where NavFn's gradient descent loses its way btnav's path follows the grid)
    cells = (xy - [cm.origin_x, cm.origin_y]) / cm.resolution - 0.5  # centres at integers
    nav2 = d["nav2_path"].astype(np.float64)
    gap = np.hypot(*(cells[:, None, :] - nav2[None, :, :]).transpose(2, 0, 1))
    assert gap.min(axis=1).max() < 4.0 and gap.min(axis=0).max() < 4.0
    assert plan.length() < 1.05 * np.hypot(*np.diff(nav2, axis=0).T).sum() * RES


@pytest.mark.parametrize("use_astar", [False, True])
def test_scattered_unknown_cells_do_not_fail_the_plan(use_astar: bool) -> None:
    """A room with one cell in twelve unknown: every goal the potential reaches gets a path
    down to the robot, clear of lethal and inscribed cells."""
    rng = np.random.default_rng(5)
    c = np.zeros((80, 80), dtype=np.uint8)
    c[30:50, 38:42] = 254  # a pillar
    c = inflate(c, RES, 0.1, 0.3, 3.0)
    c[(rng.random(c.shape) < 1 / 12) & (c < INSCRIBED_INFLATED_OBSTACLE)] = NO_INFORMATION
    cm = Costmap2D(c, RES)
    nav = planner(use_astar=use_astar)
    free = np.argwhere(c == 0)
    for a, b in free[rng.integers(len(free), size=(12, 2))]:
        start = Pose2D((a[1] + 0.5) * RES, (a[0] + 0.5) * RES)
        goal = Pose2D((b[1] + 0.5) * RES, (b[0] + 0.5) * RES)
        path = nav.create_plan(start, goal, cm)
        xy = path.poses[:, :2]
        assert xy[0] == pytest.approx([start.x, start.y])
        assert xy[-1] == pytest.approx([goal.x, goal.y])
        m = cells_of(xy, cm)
        assert cm.costs[m[:, 1], m[:, 0]].max() != INSCRIBED_INFLATED_OBSTACLE
        assert not (cm.costs[m[:, 1], m[:, 0]] == 254).any()
        assert_no_jumps(xy)
