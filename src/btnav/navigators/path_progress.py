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
from collections.abc import Callable
from itertools import accumulate, islice
from typing import Any

import numpy as np

from ..core import fmath
from ..core.messages import Path

_add_reduce = np.add.reduce

#: Relative slack on the distance bound: far above float64 rounding (1e-16), far below
#: any distance a path resolves, so a jump never passes a pose that could be closest.
_SLACK = 1e-9


class PathProgress:
    """The closest pose and the length left along one path at a time (Nav2's feedback)."""

    def __init__(self, search_window: Callable[[], float]) -> None:
        #: Nav2's `search_window` (m along the path), read each time a window is computed.
        self.search_window = search_window
        self.path: Path | None = None  # the path of the latest search (never an empty one)
        self.closest = 0  # index of the path pose closest to the robot
        self._n = 0  # the path's poses
        self._xs: list[float] = []  # the path's x and y, as Python floats
        self._ys: list[float] = []
        self._seg: Any = None  # the segment lengths (numpy), as Nav2 sums them
        self._segs: list[float] = []  # the same, as Python floats
        self._arc: list[float] = []  # length along the path to each pose
        self._slack = 0.0  # the distance bound's absolute margin for this path
        self._exact = False  # float64 and finite: the pruned scan applies
        self._px: Any = None  # the path's x and y (numpy), for the full scan
        self._py: Any = None
        self._stop: dict[int, int] = {}  # one past the search window's last pose, by start
        self._length_from: dict[int, float] = {}  # by closest pose
        # the last search, (start, x, y, closest, its squared distance, stop): odometry
        # comes at half the tree's rate
        self._last: tuple[int, float, float, int, float, int] = (
            -1,
            math.nan,
            math.nan,
            0,
            math.nan,
            -1,
        )

    def reset(self) -> None:
        """A new goal: the next path starts the search from its first pose."""
        self.path = None
        self.closest = 0

    def _take(self, path: Path) -> None:
        """Everything that depends only on `path`, once per path."""
        self.path, self.closest = path, 0
        xy = path.poses[:, :2]
        self._n = len(xy)
        self._px, self._py = np.ascontiguousarray(xy[:, 0]), np.ascontiguousarray(xy[:, 1])
        self._seg = seg = fmath.hypot(*np.diff(xy, axis=0).T) if len(xy) > 1 else np.zeros(0)
        self._stop = {}
        self._length_from = {}
        self._last = (-1, math.nan, math.nan, 0, math.nan, -1)
        self._exact = xy.dtype == np.float64 and bool(np.isfinite(xy).all())
        if self._exact:
            self._xs, self._ys = self._px.tolist(), self._py.tolist()
            self._segs = seg.tolist()
            self._arc = [0.0, *accumulate(self._segs)]
            scale = self._arc[-1] + float(np.abs(xy).max())
            self._exact = math.isfinite(scale)
            self._slack = _SLACK * (1.0 + scale)

    def remaining(self, path: Path, x: float, y: float) -> float:
        """The length of `path` (not empty) left from its pose closest to the robot at (x, y)."""
        if path is not self.path:
            self._take(path)
        start = self.closest
        last = self._last
        if last[1] == x and last[2] == y and last[0] == start:  # the same search again
            closest = last[3]
        else:
            stop = self._stop.get(start)
            if stop is None:
                end = self._window(start, self.search_window())
                stop = self._stop[start] = min(end + 1, self._n)
            if not (self._exact and math.isfinite(x) and math.isfinite(y)):
                closest, best_sq = self._full_scan(start, stop, x, y), math.nan
            elif last[1] == x and last[2] == y and last[3] == start and last[5] <= stop:
                # the robot has not moved since the search that found `start` (odometry
                # comes at half the tree's rate): that search's window held no pose nearer
                # than `start` up to its end, so only the poses this window adds can be
                closest, best_sq = self._scan(last[5], stop, x, y, start, last[4])
            else:
                dx = self._xs[start] - x
                dy = self._ys[start] - y
                closest, best_sq = self._scan(start + 1, stop, x, y, start, dx * dx + dy * dy)
            self._last = (start, x, y, closest, best_sq, stop)
        self.closest = closest
        remaining = self._length_from.get(closest)
        if remaining is None:  # float(seg[closest:].sum()), without sum's Python wrapper
            remaining = self._length_from[closest] = float(_add_reduce(self._seg[closest:]))
        return remaining

    def _window(self, start: int, search_window: float) -> int:
        """The last pose within `search_window` along the path from `start`, as Nav2's
        `searchsorted(cumsum(seg[start:]), search_window)` finds it: from the running sums
        kept per path where they leave no doubt, else from cumsum's own sequential sums."""
        if not len(self._seg):
            return start + 1
        if self._exact and math.isfinite(search_window):
            arc, slack = self._arc, self._slack
            origin = arc[start] + search_window
            # arc[k] - arc[start] and cumsum's sum up to k differ by less than the slack
            lo = bisect_left(arc, origin - slack, start + 1)
            hi = bisect_left(arc, origin + slack, start + 1)
            if lo == hi:
                return lo
            # a tie within rounding (a path on a grid, a window a multiple of its step):
            # cumsum adds in order, as accumulate does on Python floats
            along = list(accumulate(islice(self._segs, start, hi)))
            return start + 1 + bisect_left(along, search_window)
        along = np.cumsum(self._seg[start:])
        return start + 1 + int(np.searchsorted(along, search_window))

    def _full_scan(self, start: int, stop: int, x: float, y: float) -> int:
        """numpy's argmin over the window's squared distances (NaNs as numpy treats them)."""
        dx = self._px[start:stop] - x
        dy = self._py[start:stop] - y
        dx *= dx
        dy *= dy
        dx += dy
        return start + int(dx.argmin())

    def _scan(
        self, first: int, stop: int, x: float, y: float, best: int, best_sq: float
    ) -> tuple[int, float]:
        """`_full_scan`'s index and squared distance over poses `first` to `stop`, given the
        closest pose before them (`best`, at `best_sq`), jumping over poses the triangle
        inequality rules out. When the robot is far from the best pose so far, the window's
        last pose is measured first: if the robot is well ahead of the search's start (a
        new path is searched from its first pose), its distance rules out the poses far
        behind at once, where the scan would otherwise walk up to it pose by pose."""
        xs, ys, arc = self._xs, self._ys, self._arc
        slack = self._slack + _SLACK * (abs(x) + abs(y))
        sqrt = math.sqrt
        end, end_sq = stop, math.inf  # the window's last pose, measured first
        if stop - first >= 2 and 16.0 * best_sq > (arc[stop - 1] - arc[first]) ** 2:
            # (the robot is a quarter of the window or more away from the best pose so far:
            # it may well be ahead; nearer, the scan rules the far poses out by itself)
            end = stop - 1
            dx = xs[end] - x
            dy = ys[end] - y
            end_sq = dx * dx + dy * dy
        bound = end_sq if end_sq < best_sq else best_sq  # some pose of the window is this near
        reach = sqrt(bound) + slack  # no pose nearer than this is ruled out
        i = first
        while i < end:
            dx = xs[i] - x
            dy = ys[i] - y
            sq = dx * dx + dy * dy
            if sq < bound:  # (bound <= best_sq; in order: the first of equal ones stays)
                bound = best_sq = sq
                best = i
                reach = sqrt(sq) + slack
                i += 1
                continue
            if sq < best_sq:  # nearer than the poses before, not than the window's last
                best_sq, best = sq, i
            # every pose k > i is at least sqrt(sq) - (arc[k] - arc[i]) from the robot
            gap = sqrt(sq) - reach
            i = bisect_left(arc, arc[i] + gap, i + 1, end) if gap > 0.0 else i + 1
        if end_sq < best_sq:
            best_sq, best = end_sq, end
        return best, best_sq
