"""Draw a world: walls, obstacles (moving ones with their routes), the robot and a scan.

`btnav world show WORLD.yaml -o world.png` saves `world_figure`. Drawing uses a
bare matplotlib `Figure` on the Agg canvas, never pyplot, so it works headless and
does not change the backend of a user's own session.
"""

from __future__ import annotations

import math
from os import PathLike
from typing import TYPE_CHECKING, Any

import numpy as np

from ..core.errors import BtnavError
from ..core.geometry import Pose2D
from ..core.messages import LaserScan
from .legend import legend_entries

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..sim.world import World

#: Colours: solids dark, moving ones orange, the robot blue, the scan red.
STATIC_COLOR = "#4a4a4a"
MOVING_COLOR = "#e07b00"
ROBOT_COLOR = "#1f5fbf"
SCAN_COLOR = "#d62728"


def _matplotlib() -> Any:
    """Import matplotlib only when drawing; without it, tell the user how to get it."""
    try:
        import matplotlib
        from matplotlib.backends.backend_agg import FigureCanvasAgg  # noqa: F401
    except ImportError:
        raise BtnavError(
            "drawing needs matplotlib, which comes with the viz extra: pip install 'btnav[viz]'"
        ) from None
    return matplotlib


def _sensor_mount(world: World, frame_id: str) -> Pose2D:
    """The mounting pose of the sensor publishing in `frame_id`, from the world file."""
    for _name, params, _line in world.sensor_specs():
        if isinstance(params, dict) and params.get("frame") == frame_id:
            pose = params.get("pose")
            if pose is not None:
                return Pose2D(*pose)
    return Pose2D()


def _routes(world: World) -> list[tuple[np.ndarray, bool]]:
    """Each moving obstacle's route (its start, then its path) and whether it loops."""
    out = []
    for solid in world.solids:
        if solid.moves is not None:
            pts = np.vstack(
                [np.asarray(solid.origin, float)[None, :], np.asarray(solid.moves.path, float)]
            )
            out.append((pts, bool(solid.moves.loop)))
    return out


def draw_world(
    world: World,
    scan: LaserScan | None = None,
    ax: Axes | None = None,
    *,
    sensor_pose: Pose2D | None = None,
) -> Axes:
    """Draw `world` as it is now onto `ax` (a new Agg figure's axes if None) and return `ax`.

    Solids come from `world.geometry()`, the very outlines the lidar sees. Moving
    obstacles are drawn where they are now, in orange, with their route dashed. The
    robot is its footprint with a heading line. `scan` (a `LaserScan`) is drawn from
    `sensor_pose`, by default the robot's pose composed with the mount the world file
    gives the scan's frame: beams to each return, and the returns as dots.
    """
    _matplotlib()
    from matplotlib.collections import LineCollection, PatchCollection
    from matplotlib.patches import Circle, Polygon, Rectangle

    if ax is None:
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure

        fig = Figure(figsize=_figsize(world))
        FigureCanvasAgg(fig)
        ax = fig.add_subplot(1, 1, 1)

    (x0, y0), (x1, y1) = world.bounds
    ax.add_patch(
        Rectangle(
            (x0, y0),
            x1 - x0,
            y1 - y0,
            facecolor="#f7f7f2",
            edgecolor="#bbbbbb",
            linewidth=0.8,
            zorder=0,
        )
    )

    from ..sim.scene import solids_geometry

    moving = [s for s in world.solids if s.moves is not None]
    moving_ids = {id(s) for s in moving}
    static = solids_geometry([s for s in world.solids if id(s) not in moving_ids])
    here = world.geometry()
    # world.geometry() holds the static solids first, then the moving ones where they are.
    n_poly, n_circ = len(static.polygons), len(static.circles)
    for polys, circles, color, label in (
        (here.polygons[:n_poly], here.circles[:n_circ], STATIC_COLOR, "walls and obstacles"),
        (here.polygons[n_poly:], here.circles[n_circ:], MOVING_COLOR, "moving obstacle"),
    ):
        patches = [Polygon(p, closed=True) for p in polys]
        patches += [Circle((cx, cy), r) for cx, cy, r in circles]
        if patches:
            ax.add_collection(
                PatchCollection(
                    patches, facecolor=color, edgecolor=color, linewidth=0.5, zorder=2, label=label
                )
            )

    for pts, loop in _routes(world):
        ax.plot(
            pts[:, 0],
            pts[:, 1],
            linestyle="--",
            color=MOVING_COLOR,
            linewidth=1.0,
            zorder=1,
            label="route (back and forth)" if loop else "route",
        )
        # Where the route ends: a dot when the obstacle turns back, a cross where it stops.
        ax.plot(
            pts[-1, 0],
            pts[-1, 1],
            marker="o" if loop else "x",
            color=MOVING_COLOR,
            markersize=4,
            zorder=1,
        )

    pose = world.robot_pose
    if scan is not None:
        sp = sensor_pose if sensor_pose is not None else pose @ _sensor_mount(world, scan.frame_id)
        pts = sp.transform_points(scan.points())
        if len(pts):
            origin = np.broadcast_to([sp.x, sp.y], pts.shape)
            beams = np.stack([origin, pts], axis=1)
            ax.add_collection(
                LineCollection(beams, colors=SCAN_COLOR, linewidths=0.25, alpha=0.15, zorder=3)
            )
            ax.scatter(
                pts[:, 0],
                pts[:, 1],
                s=3,
                color=SCAN_COLOR,
                zorder=4,
                label=f"scan ({len(pts)} returns)",
            )

    fp = world.spec.robot.footprint
    if fp.radius is not None:
        body = Circle((pose.x, pose.y), fp.radius)
        size = fp.radius
    else:
        outline = pose.transform_points(np.asarray(fp.polygon, float))
        body = Polygon(outline, closed=True)
        size = float(np.hypot(*np.asarray(fp.polygon, float).T).max())
    body.set(
        facecolor=ROBOT_COLOR,
        edgecolor="#0b2f6b",
        alpha=0.55,
        linewidth=1.0,
        zorder=5,
        label="robot",
    )
    ax.add_patch(body)
    ax.plot(
        [pose.x, pose.x + 1.3 * size * math.cos(pose.yaw)],
        [pose.y, pose.y + 1.3 * size * math.sin(pose.yaw)],
        color="#0b2f6b",
        linewidth=1.5,
        zorder=6,
    )

    margin = 0.03 * max(x1 - x0, y1 - y0)
    ax.set_xlim(x0 - margin, x1 + margin)
    ax.set_ylim(y0 - margin, y1 + margin)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title(f"{world.spec.world}: robot at ({pose.x:.2f}, {pose.y:.2f}, {pose.yaw:.2f})")
    ax.grid(True, linewidth=0.3, alpha=0.5)
    unique = legend_entries(ax)
    if unique:
        ax.legend(unique.values(), unique.keys(), loc="upper right", fontsize=7, framealpha=0.85)
    return ax


def _figsize(world: World) -> tuple[float, float]:
    (x0, y0), (x1, y1) = world.bounds
    w, h = x1 - x0, y1 - y0
    scale = 9.0 / max(w, h)
    return (max(4.0, w * scale + 1.2), max(3.0, h * scale + 0.8))


def world_figure(world_path: str | PathLike[str]) -> Figure:
    """The world as `btnav world show` draws it: the robot at its start and one scan.

    The scan is the first lidar's first reading (seed 0), so the picture shows what the
    robot sees before it moves. The figure is a bare Agg `Figure`, ready to save.
    """
    _matplotlib()
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    from ..sim import lidar as _lidar  # noqa: F401  (registers the lidar plugin)
    from ..sim.sensor import Sensor
    from ..sim.world import World
    from ..sim.world_sensors import make_sensors

    world = World.from_file(world_path, seed=0)
    scan = None
    for sensor in make_sensors(world, seed=0):
        if isinstance(sensor, Sensor):
            msg = sensor.measure(world.time)
            if isinstance(msg, LaserScan):
                scan = msg
                break
    fig = Figure(figsize=_figsize(world))
    FigureCanvasAgg(fig)
    ax = fig.add_subplot(1, 1, 1)
    draw_world(world, scan, ax)
    fig.tight_layout()
    return fig
