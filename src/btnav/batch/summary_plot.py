"""`summary.png`: each metric against the swept value, one line per mission.

Drawn only when matplotlib (the `viz` extra) is installed. With one numeric sweep
key the x axis is its value; otherwise each set of swept values is a category.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from .summary import GroupSummary

PANELS = (
    ("success_rate", "success rate (95% CI)"),
    ("sim_time_median", "sim time, median (s)"),
    ("path_length_median", "path length, median (m)"),
    ("collisions_mean", "collisions, mean"),
    ("recoveries_mean", "recoveries, mean"),
)


def _number(text: str) -> float | None:
    try:
        return float(text)
    except ValueError:
        return None


def plot_summary(summaries: Sequence[GroupSummary], path: Path) -> bool:
    """Write the figure; False (and nothing written) without matplotlib."""
    try:
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure
    except ImportError:
        return False
    keys = list(summaries[0].sweep)
    numeric = len(keys) == 1 and all(_number(s.sweep[keys[0]]) is not None for s in summaries)
    labels = list(dict.fromkeys(",".join(s.sweep.values()) or "default" for s in summaries))

    def x_of(s: GroupSummary) -> float:
        if numeric:
            return float(s.sweep[keys[0]])
        return float(labels.index(",".join(s.sweep.values()) or "default"))

    fig = Figure(figsize=(4.0 * len(PANELS), 3.6))
    FigureCanvasAgg(fig)
    axes = fig.subplots(1, len(PANELS))
    missions = list(dict.fromkeys(s.mission for s in summaries))
    for ax, (field, title) in zip(axes, PANELS, strict=True):
        for mission in missions:
            group = sorted((s for s in summaries if s.mission == mission), key=x_of)
            xs = [x_of(s) for s in group]
            ys = [getattr(s, field) for s in group]
            ys = [float("nan") if y is None else y for y in ys]
            if field == "success_rate":
                err = [
                    [y - s.ci95_low for y, s in zip(ys, group, strict=True)],
                    [s.ci95_high - y for y, s in zip(ys, group, strict=True)],
                ]
                ax.errorbar(xs, ys, yerr=err, marker="o", capsize=3, label=mission)
                ax.set_ylim(-0.05, 1.05)
            else:
                ax.plot(xs, ys, marker="o", label=mission)
        ax.set_title(title, fontsize=10)
        ax.set_xlabel(keys[0].split(".")[-1] if numeric else ", ".join(keys) or "runs")
        if not numeric:
            ax.set_xticks(range(len(labels)), labels, rotation=30, ha="right", fontsize=7)
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    return True
