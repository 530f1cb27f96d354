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

Most searches need no scan: the robot moves about a centimetre between two odometry
messages and the closest pose changes every few centimetres. A scan from a start near
the robot leaves a certificate: the poses closer than the start's distance plus twice
`_RADIUS` ("near", a small tuple), every other pose of the window (and of a few poses
past its end) measured or jumped over as further. From anywhere within `_RADIUS` of
where the scan ran those others are no nearer than that reach less `_RADIUS`, so while
a near pose of the window is nearer than that, the first minimum over the near poses
(measured in order, with the scan's arithmetic) is the first minimum over the window.
And every other search repeats the one before (odometry reports at half the tree's
rate): the same start and robot give the same answer, kept.
"""

from __future__ import annotations

import math
from bisect import bisect_left
from collections.abc import Callable
from itertools import accumulate
from typing import Any

import numpy as np

from ..core import fmath
from ..core.messages import Path

_add_reduce = np.add.reduce

#: Relative slack on the distance bound: far above float64 rounding (1e-16), far below
#: any distance a path resolves, so a jump never passes a pose that could be closest.
_SLACK = 1e-9

#: How far (m) the robot may move from where a scan ran and still be searched among that
#: scan's near poses (about four on a NavFn path): on the RPP office tour one scan serves
#: about eight searches (515 scans for 4322 searches; 2847 without certificates).
_RADIUS = 0.03
#: Poses past the window's end a certificate also covers: the window moves on with its start.
_AHEAD = 6
#: Poses whose window end and length left are computed together (`_ahead`).
_AHEAD_POSES = 8
#: The latest search of none (`PathProgress._last`).
_NO_SEARCH: tuple[int, float, float, float] = (-1, 0.0, 0.0, 0.0)
#: The certificate of no scan: (first, stop, x, y, radius², limit², near) covering no window.
_NO_CERTIFICATE: tuple[Any, ...] = (1, 0, 0.0, 0.0, -1.0, 0.0, ())


class PathProgress:
    """The closest pose and the length left along one path at a time (Nav2's feedback)."""

    def __init__(self, search_window: Callable[[], float]) -> None:
        #: Nav2's `search_window` (m along the path), read once per path (Nav2 reads it
        #: once, at configure), so the window ends kept per path never outlive its value.
        self.search_window = search_window
        self._window_length = 0.0
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
        # the latest scan's certificate: poses first to stop (not included) of this path
        # are searched among `near`, ((index, x, y), ...), while the robot is within
        # `radius²` of (x, y) and the nearest near pose within `limit²` (`_certify`)
        self._certificate = _NO_CERTIFICATE
        # the latest search, (start, x, y, length left): odometry reports at half the
        # tree's rate, so every other search repeats the one before it (the same start
        # and robot, hence the same closest pose)
        self._last: tuple[int, float, float, float] = _NO_SEARCH

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
        self._window_length = self.search_window()
        self._stop = {}
        self._length_from = {}
        self._certificate = _NO_CERTIFICATE
        self._last = _NO_SEARCH
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
        last_start, last_x, last_y, last_remaining = self._last
        if start == last_start and x == last_x and y == last_y:
            return last_remaining  # (the same search: NaN never equals)
        stop = self._stop.get(start)
        if stop is None:
            self._ahead(start)
            stop = self._stop[start]
        closest = -1
        first, last, cx, cy, radius_sq, limit_sq, near = self._certificate
        if first <= start and stop <= last:
            dx = x - cx
            dy = y - cy
            if dx * dx + dy * dy <= radius_sq:  # (False for NaN)
                best_sq = limit_sq
                for i, px, py in near:
                    if start <= i < stop:
                        dx = px - x
                        dy = py - y
                        sq = dx * dx + dy * dy
                        if sq < best_sq:  # (in order: the first of equal ones stays)
                            best_sq, closest = sq, i
        if closest < 0:
            if self._exact and math.isfinite(x) and math.isfinite(y):
                closest = self._certify(start, stop, x, y)
            else:
                closest = self._full_scan(start, stop, x, y)
        self.closest = closest
        remaining = self._length_from.get(closest)
        if remaining is None:
            self._ahead(closest)
            remaining = self._length_from[closest]
        self._last = (start, x, y, remaining)  # (repeated only if closest == start)
        return remaining

    def _ahead(self, first: int) -> None:
        """The window's end (one past it) and the length left for poses `first` to
        `first + _AHEAD_POSES`: the robot moves on along the path, and these calls, cold
        one at a time between the simulation's steps, run warm back to back."""
        n, seg = self._n, self._seg
        stops, lengths = self._stop, self._length_from
        poses = range(first, min(first + _AHEAD_POSES, n))
        starts = [i for i in poses if i not in stops]
        for i, end in zip(starts, self._windows(starts), strict=True):
            stops[i] = min(end + 1, n)
        for i in poses:
            if i not in lengths:  # float(seg[i:].sum()), without sum's Python wrapper
                lengths[i] = float(_add_reduce(seg[i:]))

    def _certify(self, start: int, stop: int, x: float, y: float) -> int:
        """`_full_scan`'s index, leaving a certificate for the searches that follow when
        the robot is near the window's start (else `_scan`'s, and no certificate).

        The near poses are those closer than `reach`, the start's distance plus twice the
        radius; every other pose from `start` to `last` is jumped over or measured no
        nearer than `reach` (less the rounding slack). From anywhere within the radius of
        (x, y) those are no nearer than `reach - radius`, so a near pose below `limit`
        (that, less the slack) is nearer than all of them: the first minimum over the
        near poses is the first minimum over the window."""
        xs, ys, arc = self._xs, self._ys, self._arc
        dx = xs[start] - x
        dy = ys[start] - y
        start_sq = dx * dx + dy * dy
        if start_sq > (4.0 * _RADIUS) ** 2:  # far from the start (a new path): no certificate
            self._certificate = _NO_CERTIFICATE
            return self._scan(start + 1, stop, x, y, start, start_sq)
        slack = self._slack + _SLACK * (1.0 + abs(x) + abs(y))
        last = min(self._n, stop + _AHEAD)
        sqrt = math.sqrt
        reach = sqrt(start_sq) + 2.0 * _RADIUS + 4.0 * slack
        near: list[tuple[int, float, float]] = []
        best, best_sq = start, math.inf
        i = start
        while i < last:
            dx = xs[i] - x
            dy = ys[i] - y
            sq = dx * dx + dy * dy
            distance = sqrt(sq)
            if distance < reach:
                near.append((i, xs[i], ys[i]))
                if sq < best_sq and i < stop:
                    best_sq, best = sq, i
                i += 1
                continue
            # every pose k > i is at least distance - (arc[k] - arc[i]) from the robot
            gap = distance - reach
            i = bisect_left(arc, arc[i] + gap, i + 1, last) if gap > 0.0 else i + 1
        limit = reach - _RADIUS - 3.0 * slack
        self._certificate = (start, last, x, y, _RADIUS * _RADIUS, limit * limit, tuple(near))
        return best

    def _windows(self, starts: list[int]) -> list[int]:
        """The last pose within `search_window` along the path from each start, as Nav2's
        `searchsorted(cumsum(seg[start:]), search_window)` finds it: from the running sums
        kept per path where they leave no doubt, else from cumsum's own sequential sums."""
        search_window = self._window_length
        if not len(self._seg):
            return [start + 1 for start in starts]
        if not (self._exact and math.isfinite(search_window)):
            seg = self._seg
            return [
                start + 1 + int(np.searchsorted(np.cumsum(seg[start:]), search_window))
                for start in starts
            ]
        arc, slack = self._arc, self._slack
        ends: list[int] = []
        ties: list[tuple[int, int, int]] = []  # (index in ends, start, hi)
        for start in starts:
            origin = arc[start] + search_window
            # arc[k] - arc[start] and cumsum's sum up to k differ by less than the slack
            lo = bisect_left(arc, origin - slack, start + 1)
            hi = bisect_left(arc, origin + slack, start + 1)
            if lo != hi:  # a tie within rounding (a path on a grid: most windows)
                ties.append((len(ends), start, hi))
            ends.append(lo)
        if len(ties) == 1:  # cumsum adds in order, as accumulate does on Python floats
            k, start, hi = ties[0]
            along = list(accumulate(self._segs[start:hi]))
            ends[k] = start + 1 + bisect_left(along, search_window)
        elif ties:
            # the sums of all the tied windows in one cumsum, a row per start (rows padded
            # with inf past the path, which no window reaches); each row's sums to `hi`
            # cross the window, so counting the sums below it is bisect's answer
            width = max(hi - start for _, start, hi in ties)
            padded = np.concatenate([self._seg, np.full(width, np.inf)])
            first = np.array([start for _, start, _ in ties])
            rows = padded[first[:, None] + np.arange(width)]
            below = (np.cumsum(rows, axis=1) < search_window).sum(axis=1).tolist()
            for (k, start, _), count in zip(ties, below, strict=True):
                ends[k] = start + 1 + count
        return ends

    def _full_scan(self, start: int, stop: int, x: float, y: float) -> int:
        """numpy's argmin over the window's squared distances (NaNs as numpy treats them)."""
        dx = self._px[start:stop] - x
        dy = self._py[start:stop] - y
        dx *= dx
        dy *= dy
        dx += dy
        return start + int(dx.argmin())

    def _scan(self, first: int, stop: int, x: float, y: float, best: int, best_sq: float) -> int:
        """`_full_scan`'s index over poses `first` to `stop`, given the closest pose before
        them (`best`, at `best_sq`), jumping over poses the triangle inequality rules out. When the robot is far from the best pose so far, the window's
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
        return end if end_sq < best_sq else best
