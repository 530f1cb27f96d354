"""What a plugin draws of itself: `drawables()` giving plain shapes in a named frame.

A controller, costmap layer or filter may define `drawables(self) -> list[Drawable]`;
the live view, `run.gif` and `run.png` draw what it returns, placed through the frame
tree, so a user's plugin shows its own state (a carrot, a corridor, candidate arcs)
without btnav knowing its attributes. Shapes are plain data (an (N, 2) array of x, y
in `frame`, a colour and an optional legend label), cheap to make and to copy.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal, Protocol, runtime_checkable

import numpy as np

Kind = Literal["polyline", "points", "polygon"]


@dataclass(frozen=True)
class Drawable:
    """One shape: `points` (N, 2) x, y in `frame`, drawn as a line, dots or a closed outline."""

    kind: Kind
    points: np.ndarray
    frame: str
    color: str = "#9467bd"
    label: str = ""

    def __post_init__(self) -> None:
        if self.kind not in ("polyline", "points", "polygon"):
            raise ValueError(f"a Drawable is a polyline, points or polygon, not {self.kind!r}")
        pts = np.asarray(self.points, dtype=float).reshape(-1, 2)
        object.__setattr__(self, "points", pts)


def polyline(points: object, frame: str, color: str = "#9467bd", label: str = "") -> Drawable:
    return Drawable("polyline", np.asarray(points, dtype=float), frame, color, label)


def points(points: object, frame: str, color: str = "#9467bd", label: str = "") -> Drawable:
    return Drawable("points", np.asarray(points, dtype=float), frame, color, label)


def polygon(points: object, frame: str, color: str = "#9467bd", label: str = "") -> Drawable:
    return Drawable("polygon", np.asarray(points, dtype=float), frame, color, label)


@runtime_checkable
class Draws(Protocol):
    """A plugin that draws itself."""

    def drawables(self) -> list[Drawable]: ...
