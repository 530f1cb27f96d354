"""NavFn's compiled search and descent give the reference's plans, float for float.

The reference (`method="numpy"`, BTNAV_NAVFN=numpy) is scipy's Dijkstra and navfn.py's
Python descent; the kernels are navfn_kernel's.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from btnav.core.geometry import Pose2D
from btnav.costmap.cost_values import NO_INFORMATION
from btnav.costmap.costmap_2d import Costmap2D
from btnav.costmap.static_layer import interpret_values
from btnav.maps import load_map
from btnav.planning.exceptions import PlannerException
from btnav.planning.navfn import (
    _OUT_OF_RANGE,
    POT_HIGH,
    GridGraph,
    _descend_compiled,
    _search,
    compute_potential,
    extract_path,
    navfn_costs,
)
from btnav.planning.navfn_planner import NavfnPlanner

from .conftest import inflate
from .test_navfn_unknown import DATA, corridor

REPO = Path(__file__).resolve().parents[2]
RES = 0.05


def rooms(seed: int, ny: int = 90, nx: int = 130) -> Costmap2D:
    """Walls with doors, pillars, a few unknown patches and scattered unknown cells."""
    rng = np.random.default_rng(seed)
    c = np.zeros((ny, nx), np.uint8)
    for x in rng.integers(10, nx - 10, 3):
        c[:, x] = 254
        door = rng.integers(5, ny - 15)
        c[door : door + 10, x] = 0
    for _ in range(6):
        y, x = rng.integers(0, ny - 5), rng.integers(0, nx - 5)
        c[y : y + 4, x : x + 4] = 254
    c = inflate(c, RES, 0.15, 0.5, 3.0)
    y, x = rng.integers(0, ny - 20), rng.integers(0, nx - 20)
    c[y : y + 12, x : x + 18] = NO_INFORMATION
    c[(rng.random(c.shape) < 0.03) & (c == 0)] = NO_INFORMATION
    return Costmap2D(c, RES)


def free_cells(cm: Costmap2D, rng: np.random.Generator, n: int) -> list[tuple[int, int]]:
    ys, xs = np.nonzero(cm.costs < 253)
    pick = rng.integers(len(xs), size=n)
    return [(int(xs[i]), int(ys[i])) for i in pick]


@pytest.mark.parametrize("seed", range(6))
def test_the_compiled_search_gives_scipys_distances(seed: int) -> None:
    cm = rooms(seed)
    rng = np.random.default_rng(seed)
    for allow_unknown in (True, False):
        costarr = navfn_costs(cm.costs, allow_unknown)
        graph = GridGraph(*costarr.shape)
        csr = graph.cached_graph(costarr)
        for sx, sy in free_cells(cm, rng, 4):
            source = sy * cm.size_x + sx
            for limit in (0.0, 49.0, 700.0, 3000.0, 1e5):
                ref = _search(csr, source, limit, "numpy")
                got = _search(csr, source, limit, "kernel", float(costarr.min()), graph.shifts)
                assert np.array_equal(ref, got)
                assert np.isfinite(got).any() and (got[np.isfinite(got)] <= limit).all()


@pytest.mark.parametrize("use_astar", [False, True])
@pytest.mark.parametrize("seed", range(4))
def test_potentials_and_paths_are_the_references(seed: int, use_astar: bool) -> None:
    cm = rooms(10 + seed)
    rng = np.random.default_rng(seed)
    costarr = navfn_costs(cm.costs, True)
    graph = GridGraph(*costarr.shape)
    for start, goal in zip(free_cells(cm, rng, 5), free_cells(cm, rng, 5), strict=True):
        pots = [
            compute_potential(graph, costarr, start, goal, use_astar, None, method)
            for method in ("numpy", "kernel")
        ]
        assert np.array_equal(pots[0], pots[1])
        for from_xy in (goal, (goal[0] + 0.3, goal[1] - 0.45)):
            for max_cycles in (3, 40, 4 * 130):
                ref = extract_path(pots[0], from_xy, start, max_cycles, None, "numpy")
                got = extract_path(pots[0], from_xy, start, max_cycles, None, "kernel")
                assert (ref is None) == (got is None)
                if ref is not None:
                    assert np.array_equal(ref, got)


def test_descents_that_lose_their_way_fall_back_alike() -> None:
    """The SLAM corridor's scattered unknown cells: calcPath's descent circles and the
    path follows the grid; both methods do so at the same step."""
    d = np.load(DATA / "navfn_slam_unknown.npz")
    cms = [Costmap2D(d["costs"], float(d["resolution"]), *map(float, d["origin"]))]
    cms += [corridor(seed) for seed in (0, 1, 2)]
    for cm in cms:
        costarr = navfn_costs(cm.costs, True)
        graph = GridGraph(*costarr.shape)
        start = (3, cm.size_y // 2)
        goal = (cm.size_x - 4, cm.size_y // 2)
        pot = compute_potential(graph, costarr, start, goal, False, None, "kernel")
        on_grid = extract_path(pot, goal, start, 2000, None, "numpy")
        assert on_grid is not None
        assert np.array_equal(on_grid, extract_path(pot, goal, start, 2000, None, "kernel"))


def test_the_cancel_checker_is_polled_at_the_same_steps() -> None:
    """Every 1000 steps of a long descent; cancelling there raises in both."""
    cm = Costmap2D(np.zeros((8, 1500), np.uint8), RES)
    costarr = navfn_costs(cm.costs, True)
    start, goal = (2, 4), (1496, 4)
    pot = compute_potential(GridGraph(*costarr.shape), costarr, start, goal)
    polls = {}
    for method in ("numpy", "kernel"):
        calls: list[int] = []
        path = extract_path(pot, goal, start, 6000, lambda c=calls: c.append(1) or False, method)
        polls[method] = (len(calls), path)
        with pytest.raises(PlannerException):
            extract_path(pot, goal, start, 6000, lambda: True, method)
    assert polls["numpy"][0] == polls["kernel"][0] >= 2
    assert np.array_equal(polls["numpy"][1], polls["kernel"][1])


def test_descents_near_the_grids_edges_are_the_references() -> None:
    """Random potentials on small grids, every cell reached: descents that end at the
    edge rows, where navfn.py reads past the potential's ends (wrapping round to the
    last cell, or raising IndexError). The kernel hands those to navfn.py (and says so:
    `_OUT_OF_RANGE`), so both answer alike."""
    rng = np.random.default_rng(11)
    handed_over = 0
    for _ in range(300):
        ny, nx = int(rng.integers(3, 7)), int(rng.integers(3, 7))
        pot = rng.uniform(50.0, 2000.0, (ny, nx))
        pot[rng.random((ny, nx)) < 0.1] = POT_HIGH
        to_cell = (int(rng.integers(0, nx)), int(rng.integers(0, ny)))
        pot[to_cell[1], to_cell[0]] = 0.0
        from_xy = (float(rng.uniform(0, nx - 1)), float(rng.uniform(0, ny - 1)))
        outcomes = []
        for method in ("numpy", "kernel"):
            try:
                outcomes.append(extract_path(pot, from_xy, to_cell, 30, None, method))
            except IndexError as exc:
                outcomes.append(type(exc))
        if isinstance(outcomes[0], np.ndarray):
            assert np.array_equal(outcomes[0], outcomes[1])
        else:
            assert outcomes[0] == outcomes[1]
        for on_grid in (False, True):
            flat = pot.reshape(-1)
            got = _descend_compiled(flat, nx, from_xy, to_cell, 30, on_grid, None)
            handed_over += got is _OUT_OF_RANGE
    assert handed_over > 10


def _numpy_and_kernel_planners() -> list[NavfnPlanner]:
    planners = []
    for method in ("numpy", "kernel"):
        planner = NavfnPlanner("GridBased", NavfnPlanner.Params())
        planner.method = method
        planners.append(planner)
    return planners


def _same_plan(
    planners: list[NavfnPlanner], start: Pose2D, goal: Pose2D, cm: Costmap2D
) -> np.ndarray | None:
    """Both paths plan `start` -> `goal` on `cm`: the same poses and potential, or the same
    failure (then None)."""
    outs = []
    for p in planners:
        try:
            outs.append((p.create_plan(start, goal, cm).poses, p.potential))
        except PlannerException as exc:
            outs.append((type(exc), None))
    (a, pa), (b, pb) = outs
    if not isinstance(a, np.ndarray):
        assert a == b
        return None
    assert np.array_equal(a, b) and np.array_equal(pa, pb)
    return a


def test_planner_plans_are_the_same_on_nav2s_benchmark_map(benchmark_costmap) -> None:
    """NavfnPlanner as the planner server runs it: a goal every few metres, some in
    walls (tolerance), the graph reused between plans on a changing costmap."""
    rng = np.random.default_rng(3)
    costs = inflate(benchmark_costmap.costs, RES, 0.22, 0.55, 3.0)
    cm = Costmap2D(costs, RES, benchmark_costmap.origin_x, benchmark_costmap.origin_y)
    planners = _numpy_and_kernel_planners()
    for _ in range(8):
        start = Pose2D(*(cm.map_to_world(free_cells(cm, rng, 1)[0])), 0.0)
        goal = Pose2D(*(cm.map_to_world(free_cells(cm, rng, 1)[0]) + rng.normal(0, 0.3, 2)), 1.0)
        cm.costs[rng.integers(0, 400, 30), rng.integers(0, 400, 30)] = 254  # new obstacles
        _same_plan(planners, start, goal, cm)


@pytest.mark.parametrize("name", ["tb3_sandbox", "depot"])
def test_planner_plans_are_the_same_on_nav2s_maps(nav2_dir: Path, name: str) -> None:
    """Nav2's own maps (unknown space kept: tb3_sandbox's outside) with Nav2's default
    inflation, replanned as the planner server does: start and goal move, the graph is
    reused, a few cells change between plans."""
    grid = load_map(nav2_dir / "maps" / f"{name}.yaml")
    costs = inflate(interpret_values(grid.data), grid.resolution, 0.22, 0.55, 3.0)
    cm = Costmap2D(costs, grid.resolution, grid.origin.x, grid.origin.y)
    rng = np.random.default_rng(len(name))
    planners = _numpy_and_kernel_planners()
    start = Pose2D(*cm.map_to_world(free_cells(cm, rng, 1)[0]), 0.0)
    planned = 0
    for _ in range(5):
        goal = Pose2D(*cm.map_to_world(free_cells(cm, rng, 1)[0]), 0.0)
        ys, xs = rng.integers(0, cm.size_y, 40), rng.integers(0, cm.size_x, 40)
        cm.costs[ys, xs] = 254
        poses = _same_plan(planners, start, goal, cm)
        if poses is not None:
            planned += 1
            start = Pose2D(*poses[len(poses) // 3, :2], 0.0)  # part of the way there
    assert planned >= 3


_COMPILE = """
import numpy as np
from btnav.costmap.costmap_2d import Costmap2D
from btnav.costmap.obstacle_layer import free_along
from btnav.costmap import inflation_kernel, raytrace_kernel
from btnav.planning import navfn_kernel
from btnav.planning.navfn import GridGraph, compute_potential, extract_path, navfn_costs
cm = Costmap2D(np.zeros((20, 20), np.uint8), 0.05)
c = navfn_costs(cm.costs, True)
pot = compute_potential(GridGraph(20, 20), c, (2, 2), (15, 12))
extract_path(pot, (15, 12), (2, 2), 80)
free_along(cm, np.array([0.3, 0.3]), np.array([[0.3, 0.3]]), np.array([[0.9, 0.7]]))
inflation_kernel.inflate_window(cm.costs, 0, 0, 20, 20, 3, np.zeros(11, np.uint8), False, False)
"""


def test_no_fused_multiply_add_in_the_kernels(fused_multiply_adds) -> None:
    """LLVM contracted no a * b + c (the descent's and the raytrace's bits depend on it)."""
    kernels = "navfn_kernel.dijkstra, navfn_kernel.descend, raytrace_kernel.clear_rays"
    n_chars, n_fused = fused_multiply_adds(_COMPILE, kernels)
    assert n_chars > 10_000 and n_fused == 0
