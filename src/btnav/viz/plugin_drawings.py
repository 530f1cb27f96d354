"""Plugins' own shapes (`core.drawing`) on a matplotlib axes: `run.png` draws them once,
`run.gif` moves the same three artists each frame (lines, outlines, dots)."""

from __future__ import annotations

from typing import Any

import numpy as np

from ..core.drawing import Drawable

ZORDER = 5.8


def plot_drawables(ax: Any, drawables: list[Drawable]) -> None:
    """Each shape as its own artist, labelled for the legend (each label once)."""
    from matplotlib.patches import Polygon

    seen: set[str] = set()
    for d in drawables:
        label = d.label if d.label and d.label not in seen else None
        seen.add(d.label)
        if d.kind == "polygon":
            if len(d.points) >= 3:
                patch = Polygon(d.points, closed=True, fill=False, edgecolor=d.color, label=label)
                patch.set_zorder(ZORDER)
                ax.add_patch(patch)
            continue
        style = {"linestyle": "-", "linewidth": 1.6} if d.kind == "polyline" else {}
        marker = {} if d.kind == "polyline" else {"marker": ".", "linestyle": "none"}
        ax.plot(*d.points.T, color=d.color, zorder=ZORDER, label=label, **style, **marker)


class DrawableArtists:
    """Three animated artists that show a frame's drawables (blitted by `run.gif`)."""

    def __init__(self, ax: Any) -> None:
        from matplotlib.collections import LineCollection, PolyCollection

        self.lines = ax.add_collection(LineCollection([], linewidths=1.6, zorder=ZORDER))
        self.outlines = ax.add_collection(
            PolyCollection([], facecolors="none", linewidths=1.2, zorder=ZORDER)
        )
        self.dots = ax.scatter(np.zeros(0), np.zeros(0), s=4, zorder=ZORDER)

    @property
    def artists(self) -> list[Any]:
        return [self.lines, self.outlines, self.dots]

    def show(self, drawables: list[Drawable]) -> None:
        lines = [d for d in drawables if d.kind == "polyline"]
        shapes = [d for d in drawables if d.kind == "polygon"]
        dots = [d for d in drawables if d.kind == "points"]
        self.lines.set_segments([d.points for d in lines])
        self.lines.set_colors([d.color for d in lines])
        self.outlines.set_verts([d.points for d in shapes])
        self.outlines.set_edgecolors([d.color for d in shapes])
        offsets = np.concatenate([d.points for d in dots]) if dots else np.zeros((0, 2))
        self.dots.set_offsets(offsets)
        self.dots.set_facecolors([d.color for d in dots for _ in range(len(d.points))])


def legend_handles(drawables: list[Drawable]) -> list[Any]:
    """One legend handle per label seen (in the order first seen)."""
    from matplotlib.lines import Line2D

    handles: dict[str, Any] = {}
    for d in drawables:
        if d.label and d.label not in handles:
            marker = {"marker": ".", "linestyle": "none"} if d.kind == "points" else {}
            handles[d.label] = Line2D([], [], color=d.color, label=d.label, **marker)
    return list(handles.values())
