"""nav2_util's path helpers on (N, 3) pose arrays: segment lengths, where a window along a
path ends, and the pose of a window closest to the robot.

Nav2 searches a path for the robot in three places: the controller server's path handler
(`first_after_integrated_distance`, then `min_by` over the poses before it), the
controllers that prune their own plan, and bt_navigator's feedback (from the last closest
pose, `search_window` metres on); the controller server's tracking feedback measures the
robot against the segments of such a window. btnav has each piece once, here.

A window's lengths are running sums from its first pose, in path order, as Nav2's loops
add them: the path's running sums from its start, differenced, round differently, and on
a NavFn path (5 cm steps) many windows end in such a tie.

Where btnav departs from Nav2: the closest pose is the *first* of equal nearest ones
(numpy's argmin), where `min_by` keeps the last; the trajectories are pinned to it.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from . import fmath

#: Segments of the first chunk a window's running sum adds (then four times more each time).
_CHUNK = 128


def segment_lengths(poses: NDArray[Any]) -> NDArray[Any]:
    """The length of each segment poses[i] -> poses[i + 1] (in the poses' float type)."""
    d = poses[1:, :2] - poses[:-1, :2]  # np.diff, without its overhead
    return fmath.hypot(d[:, 0], d[:, 1])  # type: ignore[no-any-return]


def first_beyond(along: NDArray[Any], distance: float, *, reaching: bool = False) -> int:
    """The first index of the running lengths `along` past `distance` (with `reaching`: at
    or past it), len(along) if none. By bisection, the lengths never decreasing; a NaN,
    which numpy sorts last, counts as reached but never as past."""
    if reaching:
        return int(along.searchsorted(distance, side="left"))
    k = int(along.searchsorted(distance, side="right"))
    if k < len(along) and not along[k] > distance:  # a NaN: the long way
        beyond = np.flatnonzero(along > distance)
        k = int(beyond[0]) if beyond.size else len(along)
    return k


def first_after_integrated_distance(
    seg: NDArray[Any], start: int, distance: float, *, reaching: bool = False
) -> int:
    """The first pose after `start` whose length along the path from `start` is past
    `distance` (at or past it with `reaching`), or the pose count (len(seg) + 1) if none:
    one past the last pose of the window. `seg` is `segment_lengths` of the path.

    The running sum grows in chunks (a window is a short stretch of a long plan), each
    continuing the one before: the same additions in the same order as one cumsum."""
    n = len(seg) + 1
    total = 0.0
    i = start  # the chunk's first segment is poses[i] -> poses[i + 1]
    size = _CHUNK
    while i < n - 1:
        j = min(i + size, n - 1)
        lengths = seg[i:j]
        if i != start:
            lengths = lengths.copy()
            lengths[0] += total
        along = np.cumsum(lengths)
        k = first_beyond(along, distance, reaching=reaching)
        if k < len(along):
            return i + 1 + k
        total = float(along[-1])
        i = j
        size *= 4
    return n


def closest_pose(
    poses: NDArray[Any], x: float, y: float, start: int = 0, stop: int | None = None
) -> int:
    """The pose of poses[start:stop] (not empty) nearest (x, y): the first minimum of the
    squared distances, as numpy's argmin finds it (a NaN distance: the first NaN)."""
    window = poses[start:stop]
    d2 = (window[:, 0] - x) ** 2 + (window[:, 1] - y) ** 2
    return start + int(d2.argmin())
