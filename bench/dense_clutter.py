"""MPPI in dense clutter: NavigateToPose across seeded cylinder forests with Nav2's defaults.

    python bench/dense_clutter.py [--worlds 10] [--spacing 0.6] [--jitter 0.08]
                                  [--removed 0.3] [--footprint] [--workers 2]

Each world is generated in memory from its seed: a 10 x 10 m walled square, cylinders
of `--radius` (0.075 m) on a jittered lattice of `--spacing` pitch over the middle
8 m, a `--removed` fraction of them taken away at random, none within 0.8 m of the
start (0.6, 5) or the goal (9.4, 5). No gap is left of a width the costmaps may judge
differently (within 0.10 m below to 0.15 m above the inscribed diameter; of such a
pair the later cylinder goes): NavFn on the map's grid would route through a gap the
local costmap, turned and shifted in odom, marks inscribed, and MPPI rightly refuses
it (a costmap question, not the controller's). A forest is kept when a route with
clearance of the inscribed radius plus half that margin joins start and goal;
otherwise the next draw of the same seed is taken. The robot is a 0.42 x 0.33 m
rectangle (diff drive, 0.5 m/s, 1.9 rad/s, a 360-beam lidar).

The mission runs with Nav2's own params/nav2_params.yaml as it is (MPPI with its 8
critics, costmaps with robot_radius 0.22, NavFn, the default recovery tree), ground-
truth localisation (the controller is judged, not AMCL), and a 100 s sim-time limit;
`--footprint` gives both costmaps the rectangle as their `footprint` instead.

Printed per world: the forest's bottleneck (the narrowest gap, between surfaces, on
the widest route from start to goal), success, sim time to the goal, contacts,
recoveries, distance driven over the straight line, and the time spent nearly still
(under 0.05 m/s over 0.5 s: stalls and dithering). Then the totals. A quality bound,
not a timing: target all worlds succeed within the limit with no contact.
"""

from __future__ import annotations

import os

if __name__ == "__main__":  # as a script (tests import it: their environment is theirs)
    for _var in (
        "OMP_NUM_THREADS",
        "OPENBLAS_NUM_THREADS",
        "MKL_NUM_THREADS",
        "NUMEXPR_NUM_THREADS",
    ):
        os.environ[_var] = "1"

import argparse
import math
import tempfile
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import yaml
from scipy import ndimage
from scipy.spatial import cKDTree

REPO = Path(__file__).resolve().parents[1]
NAV2_PARAMS = REPO / "params" / "nav2_params.yaml"
TIME_LIMIT = 100.0
SIZE = 10.0
WALL_THICKNESS = 0.1
START = (0.6, 5.0, 0.0)
GOAL = (9.4, 5.0, 0.0)
#: The forest's extent along x; across, it spans the square.
FOREST_X = (1.0, 9.0)
CLEAR_AROUND_ENDS = 0.8
#: The robot: base_footprint at the centre of a 0.42 m long, 0.33 m wide base.
LENGTH, WIDTH = 0.42, 0.33
#: Nav2's params: robot_radius 0.22 (the inscribed radius of a circular robot).
NAV2_ROBOT_RADIUS = 0.22
#: Nav2's costmaps pad a footprint polygon by footprint_padding (0.01 m by default).
FOOTPRINT_PADDING = 0.01
#: Below this speed (m/s, over STILL_WINDOW s) the robot counts as still.
STILL_SPEED = 0.05
STILL_WINDOW = 0.5
GRID = 0.05
#: A gap is closed below the inscribed diameter less this, open above it plus this (m).
CLOSED_MARGIN = 0.10
OPEN_MARGIN = 0.15


@dataclass(frozen=True)
class Density:
    """How the forest is drawn: lattice pitch, jitter (m, each axis), fraction removed."""

    spacing: float = 0.6
    jitter: float = 0.08
    removed: float = 0.3
    radius: float = 0.075

    def label(self) -> str:
        return (
            f"r {self.radius:g} m on a {self.spacing:g} m lattice, jitter +-{self.jitter:g} m, "
            f"{self.removed:.0%} removed"
        )


def footprint_polygon() -> list[list[float]]:
    hx, hy = LENGTH / 2, WIDTH / 2
    return [[-hx, -hy], [hx, -hy], [hx, hy], [-hx, hy]]


def inscribed_radius(footprint: bool) -> float:
    """The costmap's inscribed radius: what NavFn's route must clear."""
    return min(LENGTH, WIDTH) / 2 + FOOTPRINT_PADDING if footprint else NAV2_ROBOT_RADIUS


def clearance_grid(cylinders: np.ndarray, radius: float) -> tuple[np.ndarray, np.ndarray]:
    """Cell centres (GRID m) inside the walls and their distance to the nearest surface."""
    inner = WALL_THICKNESS / 2
    c = np.arange(inner + GRID / 2, SIZE - inner, GRID)
    gx, gy = np.meshgrid(c, c, indexing="xy")
    cells = np.stack([gx.ravel(), gy.ravel()], axis=1)
    walls = np.minimum.reduce([gx, gy, SIZE - gx, SIZE - gy]) - inner
    if len(cylinders):
        d, _ = cKDTree(cylinders).query(cells)
        walls = np.minimum(walls, d.reshape(gx.shape) - radius)
    return c, walls


def bottleneck(cylinders: np.ndarray, radius: float) -> float:
    """The largest clearance c such that start and goal are joined through cells of
    clearance >= c (the widest route's narrowest half-gap), to GRID / 8."""
    c, clear = clearance_grid(cylinders, radius)
    si = (int(np.argmin(abs(c - START[1]))), int(np.argmin(abs(c - START[0]))))
    gi = (int(np.argmin(abs(c - GOAL[1]))), int(np.argmin(abs(c - GOAL[0]))))
    lo, hi = 0.0, float(min(clear[si], clear[gi]))
    while hi - lo > GRID / 8:
        mid = 0.5 * (lo + hi)
        labels, _ = ndimage.label(clear >= mid)
        if labels[si] != 0 and labels[si] == labels[gi]:
            lo = mid
        else:
            hi = mid
    return lo


def unambiguous(pts: np.ndarray, radius: float, footprint: bool) -> np.ndarray:
    """The cylinders left once no gap (between two cylinders, or a cylinder and a wall)
    is of a width the two costmaps may judge differently: each gap is either closed
    (narrower than the robot's inscribed diameter by CLOSED_MARGIN) or open (wider by
    OPEN_MARGIN). A gap in between is passable in one costmap's cells and not in the
    other's (the local costmap is in odom, shifted and turned off the map's grid), so
    NavFn would route through a gap that MPPI rightly sees as blocked: that is a
    costmap question, not the controller's. Of a pair, the later cylinder goes."""
    lo = 2 * inscribed_radius(footprint) - CLOSED_MARGIN
    hi = 2 * inscribed_radius(footprint) + OPEN_MARGIN
    inner = WALL_THICKNESS / 2
    wall_gap = np.minimum.reduce([pts[:, 0], pts[:, 1], SIZE - pts[:, 0], SIZE - pts[:, 1]])
    wall_gap = wall_gap - inner - radius
    keep = ~((wall_gap > lo) & (wall_gap < hi))
    pairs = cKDTree(pts).query_pairs(2 * radius + hi, output_type="ndarray")
    if len(pairs):
        pairs = pairs[np.lexsort((pairs[:, 1], pairs[:, 0]))]
        gap = np.hypot(*(pts[pairs[:, 0]] - pts[pairs[:, 1]]).T) - 2 * radius
        for i, j in pairs[(gap > lo) & (gap < hi)]:
            if keep[i] and keep[j]:
                keep[j] = False
    return pts[keep]


def forest(seed: int, density: Density, footprint: bool = False) -> tuple[np.ndarray, float, int]:
    """The cylinders' centres (K, 2) of world `seed`, the bottleneck half-gap, and the
    draw it took: the first draw the planner can get through (clearance above the
    inscribed radius plus half the open margin)."""
    need = inscribed_radius(footprint) + OPEN_MARGIN / 2 - 1e-6
    for draw in range(100):
        rng = np.random.default_rng([seed, draw, 0x5EED])
        s = density.spacing
        xs = np.arange(FOREST_X[0], FOREST_X[1] + 1e-9, s)
        ys = np.arange(s / 2, SIZE - s / 2 + 1e-9, s)
        gx, gy = np.meshgrid(xs, ys)
        pts = np.stack([gx.ravel(), gy.ravel()], axis=1)
        pts = pts + rng.uniform(-density.jitter, density.jitter, pts.shape)
        pts = pts[rng.random(len(pts)) >= density.removed]
        ends = np.array([START[:2], GOAL[:2]])
        far = np.min(np.hypot(*(pts[:, None, :] - ends[None]).transpose(2, 0, 1)), axis=1)
        inner = WALL_THICKNESS / 2 + density.radius + 0.02
        inside = np.all((pts > inner) & (pts < SIZE - inner), axis=1)
        pts = unambiguous(pts[(far > CLEAR_AROUND_ENDS) & inside], density.radius, footprint)
        gap = bottleneck(pts, density.radius)
        if gap >= need:
            return pts, gap, draw
    raise RuntimeError(f"world {seed}: no forest of {density.label()} lets the robot through")


def world_doc(seed: int, cylinders: np.ndarray, radius: float) -> dict[str, Any]:
    """The world file's content (see worlds/*.yaml)."""
    s = SIZE
    return {
        "world": f"forest_{seed}",
        "bounds": [[-0.2, -0.2], [s + 0.2, s + 0.2]],
        "walls": [
            {"points": [[0, 0], [s, 0], [s, s], [0, s], [0, 0]], "thickness": WALL_THICKNESS}
        ],
        "obstacles": [
            {"circle": {"center": [round(float(x), 4), round(float(y), 4)], "radius": radius}}
            for x, y in cylinders
        ],
        "robot": {
            "drive": "diff_drive",
            "footprint": {"polygon": footprint_polygon()},
            "pose": list(START),
            "limits": {"v_max": 0.5, "w_max": 1.9, "a_max": 3.0, "alpha_max": 3.5},
            "odometry": {"noise": [0.002, 0.0005, 0.0001, 0.0001], "rate": 50},
            "sensors": [
                {
                    "lidar": {
                        "frame": "laser",
                        "pose": [0.15, 0.0, 0.0],
                        "beams": 360,
                        "range": [0.12, 8.0],
                        "rate": 10,
                        "noise_std": 0.01,
                    }
                }
            ],
        },
    }


@dataclass
class Stillness:
    """A progress hook: time the robot spends nearly still, from ground truth (it only reads)."""

    last_t: float = 0.0
    last_xy: tuple[float, float] | None = None
    still: float = 0.0

    def __call__(self, nav: Any) -> None:
        t = nav.now
        if self.last_xy is None:
            self.last_t, self.last_xy = t, (nav.robot_pose.x, nav.robot_pose.y)
            return
        if t - self.last_t < STILL_WINDOW - 1e-9:
            return
        p = nav.robot_pose
        moved = math.hypot(p.x - self.last_xy[0], p.y - self.last_xy[1])
        if moved < STILL_SPEED * (t - self.last_t):
            self.still += t - self.last_t
        self.last_t, self.last_xy = t, (p.x, p.y)


@dataclass
class WorldResult:
    seed: int
    cylinders: int
    gap: float
    status: str
    sim_time: float
    collisions: int
    recoveries: int
    path_length: float
    still: float

    @property
    def passed(self) -> bool:
        return self.status == "succeeded" and self.collisions == 0 and self.sim_time <= TIME_LIMIT


def run_world(
    seed: int,
    density: Density = Density(),
    footprint: bool = False,
    time_limit: float = TIME_LIMIT,
    overrides: dict[str, Any] | None = None,
) -> WorldResult:
    """Generate world `seed` and run NavigateToPose on it (a fresh process per world is
    safest: the py_trees blackboard is process-wide)."""
    from btnav.maps.map_io import save_map
    from btnav.mission import Mission, run_mission
    from btnav.sim.rasterize import rasterize
    from btnav.sim.world_spec import WorldSpec

    cylinders, gap, _ = forest(seed, density, footprint)
    doc = world_doc(seed, cylinders, density.radius)
    with tempfile.TemporaryDirectory(prefix="btnav_forest_") as tmp:
        folder = Path(tmp)
        text = yaml.safe_dump(doc, sort_keys=False)
        (folder / "world.yaml").write_text(text)
        save_map(rasterize(WorldSpec.from_text(text)), folder / "map.yaml")
        mission = {
            "mission": f"forest_{seed}",
            "world": "world.yaml",
            "params": str(NAV2_PARAMS),
            "map": "map.yaml",
            "localization": "ground_truth",
            "initial_pose": list(START),
            "task": {"navigate_to_pose": list(GOAL)},
            "time_limit": time_limit,
            "seed": seed,
            "outputs": [],
        }
        (folder / "mission.yaml").write_text(yaml.safe_dump(mission, sort_keys=False))
        sets = dict(overrides or {})
        if footprint:
            polygon = str(footprint_polygon())
            sets["local_costmap.local_costmap.footprint"] = polygon
            sets["global_costmap.global_costmap.footprint"] = polygon
        m = Mission.load(folder / "mission.yaml", overrides=sets)
        still = Stillness()
        r = run_mission(m, progress=still)
    return WorldResult(
        seed, len(cylinders), 2 * gap, r.status, r.sim_time, r.collisions, r.recoveries,
        r.path_length, still.still,
    )  # fmt: skip


def _run(args: tuple[int, Density, bool]) -> WorldResult:
    return run_world(*args)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--worlds", type=int, default=10, help="worlds 0..N-1 (default 10)")
    ap.add_argument("--first", type=int, default=0, help="the first world's seed")
    ap.add_argument("--spacing", type=float, default=Density.spacing)
    ap.add_argument("--jitter", type=float, default=Density.jitter)
    ap.add_argument("--removed", type=float, default=Density.removed)
    ap.add_argument("--radius", type=float, default=Density.radius)
    ap.add_argument("--footprint", action="store_true", help="costmaps get the rectangle")
    ap.add_argument("--workers", type=int, default=min(2, os.cpu_count() or 1))
    args = ap.parse_args()
    density = Density(args.spacing, args.jitter, args.removed, args.radius)
    seeds = range(args.first, args.first + args.worlds)
    shape = "the rectangle as footprint" if args.footprint else "robot_radius 0.22"
    print(f"forests: {density.label()}; costmaps: {shape}; limit {TIME_LIMIT:g} s sim")
    with ProcessPoolExecutor(args.workers, max_tasks_per_child=1) as pool:
        results = list(pool.map(_run, [(s, density, args.footprint) for s in seeds]))
    straight = math.dist(START[:2], GOAL[:2])
    print("world  cyl  gap_m  status      time_s  contacts  recov  driven/straight  still_s")
    for r in results:
        print(
            f"{r.seed:5d} {r.cylinders:4d}  {r.gap:5.2f}  {r.status:10s} {r.sim_time:7.1f} "
            f"{r.collisions:9d} {r.recoveries:6d} {r.path_length / straight:16.2f} "
            f"{r.still:8.1f}" + ("" if r.passed else "  FAIL")
        )
    passes = sum(r.passed for r in results)
    done = [r.sim_time for r in results if r.status == "succeeded"]
    print(
        f"passes {passes}/{len(results)} (ratio {passes / len(results):.2f}, target 1.00); "
        f"contacts {sum(r.collisions for r in results)}; "
        f"recoveries {sum(r.recoveries for r in results)}; "
        + (
            f"time to goal median {np.median(done):.1f} s, slowest {max(done):.1f} s"
            if done
            else "no world reached"
        )
    )


if __name__ == "__main__":
    main()
