"""bt_navigator's `distance_remaining`: the robot's progress along the blackboard's path.

Nav2 (`NavigateToPoseNavigator::onLoop`) finds the path pose closest to the robot
within `search_window` metres (along the path) of the last closest one, then sums the
path's length from there (`nav2_util::calculate_path_length`). The tree ticks 100
times a second and the path changes about once, so everything that depends only on
the path is kept per path: its coordinates as Python floats, its segment lengths and
their running sums, and per closest pose the window's end and the length left.

The closest pose is the first minimum of the squared distances, as numpy's `argmin`
over `dx*dx + dy*dy` finds it, but without visiting every pose of the window: by the
triangle inequality a pose `s` metres along the path from one at distance `d` is at
least `d - s` from the robot, so the poses that cannot beat the best one so far (by
more than a rounding margin) are jumped over. The poses it does visit get the same
float64 arithmetic as numpy's, so the index found is the same, ties included.
"""

from __future__ import annotations

import math
from bisect import bisect_left
from itertools import accumulate
from typing import Any

import numpy as np

from ..core import fmath
from ..core.messages import Path

#: Relative slack on the distance bound: far above float64 rounding (1e-16), far below
#: any distance a path resolves, so a jump never passes a pose that could be closest.
_SLACK = 1e-9


class PathProgress:
    """The closest pose and the length left along one path at a time (Nav2's feedback)."""

    def __init__(self) -> None:
        self.path: Path | None = None
        self.closest = 0  # index of the path pose closest to the robot
        self._xs: list[float] = []  # the path's x and y, as Python floats
        self._ys: list[float] = []
        self._arc: list[float] = []  # length along the path to each pose
        self._seg: Any = None  # the segment lengths (numpy), as Nav2 sums them
        self._slack = 0.0  # the distance bound's absolute margin for this path
        self._exact = False  # float64 and finite: the pruned scan applies
        self._px: Any = None  # the path's x and y (numpy), for the full scan
        self._py: Any = None
        self._window_end: dict[int, int] = {}  # by closest pose
        self._length_from: dict[int, float] = {}  # by closest pose
        # the last search, (start, x, y) -> closest: odometry comes at half the tree's rate
        self._last: tuple[int, float, float, int] = (-1, math.nan, math.nan, 0)

    def reset(self) -> None:
        """A new goal: the next path starts the search from its first pose."""
        self.path = None
        self.closest = 0

    def _take(self, path: Path) -> None:
        """Everything that depends only on `path`, once per path."""
        self.path, self.closest = path, 0
        xy = path.poses[:, :2]
        self._px, self._py = np.ascontiguousarray(xy[:, 0]), np.ascontiguousarray(xy[:, 1])
        self._seg = seg = fmath.hypot(*np.diff(xy, axis=0).T) if len(xy) > 1 else np.zeros(0)
        self._window_end = {}
        self._length_from = {}
        self._last = (-1, math.nan, math.nan, 0)
        self._exact = xy.dtype == np.float64 and bool(np.isfinite(xy).all())
        if self._exact:
            self._xs, self._ys = self._px.tolist(), self._py.tolist()
            self._arc = [0.0, *accumulate(seg.tolist())]
            scale = self._arc[-1] + float(np.abs(xy).max())
            self._exact = math.isfinite(scale)
            self._slack = _SLACK * (1.0 + scale)

    def remaining(self, path: Path, x: float, y: float, search_window: float) -> float:
        """The length of `path` left from its pose closest to the robot at (x, y)."""
        if path is not self.path or self._seg is None:
            self._take(path)
        seg = self._seg
        start = self.closest
        last = self._last
        if last[0] == start and last[1] == x and last[2] == y:  # the same search again
            self.closest = closest = last[3]
            return self._length_from[closest]
        window_end = self._window_end.get(start)
        if window_end is None:
            window_end = start + 1
            if len(seg):
                along = np.cumsum(seg[start:])
                window_end = start + 1 + int(np.searchsorted(along, search_window))
            self._window_end[start] = window_end
        stop = min(window_end + 1, len(self._px))
        if self._exact and math.isfinite(x) and math.isfinite(y):
            closest = self._scan(start, stop, x, y)
        else:
            closest = self._full_scan(start, stop, x, y)
        self.closest = closest
        self._last = (start, x, y, closest)
        remaining = self._length_from.get(closest)
        if remaining is None:
            remaining = self._length_from[closest] = float(seg[closest:].sum())
        return remaining

    def _full_scan(self, start: int, stop: int, x: float, y: float) -> int:
        """numpy's argmin over the window's squared distances (NaNs as numpy treats them)."""
        dx = self._px[start:stop] - x
        dy = self._py[start:stop] - y
        dx *= dx
        dy *= dy
        dx += dy
        return start + int(dx.argmin())

    def _scan(self, start: int, stop: int, x: float, y: float) -> int:
        """`_full_scan`'s index, jumping over poses the triangle inequality rules out."""
        xs, ys, arc = self._xs, self._ys, self._arc
        slack = self._slack + _SLACK * (abs(x) + abs(y))
        dx = xs[start] - x
        dy = ys[start] - y
        best_sq = dx * dx + dy * dy
        best = start
        reach = math.sqrt(best_sq) + slack  # no pose nearer than this is ruled out
        i = start + 1
        while i < stop:
            dx = xs[i] - x
            dy = ys[i] - y
            sq = dx * dx + dy * dy
            if sq < best_sq:
                best_sq, best = sq, i
                reach = math.sqrt(sq) + slack
                i += 1
                continue
            # every pose k > i is at least sqrt(sq) - (arc[k] - arc[i]) from the robot
            gap = math.sqrt(sq) - reach
            i = bisect_left(arc, arc[i] + gap, i + 1, stop) if gap > 0.0 else i + 1
        return best
