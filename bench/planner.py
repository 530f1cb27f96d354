"""NavFn next to scikit-image's MCP_Geometric and scipy's csgraph.dijkstra on one costmap.

The costmap is a 400 x 400 crop of Nav2's benchmark map 100by100_20 (0.05 m cells),
with Nav2-style inflation (inscribed 0.1 m, radius 0.55 m, scaling 3.0). Start/goal
pairs follow Nav2's planner benchmark: seed 33, cells of cost below 210, a border
(here 20 cells, for the smaller map), more than 3 m apart. All three search the same
grid with NavFn's mapped costs (obstacles impassable): MCP_Geometric and the scipy
8-connected graph give the 8-connected optimum; NavFn gives its own potential and
gradient-descent path. Printed: time ratios (target NavFn <= 2x MCP) and path-length
ratios to the 8-connected optimum. NavFn is timed cold (the costmap's graph built
inside the timing, as MCP builds its own) and warm (graph reused: the costmap did
not change since the last plan). Single-threaded.

    python bench/planner.py [n_pairs]
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"

import math  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
from scipy.ndimage import distance_transform_edt  # noqa: E402
from scipy.sparse import csr_matrix  # noqa: E402
from scipy.sparse.csgraph import dijkstra  # noqa: E402
from skimage.graph import MCP_Geometric  # noqa: E402

from btnav.core.geometry import Pose2D  # noqa: E402
from btnav.costmap.costmap_2d import Costmap2D  # noqa: E402
from btnav.maps import load_map  # noqa: E402
from btnav.planning.navfn import navfn_costs  # noqa: E402
from btnav.planning.navfn_planner import NavfnPlanner  # noqa: E402

MAP = (
    Path(__file__).resolve().parents[2] / "shared" / "nav2" / "benchmark_maps" / "100by100_20.yaml"
)
SIZE, BORDER, MIN_DIST, MAX_COST, SEED = 400, 20, 3.0, 210, 33


def costmap() -> Costmap2D:
    grid = load_map(MAP)
    crop = grid.data[800 : 800 + SIZE, 800 : 800 + SIZE]
    lethal = crop >= 65
    d = distance_transform_edt(~lethal) * grid.resolution
    inscribed, radius, scale = 0.1, 0.55, 3.0
    costs = np.where(d <= inscribed, 253, np.floor(252 * np.exp(-scale * (d - inscribed))))
    costs[d > radius] = 0
    costs[lethal] = 254
    return Costmap2D(costs.astype(np.uint8), grid.resolution)


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


def main() -> None:
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 20
    cm = costmap()
    cost = navfn_costs(cm.costs, allow_unknown=True).astype(float)
    cost[cost >= 254] = np.inf
    dij, ast = NavfnPlanner("d"), NavfnPlanner("a", NavfnPlanner.Params(use_astar=True))
    warm = pairs(cm, 1)[0]
    dij.create_plan(Pose2D(*cm.map_to_world(warm[0])), Pose2D(*cm.map_to_world(warm[1])), cm)
    t: dict[str, list[float]] = {
        "navfn": [],
        "navfn_warm": [],
        "navfn_astar": [],
        "mcp": [],
        "scipy": [],
    }
    ratio: dict[str, list[float]] = {"navfn": [], "navfn_warm": [], "navfn_astar": [], "mcp": []}
    for a, b in pairs(cm, n):
        s, g = Pose2D(*cm.map_to_world(a)), Pose2D(*cm.map_to_world(b))
        t0 = time.perf_counter()
        _, opt_cells = scipy_optimum(cost, a, b)
        t["scipy"].append(time.perf_counter() - t0)
        opt = length(opt_cells) * cm.resolution
        for key, pl in (("navfn", dij), ("navfn_warm", dij), ("navfn_astar", ast)):
            if key == "navfn":
                pl._graph = None  # cold: the costmap's graph is built inside the timing
            t0 = time.perf_counter()
            path = pl.create_plan(s, g, cm)
            t[key].append(time.perf_counter() - t0)
            ratio[key].append(path.length() / opt)
        t0 = time.perf_counter()
        mcp = MCP_Geometric(cost, fully_connected=True)
        mcp.find_costs([(a[1], a[0])], [(b[1], b[0])])
        tb = np.array(mcp.traceback((b[1], b[0])), dtype=float)
        t["mcp"].append(time.perf_counter() - t0)
        ratio["mcp"].append(length(tb) * cm.resolution / opt)
    mean = {k: float(np.mean(v)) * 1e3 for k, v in t.items()}
    print(f"{n} start/goal pairs on a {SIZE}x{SIZE} crop of 100by100_20 (seed {SEED})")
    print(f"{'planner':<14}{'ms/plan':>9}{'x MCP':>8}{'len/opt8':>10}{'max':>7}")
    for k in ("navfn", "navfn_warm", "navfn_astar", "mcp", "scipy"):
        r = ratio.get(k, [1.0])
        print(
            f"{k:<14}{mean[k]:>9.1f}{mean[k] / mean['mcp']:>8.2f}"
            f"{np.mean(r):>10.3f}{np.max(r):>7.3f}"
        )
    verdict = "PASS" if mean["navfn"] <= 2 * mean["mcp"] else "FAIL"
    print(f"target NavFn <= 2x MCP: {mean['navfn'] / mean['mcp']:.2f}x -> {verdict} (cold)")
    print("navfn_warm: same costmap as the last plan, its graph reused (a replanning server)")


if __name__ == "__main__":
    main()
