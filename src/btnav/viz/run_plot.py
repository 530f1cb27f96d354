"""`run.png`, the `png` output of a run: the world as the run left it, and where the robot went.

Registered as the `png` output plugin (the `viz` entry point), so a mission asks for it
with `outputs: [report, png]`. The ground-truth path is solid, the localiser's estimate
dashed, the task's poses numbered; the title is the run's result.
"""

from __future__ import annotations

from typing import Any

from ..mission.outputs import RunOutput
from ..plugins import register
from .world_plot import _figsize, _matplotlib, draw_world

PATH_COLOR = "#1f5fbf"
ESTIMATE_COLOR = "#555555"
GOAL_COLOR = "#2ca02c"


@register("output", "png")
class RunPicture:
    """Draws `run.png`; needs matplotlib (the viz extra), checked before the run starts."""

    files = ("run.png",)

    def __init__(self) -> None:
        _matplotlib()

    def write(self, run: RunOutput) -> None:
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure

        world = run.navigator.world
        fig = Figure(figsize=_figsize(world))
        FigureCanvasAgg(fig)
        ax = fig.add_subplot(1, 1, 1)
        draw_world(world, ax=ax)
        track = run.track
        if len(track):
            ax.plot(
                track[:, 1],
                track[:, 2],
                color=PATH_COLOR,
                linewidth=1.4,
                zorder=4,
                label="path (ground truth)",
            )
            ax.plot(
                track[:, 4],
                track[:, 5],
                color=ESTIMATE_COLOR,
                linewidth=0.8,
                linestyle="--",
                zorder=4,
                label="estimate",
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
        ax.set_title(_title(run.report), fontsize=9)
        handles, labels = ax.get_legend_handles_labels()
        unique = dict(zip(labels, handles, strict=True))
        ax.legend(unique.values(), unique.keys(), loc="upper right", fontsize=7, framealpha=0.85)
        fig.tight_layout()
        fig.savefig(run.out_dir / self.files[0], dpi=120)


def _title(report: Any) -> str:
    code = f", error {report.error_code}" if report.error_code is not None else ""
    return (
        f"{report.mission}: {report.status}{code}, {report.sim_time:.1f} s, "
        f"{report.path_length:.1f} m, {report.collisions} collisions, "
        f"{report.recoveries} recoveries"
    )
