"""btnav's global planners next to scikit-image's MCP_Geometric and scipy's csgraph.dijkstra.

Part 1, the grid planners on one costmap: a 400 x 400 crop of Nav2's benchmark map
100by100_20 (0.05 m cells) with Nav2-style inflation (inscribed 0.1 m, radius 0.55 m,
scaling 3.0). Start/goal pairs follow Nav2's planner benchmark: seed 33, cells of cost
below 210, a border (here 20 cells, for the smaller map), more than 3 m apart. MCP and
the scipy 8-connected graph search NavFn's mapped costs (obstacles impassable) and give
the 8-connected optimum every path length is divided by. Rows: NavFn timed cold (the
costmap's graph built inside the timing, as MCP builds its own), warm (graph reused:
the costmap did not change since the last plan) and with A*; SmacPlanner2D, Theta* and
SmacPlannerHybrid with Nav2's defaults (Hybrid starts and ends at yaw 0, so its length
is a car's, not a point's). Targets: NavFn <= 2x MCP, Smac 2D <= 2x NavFn (both cold).

Part 2, Hybrid-A* on btnav's small office map: first with Nav2's defaults (DUBIN and
REEDS_SHEPP, 0.4 m radius, a radius footprint on Nav2's default inflation) from the
office's corner into the next room (short) and into the far room (long); then for the
racecar: its planner section and global costmap (footprint polygon, inflation) from
params/racecar_nav2_params.yaml, its footprint checked at every pose, on requests that
turn round, back up or cross doorways. Target: each racecar plan under 100 ms.

Single-threaded; times are this process's CPU time (other load on a shared machine does
not inflate them). About 20 s of CPU with the default 20 pairs. Part 1 needs
scikit-image (the bench extra); `--part 2` runs without it.

    python bench/planner.py [n_pairs] [--turning-radius R] [--part {1,2}]
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import gc  # noqa: E402
import math  # noqa: E402
import time  # noqa: E402
from collections.abc import Callable  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
from scipy.ndimage import distance_transform_edt  # noqa: E402
from scipy.sparse import csr_matrix  # noqa: E402
from scipy.sparse.csgraph import dijkstra  # noqa: E402

from btnav.core.geometry import Pose2D  # noqa: E402
from btnav.costmap.costmap_2d import Costmap2D  # noqa: E402
from btnav.costmap.costmap_ros import CostmapROS  # noqa: E402
from btnav.maps import load_map  # noqa: E402
from btnav.params import load_params  # noqa: E402
from btnav.planning.exceptions import PlannerException  # noqa: E402
from btnav.planning.global_planner import GlobalPlanner  # noqa: E402
from btnav.planning.navfn import navfn_costs  # noqa: E402
from btnav.planning.navfn_planner import NavfnPlanner  # noqa: E402
from btnav.planning.smac_common import HeuristicCache  # noqa: E402
from btnav.planning.smac_planner_2d import SmacPlanner2D  # noqa: E402
from btnav.planning.smac_planner_hybrid import SmacPlannerHybrid  # noqa: E402
from btnav.planning.smac_planner_lattice import SmacPlannerLattice  # noqa: E402
from btnav.planning.theta_star_planner import ThetaStarPlanner  # noqa: E402

REPO = Path(__file__).resolve().parents[1]
MAP = REPO.parent / "shared" / "nav2" / "benchmark_maps" / "100by100_20.yaml"
OFFICE_MAP = REPO / "maps" / "small_office.yaml"
RACECAR_PARAMS = REPO / "params" / "racecar_nav2_params.yaml"
SIZE, BORDER, MIN_DIST, MAX_COST, SEED = 400, 20, 3.0, 210, 33
#: Racecar requests on the office map: (start, goal) as (x, y, yaw).
OFFICE_REQUESTS = (
    ((1.0, 1.0, 0.0), (6.0, 3.0, math.pi)),  # through a doorway, facing back
    ((1.0, 1.0, 0.0), (10.0, 6.0, math.pi / 2)),  # two doorways into the far room
    ((2.5, 1.0, 0.0), (1.0, 1.5, 0.0)),  # a goal behind: back up
    ((5.5, 2.5, 0.0), (9.5, 1.2, math.pi)),  # across a room, turning round
    ((6.0, 2.0, 0.0), (6.0, 2.0, math.pi)),  # turn round on the spot: a three-point turn
)
#: Nav2's defaults on the office: (name, start, goal).
OFFICE_DEFAULT_REQUESTS = (
    ("short", (1.0, 1.0, 0.0), (6.0, 3.0, 3.14)),  # into the next room, facing back
    ("long", (1.0, 1.0, 0.0), (10.0, 6.0, 1.57)),  # two doorways into the far room
)


def inflate(lethal: np.ndarray, resolution: float, inscribed: float) -> np.ndarray:
    """Nav2-style inflation (radius 0.55 m, scaling 3.0) of a lethal mask."""
    d = distance_transform_edt(~lethal) * resolution
    radius, scale = 0.55, 3.0
    costs = np.where(d <= inscribed, 253, np.floor(252 * np.exp(-scale * (d - inscribed))))
    costs[d > radius] = 0
    costs[lethal] = 254
    return costs


def costmap() -> Costmap2D:
    grid = load_map(MAP)
    crop = grid.data[800 : 800 + SIZE, 800 : 800 + SIZE]
    costs = inflate(crop >= 65, grid.resolution, 0.1)
    return Costmap2D(costs.astype(np.uint8), grid.resolution)


def office_costmap() -> Costmap2D:
    """The small office with Nav2's default inflation (inscribed radius 0.22 m), unknown
    cells kept unknown."""
    grid = load_map(OFFICE_MAP)
    costs = inflate(grid.data >= 65, grid.resolution, 0.22)
    costs[(grid.data < 0) & (costs < 253)] = 255
    return Costmap2D(costs.astype(np.uint8), grid.resolution, grid.origin.x, grid.origin.y)


def pairs(cm: Costmap2D, n: int) -> list[tuple[np.ndarray, np.ndarray]]:
    rng = np.random.default_rng(SEED)
    out: list[tuple[np.ndarray, np.ndarray]] = []
    lo, hi = BORDER, SIZE - BORDER
    while len(out) < n:
        a, b = rng.integers(lo, hi, size=(2, 2))  # (mx, my)
        if cm.costs[a[1], a[0]] >= MAX_COST or cm.costs[b[1], b[0]] >= MAX_COST:
            continue
        if np.hypot(*(a - b)) * cm.resolution <= MIN_DIST:
            continue
        out.append((a, b))
    return out


def length(xy: np.ndarray) -> float:
    return float(np.hypot(*np.diff(xy, axis=0).T).sum())


def scipy_optimum(cost: np.ndarray, a: np.ndarray, b: np.ndarray) -> tuple[float, np.ndarray]:
    """8-connected shortest path with MCP_Geometric's edge weights (mean cost x length)."""
    ny, nx = cost.shape
    idx = np.arange(ny * nx).reshape(ny, nx)
    rows, cols, w = [], [], []
    for dy, dx in ((0, 1), (1, 0), (1, 1), (1, -1)):
        ys = slice(max(0, -dy), ny - max(0, dy))
        xs = slice(max(0, -dx), nx - max(0, dx))
        yd = slice(max(0, dy), ny + min(0, dy) or None)
        xd = slice(max(0, dx), nx + min(0, dx) or None)
        wt = (cost[ys, xs] + cost[yd, xd]) / 2 * math.hypot(dx, dy)
        ok = np.isfinite(wt)
        for s, t in ((idx[ys, xs][ok], idx[yd, xd][ok]), (idx[yd, xd][ok], idx[ys, xs][ok])):
            rows.append(s)
            cols.append(t)
            w.append(wt[ok])
    g = csr_matrix(
        (np.concatenate(w), (np.concatenate(rows), np.concatenate(cols))), (ny * nx,) * 2
    )
    src, dst = a[1] * nx + a[0], b[1] * nx + b[0]
    dist, pred = dijkstra(g, indices=src, return_predecessors=True)
    node, cells = dst, []
    while node >= 0:
        cells.append((node % nx, node // nx))
        node = pred[node]
    return float(dist[dst]), np.array(cells[::-1], dtype=float)


def mapped_costs(cm: Costmap2D) -> np.ndarray:
    """NavFn's mapped costs with obstacles impassable: the graph MCP and scipy search."""
    cost = navfn_costs(cm.costs, allow_unknown=True).astype(float)
    cost[cost >= 254] = np.inf
    return cost


class Row:
    """One planner's timings and path lengths over the requests."""

    def __init__(self, name: str, run: Callable[[Pose2D, Pose2D], np.ndarray]) -> None:
        self.name, self.run = name, run
        self.ms: list[float] = []
        self.ratio: list[float] = []
        self.failures = 0

    def plan(self, start: Pose2D, goal: Pose2D, optimum: float) -> None:
        t0 = time.process_time()
        try:
            xy = self.run(start, goal)
        except PlannerException:
            self.ms.append((time.process_time() - t0) * 1e3)
            self.failures += 1
            return
        self.ms.append((time.process_time() - t0) * 1e3)
        self.ratio.append(length(xy) / optimum)


def planner_row(name: str, planner: GlobalPlanner, cm: Costmap2D, cold: bool = False) -> Row:
    def run(start: Pose2D, goal: Pose2D) -> np.ndarray:
        if cold:
            planner._graph = None  # type: ignore[attr-defined]  # NavFn: rebuild its graph
        return planner.create_plan(start, goal, cm).poses[:, :2] / cm.resolution

    return Row(name, run)


def grid_planners(n: int) -> dict[str, float]:
    """Part 1; returns the mean ms per plan of each row."""
    from skimage.graph import MCP_Geometric

    cm = costmap()
    cost = mapped_costs(cm)

    def mcp(start: Pose2D, goal: Pose2D) -> np.ndarray:
        (a, b), _ = cm.world_to_map([[start.x, start.y], [goal.x, goal.y]])
        m = MCP_Geometric(cost, fully_connected=True)
        m.find_costs([(a[1], a[0])], [(b[1], b[0])])
        return np.array(m.traceback((b[1], b[0])), dtype=float)[:, ::-1]

    def scipy(start: Pose2D, goal: Pose2D) -> np.ndarray:
        (a, b), _ = cm.world_to_map([[start.x, start.y], [goal.x, goal.y]])
        return scipy_optimum(cost, a, b)[1]

    navfn = NavfnPlanner("navfn")
    rows = [
        planner_row("navfn", navfn, cm, cold=True),
        planner_row("navfn_warm", navfn, cm),
        planner_row("navfn_astar", NavfnPlanner("a", NavfnPlanner.Params(use_astar=True)), cm),
        Row("mcp", mcp),
        Row("scipy", scipy),
        planner_row("smac_2d", SmacPlanner2D("smac_2d"), cm),
        planner_row("theta_star", ThetaStarPlanner("theta_star"), cm),
        planner_row("smac_hybrid", SmacPlannerHybrid("smac_hybrid"), cm),
        planner_row("smac_lattice", SmacPlannerLattice("smac_lattice"), cm),
    ]
    requests = [(Pose2D(*cm.map_to_world(a)), Pose2D(*cm.map_to_world(b))) for a, b in pairs(cm, n)]
    warm = pairs(cm, 1)[0]
    for row in rows:  # one untimed plan each: imports, tables, the first allocations
        row.run(Pose2D(*cm.map_to_world(warm[0])), Pose2D(*cm.map_to_world(warm[1])))
    for start, goal in requests:
        (a, b), _ = cm.world_to_map([[start.x, start.y], [goal.x, goal.y]])
        opt = length(scipy_optimum(cost, a, b)[1])
        for row in rows:
            row.plan(start, goal, opt)
    mean = {row.name: float(np.mean(row.ms)) for row in rows}
    print(f"{n} start/goal pairs on a {SIZE}x{SIZE} crop of 100by100_20 (seed {SEED})")
    print(f"{'planner':<13}{'ms/plan':>9}{'max ms':>8}{'x MCP':>7}{'x NavFn':>8}{'len/opt8':>10}"
          f"{'min':>7}{'max':>7}{'fails':>6}")  # fmt: skip
    for row in rows:
        r = row.ratio or [math.nan]
        print(
            f"{row.name:<13}{mean[row.name]:>9.1f}{max(row.ms):>8.1f}"
            f"{mean[row.name] / mean['mcp']:>7.2f}{mean[row.name] / mean['navfn']:>8.2f}"
            f"{np.mean(r):>10.3f}{np.min(r):>7.3f}{np.max(r):>7.3f}{row.failures:>6}"
        )
    for what, value, bound in (
        ("NavFn <= 2x MCP", mean["navfn"] / mean["mcp"], 2.0),
        ("Smac 2D <= 2x NavFn", mean["smac_2d"] / mean["navfn"], 2.0),
    ):
        print(f"target {what}: {value:.2f}x -> {'PASS' if value <= bound else 'FAIL'} (cold)")
    print("navfn_warm: same costmap as the last plan, its graph reused (a replanning server)")
    print("smac_hybrid: Nav2's defaults (DUBIN, 0.4 m radius), yaw 0 at both ends")
    print("smac_lattice: Nav2's default lattice (Ackermann 0.5 m, 16 headings), yaw 0 at both ends")
    return mean


def pose_text(pose: tuple[float, float, float]) -> str:
    return f"({pose[0]:.1f}, {pose[1]:.1f}, {pose[2]:.2f})"


def defaults_in_the_office() -> None:
    """Part 2, first half: Hybrid-A* with Nav2's defaults on the office."""
    cm = office_costmap()
    cost = mapped_costs(cm)
    print(
        f"\nHybrid-A* with Nav2's defaults on small_office ({cm.size_x}x{cm.size_y}, "
        f"{cm.resolution} m): minimum_turning_radius 0.4 m, a radius footprint"
    )
    print(f"{'model':<12}{'request':<8}{'ms':>8}{'expanded':>10}{'length':>8}{'opt8':>7}")
    for model in ("DUBIN", "REEDS_SHEPP"):
        hybrid = SmacPlannerHybrid(
            "GridBased", SmacPlannerHybrid.Params(motion_model_for_search=model)
        )
        name, s, g = OFFICE_DEFAULT_REQUESTS[0]
        hybrid.create_plan(Pose2D(*s), Pose2D(*g), cm)  # untimed: the first allocations
        for name, s, g in OFFICE_DEFAULT_REQUESTS:
            ms, got = timed_plan(hybrid, Pose2D(*s), Pose2D(*g), cm)
            print(
                f"{model:<12}{name:<8}{ms:>8.1f}{hybrid.expansions:>10}{got}"
                f"{optimum_m(cost, cm, s, g):>7.2f}"
            )


def timed_plan(
    planner: SmacPlannerHybrid, start: Pose2D, goal: Pose2D, cm: Costmap2D
) -> tuple[float, str]:
    """One plan's CPU ms, its obstacle heuristic computed inside, and its length."""
    planner._heuristic = HeuristicCache()  # a new goal's heuristic is part of its plan
    gc.collect()  # the garbage earlier rows left is not this plan's to collect
    t0 = time.process_time()
    try:
        got = f"{planner.create_plan(start, goal, cm).length():>8.2f}"
    except PlannerException as exc:
        got = f"  {type(exc).__name__}"
    return (time.process_time() - t0) * 1e3, got


def optimum_m(cost: np.ndarray, cm: Costmap2D, s: tuple, g: tuple) -> float:
    """The 8-connected optimum between two poses' cells, in metres."""
    (a, b), _ = cm.world_to_map([[s[0], s[1]], [g[0], g[1]]])
    return length(scipy_optimum(cost, a, b)[1]) * cm.resolution


def racecar_in_the_office(turning_radius: float | None) -> None:
    """Part 2: Hybrid-A* with the racecar's planner and global costmap."""
    params = load_params(RACECAR_PARAMS)
    ros = CostmapROS.from_params(params, "global_costmap", map=load_map(OFFICE_MAP))
    ros.refresh()
    cm = ros.costmap
    section = params.server("planner_server").plugins["GridBased"]
    hybrid_params = section.params
    if turning_radius is not None:
        hybrid_params = hybrid_params.model_copy(update={"minimum_turning_radius": turning_radius})
    hybrid = SmacPlannerHybrid("GridBased", hybrid_params)
    hybrid.configure(ros)
    cost = mapped_costs(cm)
    hybrid.create_plan(Pose2D(*OFFICE_REQUESTS[2][0]), Pose2D(*OFFICE_REQUESTS[2][1]), cm)
    p = hybrid.params
    print(
        f"\nHybrid-A* for the racecar on small_office ({cm.size_x}x{cm.size_y}, "
        f"{cm.resolution} m): {p.motion_model_for_search}, minimum_turning_radius "
        f"{p.minimum_turning_radius} m, its footprint polygon checked"
    )
    print(f"{'start':>17} -> {'goal':<17}{'ms':>8}{'expanded':>10}{'length':>8}{'opt8':>7}")
    ms = []
    for s, g in OFFICE_REQUESTS:
        took, got = timed_plan(hybrid, Pose2D(*s), Pose2D(*g), cm)
        ms.append(took)
        print(
            f"{pose_text(s):>17} -> {pose_text(g):<17}"
            f"{took:>8.1f}{hybrid.expansions:>10}{got}{optimum_m(cost, cm, s, g):>7.2f}"
        )
    verdict = "PASS" if max(ms) < 100.0 else "FAIL"
    print(
        f"target Hybrid-A* < 100 ms per plan: mean {np.mean(ms):.0f} ms, "
        f"max {max(ms):.0f} ms -> {verdict}"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("n_pairs", nargs="?", type=int, default=20)
    parser.add_argument(
        "--turning-radius", type=float, help="override the racecar's minimum_turning_radius (m)"
    )
    parser.add_argument("--part", type=int, choices=(1, 2), help="run only this part")
    args = parser.parse_args()
    if args.part in (None, 1):
        grid_planners(args.n_pairs)
    if args.part in (None, 2):
        defaults_in_the_office()
        racecar_in_the_office(args.turning_radius)


if __name__ == "__main__":
    main()
