"""`run.png`, the `png` output of a run: the world as the run left it, and where the robot went.

Registered as the `png` output plugin (the `viz` entry point), so a mission asks for it
with `outputs: [report, png]`. Under the world lies the inflated global costmap (what
the planner saw); over it the last global plan, the ground-truth path (solid), the
localiser's estimate (dashed, another colour), the task's poses numbered, the shapes
plugins draw of themselves (`core.drawing`, as the run left them) and every
contact as a red X naming what was hit. With a particle-filter localiser (AMCL) the
particle cloud at the end is drawn too (a dot and a short heading tick each), with
the final estimate and ground-truth poses as arrows, and the title adds the
localisation error over the run, so a glance says whether localisation held. The
title is the run's result.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from ..costmap.cost_values import FREE_SPACE, NO_INFORMATION
from ..mission.outputs import RunOutput
from ..plugins import register
from .legend import legend_entries
from .plugin_drawings import plot_drawables
from .run_recorder import drawing_plugins, plugin_drawables
from .world_plot import _figsize, _matplotlib, draw_world

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

PATH_COLOR = "#1f5fbf"
ESTIMATE_COLOR = "#17becf"
PLAN_COLOR = "#2ca02c"
GOAL_COLOR = "#2ca02c"
CONTACT_COLOR = "#d62728"
COSTMAP_CMAP = "Purples"
COSTMAP_ALPHA = 0.45
#: Inches added on the right for the legend, so it covers nothing.
LEGEND_WIDTH = 2.0
#: Contacts beyond this many get their X but no text, so the picture stays readable.
MAX_CONTACT_LABELS = 12

LEGEND_PATH = "path (ground truth)"
LEGEND_ESTIMATE = "estimate (localisation)"
LEGEND_PLAN = "global plan (last)"
LEGEND_COSTMAP = "global costmap (inflated)"
LEGEND_CONTACT = "contact"
LEGEND_PARTICLES = "particles (end)"
PARTICLE_COLOR = "#ff7f0e"
#: Particles drawn at most (evenly thinned beyond), so a picture stays light.
MAX_PARTICLES_DRAWN = 2000


@register("output", "png")
class RunPicture:
    """Draws `run.png`; needs matplotlib (the viz extra), checked before the run starts."""

    files = ("run.png",)

    def __init__(self) -> None:
        _matplotlib()

    def write(self, run: RunOutput) -> None:
        fig = draw_run(run)
        fig.savefig(run.out_dir / self.files[0], dpi=120)


def draw_run(run: RunOutput) -> Figure:
    """The picture of a run, as an Agg `Figure` (what `run.png` saves; tests read its artists)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    world = run.navigator.world
    width, height = _figsize(world)
    fig = Figure(figsize=(width + LEGEND_WIDTH, height))
    FigureCanvasAgg(fig)
    ax = fig.add_subplot(1, 1, 1)
    draw_world(world, ax=ax)
    _draw_costmap(ax, run.navigator.stack.global_costmap.costmap)
    plan = run.plan
    if len(plan):
        ax.plot(
            plan[:, 0],
            plan[:, 1],
            color=PLAN_COLOR,
            linewidth=1.2,
            linestyle="-.",
            alpha=0.9,
            zorder=3,
            label=LEGEND_PLAN,
        )
    track = run.track
    if len(track):
        ax.plot(
            track[:, 1],
            track[:, 2],
            color=PATH_COLOR,
            linewidth=2.2,
            zorder=4,
            label=LEGEND_PATH,
        )
        ax.plot(
            track[:, 4],
            track[:, 5],
            color=ESTIMATE_COLOR,
            linewidth=1.0,
            linestyle=(0, (4, 2)),
            zorder=4.5,
            label=LEGEND_ESTIMATE,
        )
        ax.plot(
            track[0, 1],
            track[0, 2],
            marker="s",
            color=PATH_COLOR,
            markersize=6,
            zorder=6,
            label="start",
        )
    for i, (x, y, _yaw) in enumerate(run.mission.spec.task.poses, start=1):
        ax.plot(
            x,
            y,
            marker="*",
            color=GOAL_COLOR,
            markersize=11,
            zorder=7,
            label="goal" if i == 1 else None,
        )
        ax.annotate(
            str(i),
            (x, y),
            xytext=(5, 5),
            textcoords="offset points",
            fontsize=8,
            color=GOAL_COLOR,
            zorder=7,
        )
    _draw_particles(ax, run.navigator.runtime.localizer, track)
    nav = run.navigator
    frame = nav.bt_navigator.params.global_frame
    plot_drawables(ax, plugin_drawables(nav, drawing_plugins(nav), frame))
    _draw_contacts(ax, world.contacts)
    ax.set_title(_title(run.report, _has_particles(run.navigator.runtime.localizer)), fontsize=9)
    from matplotlib.patches import Patch

    unique = legend_entries(ax)
    unique.setdefault(LEGEND_COSTMAP, Patch(facecolor="#6a51a3", alpha=COSTMAP_ALPHA))
    ax.legend(
        unique.values(),
        unique.keys(),
        loc="upper left",
        bbox_to_anchor=(1.01, 1.0),
        fontsize=7,
        framealpha=0.85,
    )
    fig.tight_layout()
    return fig


def _draw_costmap(ax: Axes, costmap: Any) -> None:
    """The costmap under the world's solids, free and unknown cells left clear."""
    costs = np.asarray(costmap.costs)
    shown = np.ma.masked_where((costs == FREE_SPACE) | (costs == NO_INFORMATION), costs)
    x0, y0 = costmap.origin_x, costmap.origin_y
    x1 = x0 + costs.shape[1] * costmap.resolution
    y1 = y0 + costs.shape[0] * costmap.resolution
    xlim, ylim = ax.get_xlim(), ax.get_ylim()
    ax.imshow(
        shown,
        origin="lower",
        extent=(x0, x1, y0, y1),
        cmap=COSTMAP_CMAP,
        vmin=0,
        vmax=NO_INFORMATION - 1,
        alpha=COSTMAP_ALPHA,
        interpolation="nearest",
        zorder=0.5,  # over the floor, under routes (1) and solids (2)
    )
    ax.set_xlim(xlim)
    ax.set_ylim(ylim)


def _draw_contacts(ax: Axes, contacts: list[Any]) -> None:
    """A red X where the robot was when each contact began, named by what it hit."""
    for n, c in enumerate(contacts):
        ax.plot(
            c.pose.x,
            c.pose.y,
            marker="x",
            markersize=12,
            markeredgewidth=2.5,
            color=CONTACT_COLOR,
            linestyle="none",
            zorder=8,
            label=f"{LEGEND_CONTACT} ({len(contacts)})" if n == 0 else None,
        )
        if n < MAX_CONTACT_LABELS:
            line = f", line {c.line}" if c.line else ""
            ax.annotate(
                f"{c.label}{line}\n{c.time:.1f} s",
                (c.pose.x, c.pose.y),
                xytext=(7, -14),
                textcoords="offset points",
                fontsize=7,
                color=CONTACT_COLOR,
                fontweight="bold",
                zorder=8,
                bbox={"boxstyle": "round,pad=0.2", "fc": "white", "ec": "none", "alpha": 0.75},
            )


def _has_particles(localizer: Any) -> bool:
    return getattr(localizer, "particles", None) is not None


def _draw_particles(ax: Axes, localizer: Any, track: np.ndarray) -> None:
    """The localiser's particle cloud at the end, and the last estimate against the truth."""
    if not _has_particles(localizer):
        return
    poses, _weights = localizer.particles
    if len(poses) > MAX_PARTICLES_DRAWN:
        poses = poses[:: -(-len(poses) // MAX_PARTICLES_DRAWN)]
    tick = 0.12  # m: a heading tick, long enough to read the cloud's spread in yaw
    ax.quiver(
        poses[:, 0],
        poses[:, 1],
        np.cos(poses[:, 2]) * tick,
        np.sin(poses[:, 2]) * tick,
        angles="xy",
        scale_units="xy",
        scale=1.0,
        width=0.0015,
        color=PARTICLE_COLOR,
        alpha=0.5,
        zorder=5,
    )
    ax.plot(
        poses[:, 0],
        poses[:, 1],
        linestyle="none",
        marker=".",
        markersize=1.5,
        color=PARTICLE_COLOR,
        zorder=5,
        label=LEGEND_PARTICLES,
    )
    if len(track):
        for (x, y, yaw), color, label in (
            (track[-1, 1:4], PATH_COLOR, "pose at the end (ground truth)"),
            (track[-1, 4:7], ESTIMATE_COLOR, "pose at the end (estimate)"),
        ):
            ax.annotate(
                "",
                xy=(x + 0.35 * np.cos(yaw), y + 0.35 * np.sin(yaw)),
                xytext=(x, y),
                arrowprops={"arrowstyle": "-|>", "color": color, "lw": 1.6},
                zorder=6.5,
            )
            ax.plot(x, y, marker="o", markersize=4, color=color, zorder=6.5, label=label)


def _title(report: Any, localised: bool = False) -> str:
    code = f", error {report.error_code}" if report.error_code is not None else ""
    n, r = report.collisions, report.recoveries
    title = (
        f"{report.mission}: {report.status}{code}, {report.sim_time:.1f} s, "
        f"{report.path_length:.1f} m, {n} collision{'s' if n != 1 else ''}, "
        f"{r} recover{'ies' if r != 1 else 'y'}"
    )
    err = getattr(report, "localization_error", None)
    if localised and err:
        title += (
            f"\nlocalisation error: rms {err['rms_xy'] * 100:.1f} cm (max "
            f"{err['max_xy'] * 100:.1f} cm), rms yaw {np.degrees(err['rms_yaw']):.1f} deg"
        )
    return title
