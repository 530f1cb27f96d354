"""bt_navigator's `distance_remaining`: the robot's progress along the blackboard's path.

Nav2 (`NavigateToPoseNavigator::onLoop`) finds the path pose closest to the robot
within `search_window` metres (along the path) of the last closest one, then sums the
path's length from there (`nav2_util::calculate_path_length`). The tree ticks 100
times a second and the path changes about once, so everything that depends only on
the path is kept per path: its coordinates as Python floats, its segment lengths, their
running sums, the length left from every pose (one running sum from the path's end:
Nav2 sums from each pose on, so the two differ by rounding, 1e-14 m on the office
tour), and the window's end per start as the robot reaches it.

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
rate): the same start and robot give the same answer, kept. When the closest pose moved
on, the repeat starts from it, and is kept as well when the certificate shows it must
find the same pose (no near pose where its window reaches further).
"""

from __future__ import annotations

import math
from bisect import bisect_left
from collections.abc import Callable
from typing import Any

import numpy as np

from ..core.messages import Path

#: Relative slack on the distance bound: far above float64 rounding (1e-16), far below
#: any distance a path resolves, so a jump never passes a pose that could be closest.
_SLACK = 1e-9

#: How far (m) the robot may move from where a scan ran and still be searched among that
#: scan's near poses (six on a NavFn path): on the RPP office tour one scan serves about
#: thirteen searches (326 scans for 4322 searches; 515 at 3 cm, with four near poses, took
#: 5 ms more; 2847 without certificates).
_RADIUS = 0.05
_RADIUS_SQ = _RADIUS * _RADIUS
#: Poses past the window's end a certificate also covers: the window moves on with its start.
_AHEAD = 6
#: Poses whose window ends are worked out together (`_ahead`): on the RPP office tour
#: 37 blocks of 32 take 5.4 ms, 108 blocks of 8 took 12.4 (each numpy call runs cold).
_AHEAD_POSES = 32
#: The latest search of none (`PathProgress._last`).
_NO_SEARCH: tuple[int, float, float, float] = (-1, 0.0, 0.0, 0.0)
#: The certificate of no scan: (first, stop, x, y, radius², limit², near, near_end) covering
#: no window.
_NO_CERTIFICATE: tuple[Any, ...] = (1, 0, 0.0, 0.0, -1.0, 0.0, (), 0)


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
        self._arc: list[float] = []  # length along the path to each pose
        self._arc_np: Any = None  # the same (numpy)
        self._left: list[float] = []  # the length left from each pose
        self._slack = 0.0  # the distance bound's absolute margin for this path
        self._exact = False  # float64 and finite: the pruned scan applies
        self._px: Any = None  # the path's x and y (numpy), for the full scan
        self._py: Any = None
        self._stop: list[int] = []  # one past the search window's last pose by start (0: not yet)
        # the latest scan's certificate: poses first to stop (not included) of this path
        # are searched among `near`, ((index, x, y), ...), while the robot is within
        # `radius²` of (x, y) and the nearest near pose within `limit²` (`_certify`);
        # `near_end` is one past the last near pose
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
        self._n = n = len(xy)
        self._px, self._py = np.ascontiguousarray(xy[:, 0]), np.ascontiguousarray(xy[:, 1])
        self._seg = seg = path.segment_lengths  # (float64; shared with the tree's nodes)
        # the length left from each pose, summed from the path's end: one running sum for
        # every pose, where Nav2 sums from each pose on (the two differ by rounding only)
        self._left = [*np.cumsum(seg[::-1])[::-1].tolist(), 0.0]
        self._window_length = self.search_window()
        self._stop = [0] * n
        self._certificate = _NO_CERTIFICATE
        self._last = _NO_SEARCH
        self._exact = xy.dtype == np.float64 and bool(np.isfinite(xy).all())
        if self._exact:
            self._xs, self._ys = self._px.tolist(), self._py.tolist()
            self._arc_np = arc = np.concatenate([[0.0], np.cumsum(seg)])
            self._arc = arc.tolist()
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
        stop = self._stop[start]
        if not stop:  # (not worked out yet: a stop is past its start)
            self._ahead(start)
            stop = self._stop[start]
        closest = -1
        first, last, cx, cy, radius_sq, limit_sq, near, near_end = self._certificate
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
        covered = closest >= 0  # the certificate answers this search
        if not covered:
            if self._exact and math.isfinite(x) and math.isfinite(y):
                closest = self._certify(start, stop, x, y)
                certificate = self._certificate
                covered = certificate is not _NO_CERTIFICATE
                last, near_end = certificate[1], certificate[7]
            else:
                closest = self._full_scan(start, stop, x, y)
        self.closest = closest
        remaining = self._left[closest]
        if covered and closest != start:
            # The next search, from `closest` at the same spot (odometry at half the tree's
            # rate), finds `closest` again if the certificate covers its window too and no
            # near pose lies where that window reaches past this one's: its near poses are
            # then this search's from `closest` on, `closest` the first minimum of them.
            next_stop = self._stop[closest]
            if next_stop and next_stop <= last and near_end <= stop:
                start = closest
        self._last = (start, x, y, remaining)
        return remaining

    def _ahead(self, first: int) -> None:
        """The search window's stop (one past its last pose) for the poses from `first`
        on, `_AHEAD_POSES` of them: the robot moves on along the path, and a block costs
        the few numpy calls of one pose (each call cold between the simulation's steps)."""
        n, stops = self._n, self._stop
        starts = np.arange(first, min(first + _AHEAD_POSES, n))
        for start, end in zip(starts.tolist(), self._windows(starts), strict=True):
            stops[start] = min(end + 1, n)

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
        near_end = near[-1][0] + 1 if near else 0  # (near poses are in path order)
        self._certificate = (start, last, x, y, _RADIUS_SQ, limit * limit, tuple(near), near_end)
        return best

    def _windows(self, starts: np.ndarray) -> list[int]:
        """The last pose within `search_window` along the path from each start, as Nav2's
        `searchsorted(cumsum(seg[start:]), search_window)` finds it: from the running sums
        kept per path where they leave no doubt, else from cumsum's own sums from the start."""
        search_window, seg = self._window_length, self._seg
        if not len(seg):
            return (starts + 1).tolist()
        if not (self._exact and math.isfinite(search_window)):
            return [
                start + 1 + int(np.searchsorted(np.cumsum(seg[start:]), search_window))
                for start in starts.tolist()
            ]
        # arc[k] - arc[start] and cumsum's sum up to k differ by less than the slack
        arc = self._arc_np
        origin = arc[starts] + search_window
        lo = np.maximum(np.searchsorted(arc, origin - self._slack), starts + 1)
        hi = np.maximum(np.searchsorted(arc, origin + self._slack), starts + 1)
        tied = np.flatnonzero(lo != hi)  # a tie within rounding (a path on a grid: most)
        if len(tied):
            # cumsum's sums of every tied window, a row per start (padded with inf past the
            # path, which no window reaches); each row's sums to its `hi` cross the window,
            # so counting the sums below it is searchsorted's answer
            first = starts[tied]
            width = int((hi[tied] - first).max())
            padded = np.concatenate([seg, np.full(width, np.inf)])
            rows = padded[first[:, None] + np.arange(width)]
            lo[tied] = first + 1 + (np.cumsum(rows, axis=1) < search_window).sum(axis=1)
        return lo.tolist()

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
        them (`best`, at `best_sq`), jumping over poses the triangle inequality rules out.
        When the robot is far from the best pose so far, the window's last pose is measured
        first: if the robot is well ahead of the search's start (a new path is searched
        from its first pose), its distance rules out the poses far behind at once, where
        the scan would otherwise walk up to it pose by pose."""
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
