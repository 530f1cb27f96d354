"""bt_navigator's `distance_remaining`: the robot's progress along the blackboard's path.

Nav2 (`NavigateToPoseNavigator::onLoop`) finds the path pose closest to the robot
within `search_window` metres (along the path) of the last closest one, then sums the
path's length from there (`nav2_util::calculate_path_length`). The window and the
closest pose are `core.path_utils`' (the path handler's search): the window takes the
poses up to the first one at or past `search_window` from its start, the closest pose
is the first nearest one. The length left from every pose is one running sum per path,
from its end (Nav2 sums from each pose on: the two differ by rounding, 1e-14 m on the
office tour).

The tree ticks 100 times a second and odometry reports at half that rate, so every
other search repeats the one before (the same start and robot): its answer is kept, and
each window's end is worked out once per path.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from ..core.messages import Path
from ..core.path_utils import closest_pose, first_after_integrated_distance


class PathProgress:
    """The closest pose and the length left along one path at a time (Nav2's feedback)."""

    def __init__(self, search_window: Callable[[], float]) -> None:
        #: Nav2's `search_window` (m along the path), read once per path (Nav2 reads it
        #: once, at configure), so the window ends kept per path never outlive its value.
        self.search_window = search_window
        self._window = 0.0
        self.path: Path | None = None  # the path of the latest search (never an empty one)
        self.closest = 0  # index of the path pose closest to the robot
        self._seg: Any = None  # the path's segment lengths
        self._left: list[float] = []  # the length left from each pose
        self._stop: dict[int, int] = {}  # one past the window's last pose, by its start
        self._last: tuple[int, float, float] | None = None  # the latest search's start and robot

    def reset(self) -> None:
        """A new goal: the next path starts the search from its first pose."""
        self.path = None
        self.closest = 0

    def _take(self, path: Path) -> None:
        """What depends only on `path`, once per path."""
        self.path, self.closest = path, 0
        self._seg = seg = path.segment_lengths  # (shared with the tree's nodes)
        self._left = [*np.cumsum(seg[::-1])[::-1].tolist(), 0.0]
        self._window = self.search_window()
        self._stop = {}
        self._last = None

    def remaining(self, path: Path, x: float, y: float) -> float:
        """The length of `path` (not empty) left from its pose closest to the robot at (x, y)."""
        if path is not self.path:
            self._take(path)
        start = self.closest
        search = (start, x, y)
        if search != self._last:
            stop = self._stop.get(start)
            if stop is None:
                end = first_after_integrated_distance(self._seg, start, self._window, reaching=True)
                stop = self._stop[start] = min(end + 1, len(path))
            self.closest = closest_pose(path.poses, x, y, start, stop)
            self._last = search
        return self._left[self.closest]
