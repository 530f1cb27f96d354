"""Change the global costmap's inflation radius mid-run and see what it does to the path.

    python examples/dynamic_inflation.py [--radius 0.3] [--at 3.0] [--goal X Y YAW]
                                         [--out out/examples/dynamic_inflation]

The seeds' `dynamic_inflation.py` does, while Nav2 drives,

    ros2 param set /global_costmap/global_costmap inflation_layer.inflation_radius 0.3

btnav's spelling is `nav.set_parameters("global_costmap", {...})`: the new value is
validated like the params file (a misspelt key or a negative radius raises and changes
nothing), and the running costmap is re-inflated at once. This script drives towards a
goal with Nav2's 0.7 m radius, changes it after `--at` sim seconds and prints, for the
plan NavFn makes from that same spot, its length and how close it passes to an
obstacle, before and after; then the plan the controller follows once the tree has
replanned (Nav2's default tree replans at 1 Hz), and the result. With matplotlib (the
`viz` extra) it also saves `before_after.png` in `--out`: the two costmaps and plans.
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy import ndimage

from btnav import Navigator
from btnav.core.geometry import Pose2D
from btnav.costmap.cost_values import LETHAL_OBSTACLE
from btnav.costmap.costmap_2d import Costmap2D
from btnav.maps import OCCUPIED, OccupancyGrid

REPO = Path(__file__).resolve().parents[1]
MISSION = REPO / "missions" / "office_tour.yaml"


@dataclass
class PlanView:
    """What a user compares: the costmap and the plan NavFn makes on it."""

    radius: float
    costmap: Costmap2D
    plan: np.ndarray  # (N, 3) x, y, yaw

    @property
    def length(self) -> float:
        steps = np.diff(self.plan[:, :2], axis=0)
        return float(np.hypot(steps[:, 0], steps[:, 1]).sum())

    @property
    def inflated_cells(self) -> int:
        return int(np.count_nonzero(self.costmap.costs > 0))


def clearance(grid: OccupancyGrid, poses: np.ndarray) -> float:
    """A plan's closest approach to a wall of the map (an occupied cell), in metres.

    Measured on map_server's map rather than the live costmap, whose obstacle layer comes
    and goes with each scan, so plans made at different times compare fairly.
    """
    distance = ndimage.distance_transform_edt(grid.data != OCCUPIED) * grid.resolution
    cells = grid.world_to_cell(poses[:, :2])
    inside = grid.in_bounds(cells)
    if not inside.any():
        return float("nan")
    return float(distance[cells[inside, 0], cells[inside, 1]].min())


def view(nav: Navigator, start: Pose2D, goal: tuple[float, float, float]) -> PlanView:
    """The global costmap as it is now, and NavFn's plan from `start` on it.

    `planner_server.create_plan` plans at once, without sending an action, so both plans
    come from the same spot and no sim time passes between them.
    """
    costmap_ros = nav.stack.global_costmap.costmap_ros
    radius = costmap_ros.layer("inflation_layer").params.inflation_radius  # `ros2 param get`
    path = nav.stack.planner_server.create_plan(goal, "", start)
    return PlanView(radius, costmap_ros.costmap.copy(), np.asarray(path.poses, dtype=float))


def followed_plan(nav: Navigator) -> np.ndarray:
    """The global plan the controller is following now (controller_server's FollowPath goal)."""
    handle = nav.stack.controller_server.action.current
    if handle is None or handle.goal.path is None:
        return np.zeros((0, 3))
    return np.asarray(handle.goal.path.poses, dtype=float)


def save_picture(nav: Navigator, views: list[PlanView], file: Path) -> bool:
    """Two panels, before and after: the world with the robot where it is now, the inflated
    costmap and the plan. Drawing only reads the run's state; it changes nothing."""
    try:
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure

        from btnav.viz.world_plot import draw_world
    except ImportError:  # the viz extra is not installed
        return False
    fig = Figure(figsize=(12, 5))
    FigureCanvasAgg(fig)
    for i, v in enumerate(views):
        ax = fig.add_subplot(1, len(views), i + 1)
        draw_world(nav.world, ax=ax)
        c = v.costmap
        shown = np.ma.masked_where((c.costs == 0) | (c.costs > LETHAL_OBSTACLE), c.costs)
        h, w = c.costs.shape
        extent = (
            c.origin_x,
            c.origin_x + w * c.resolution,
            c.origin_y,
            c.origin_y + h * c.resolution,
        )
        ax.imshow(shown, origin="lower", extent=extent, cmap="Purples", alpha=0.5, zorder=0.5)
        ax.plot(v.plan[:, 0], v.plan[:, 1], color="#2ca02c", linewidth=2)
        ax.set_title(f"inflation_radius {v.radius:.2f} m: plan {v.length:.2f} m")
    file.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(file, dpi=80, bbox_inches="tight")
    return True


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--radius", type=float, default=0.3, help="the new inflation_radius")
    parser.add_argument("--at", type=float, default=3.0, help="sim seconds before the change")
    parser.add_argument("--goal", nargs=3, type=float, default=[9.0, 1.5, 0.0], metavar="V")
    parser.add_argument("--out", default="out/examples/dynamic_inflation", help="picture folder")
    args = parser.parse_args()
    goal = (args.goal[0], args.goal[1], args.goal[2])

    nav = Navigator.from_mission(MISSION)
    print(
        f"brought up {nav.mission.name}; driving to ({goal[0]:.2f}, {goal[1]:.2f}, {goal[2]:.2f})"
    )
    nav.go_to_pose(goal)
    nav.wait_until_done(timeout=args.at)  # drive for `--at` sim seconds
    start = nav.stack.global_costmap.costmap_ros.get_robot_pose(nav.runtime.frames)
    followed_before = followed_plan(nav)
    t_change = nav.now

    before = view(nav, start, goal)
    # `ros2 param set /global_costmap/global_costmap inflation_layer.inflation_radius 0.3`
    nav.set_parameters("global_costmap", {"inflation_layer.inflation_radius": args.radius})
    after = view(nav, start, goal)

    walls = nav.stack.map_server.map
    print(f"t={t_change:.1f} s, robot at ({start.x:.2f}, {start.y:.2f}): the plan from here")
    print(f"  {'':34}{'before':>10}{'after':>10}")
    rows = [
        ("inflation_radius (m)", before.radius, after.radius, ".2f"),
        ("plan length (m)", before.length, after.length, ".2f"),
        (
            "closest approach to a wall (m)",
            clearance(walls, before.plan),
            clearance(walls, after.plan),
            ".2f",
        ),
        ("inflated cells (cost > 0)", before.inflated_cells, after.inflated_cells, "d"),
    ]
    for name, b, a, fmt in rows:
        print(f"  {name:34}{b:>10{fmt}}{a:>10{fmt}}")

    picture = Path(args.out) / "before_after.png"
    if save_picture(nav, [before, after], picture):
        print(f"picture: {picture}")

    # The tree replans on its own (RateController, 1 Hz): wait for it, then look again.
    nav.wait_until_done(timeout=2.0)
    print(
        "the plan the controller follows: closest approach to a wall "
        f"{clearance(walls, followed_before):.2f} m at t={t_change:.1f} s, "
        f"{clearance(walls, followed_plan(nav)):.2f} m at t={nav.now:.1f} s"
    )

    result = nav.wait_until_done(timeout=120.0)
    print(f"result: {result if result is not None else 'still running'} at t={nav.now:.1f} s")
    return 0 if result is not None and result.succeeded else 1


if __name__ == "__main__":
    sys.exit(main())
