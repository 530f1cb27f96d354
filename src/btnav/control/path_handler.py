"""The path handler (nav2_controller::FeasiblePathHandler): the part of the global plan a controller sees.

Each control cycle it finds the plan pose closest to the robot (searching only
the first `max_robot_pose_search_dist` metres of the remaining plan, so a path
that passes the robot twice is not short-cut), drops everything before it, and
hands the controller the next `prune_distance` metres, transformed into the
costmap's frame and cut where the plan leaves the costmap.

With `enforce_path_inversion` (a cusp where the plan reverses direction) or
`enforce_path_rotation` (an in-place rotation larger than
`minimum_rotation_angle`), the controller only sees the plan up to that
constraint; once the robot is within `inversion_xy_tolerance` /
`inversion_yaw_tolerance` of that pose, the rest of the plan is released.

The helpers `integrated_index` and `closest_index` are vectorised and shared with
the controllers (DWB, RPP) that prune a plan themselves.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray
from pydantic import Field

from ..core import fmath
from ..core.geometry import Pose2D, angle_diff, compose_arrays
from ..core.messages import Path
from ..costmap.costmap_2d import Costmap2D
from ..params.schema import ParamsModel
from ..plugins import Plugin, register
from .exceptions import InvalidPath

_EPS_TRANS = 1e-4
#: Segments of the first chunk `integrated_index` sums (then four times more each time).
_CHUNK = 128


def segment_lengths(poses: NDArray[np.float64]) -> NDArray[np.float64]:
    """Length of each segment poses[i] -> poses[i + 1] (what `integrated_index` sums)."""
    d = poses[1:, :2] - poses[:-1, :2]  # np.diff, without its overhead
    return fmath.hypot(d[:, 0], d[:, 1])


def integrated_index(
    poses: NDArray[np.float64],
    start: int,
    distance: float,
    seg: NDArray[np.float64] | None = None,
) -> int:
    """Index of the first pose after `start` whose path distance from `start` exceeds `distance`
    (len(poses) when none does): the exclusive end of the window of that length.

    `seg`, when given, is `segment_lengths(poses)` (worked out once for a plan that is
    pruned from the front cycle after cycle: the lengths do not change)."""
    n = len(poses)
    if start >= n:
        return n
    # The running length in growing chunks from `start` (a window is a short stretch of a
    # long plan): the same sums, added in the same order, as one cumsum over the rest.
    total = 0.0
    i = start  # the chunk's first segment is poses[i] -> poses[i + 1]
    size = _CHUNK
    while i < n - 1:
        j = min(i + size, n - 1)
        if seg is None:
            d = poses[i + 1 : j + 1, :2] - poses[i:j, :2]  # np.diff, without its overhead
            lengths = fmath.hypot(d[:, 0], d[:, 1])
        else:
            lengths = seg[i:j]
        if i != start:
            # the chunk continues the running sum: total + s_i, then + s_i+1 ...
            lengths = lengths.copy()
            lengths[0] += total
        along = np.cumsum(lengths)
        # The sums never decrease (lengths are >= 0): the first one beyond `distance` is
        # found by bisection; a NaN (sorted last) is checked the long way.
        k = int(along.searchsorted(distance, side="right"))
        if k < len(along):
            if along[k] > distance:
                return i + 1 + k
            beyond = np.flatnonzero(along > distance)
            if beyond.size:
                return i + 1 + int(beyond[0])
        total = float(along[-1])
        i = j
        size *= 4
    return n


def closest_index(
    poses: NDArray[np.float64],
    x: float,
    y: float,
    search_dist: float = math.inf,
    seg: NDArray[np.float64] | None = None,
) -> int:
    """The closest pose to (x, y) among the first `search_dist` metres of the path (`seg`:
    see `integrated_index`)."""
    upper = (
        integrated_index(poses, 0, search_dist, seg) if math.isfinite(search_dist) else len(poses)
    )
    upper = max(upper, 1)
    d2 = (poses[:upper, 0] - x) ** 2 + (poses[:upper, 1] - y) ** 2
    return int(d2.argmin())


def first_beyond(along: NDArray[np.float64], distance: float) -> int:
    """The first index of the running lengths `along` beyond `distance` (len(along) if none):
    by bisection, as lengths are >= 0; a NaN (sorted last) is checked the long way."""
    k = int(along.searchsorted(distance, side="right"))
    if k < len(along) and not along[k] > distance:
        beyond = np.flatnonzero(along > distance)
        k = int(beyond[0]) if beyond.size else len(along)
    return k


def closest_within(
    poses: NDArray[np.float64], along: NDArray[np.float64], x: float, y: float, search: float
) -> int:
    """`closest_index(poses, x, y, search)`, given `along = np.cumsum(segment_lengths(poses))`
    (the same running sums `integrated_index` adds chunk by chunk)."""
    n = len(poses)
    upper = n
    if math.isfinite(search):
        k = first_beyond(along, search)
        upper = k + 1 if k < len(along) else n
    upper = max(upper, 1)
    d2 = (poses[:upper, 0] - x) ** 2 + (poses[:upper, 1] - y) ** 2
    return int(d2.argmin())


def window_end(n: int, start: int, along: NDArray[np.float64], distance: float) -> int:
    """`integrated_index(poses, start, distance)` of n poses, given the running lengths
    from `start` (`np.cumsum(segment_lengths(poses)[start:])`)."""
    if start >= n:
        return n
    k = first_beyond(along, distance)
    return start + 1 + k if k < len(along) else n


def first_path_constraint(
    poses: NDArray[np.float64], enforce_inversion: bool, rotation_threshold: float
) -> int:
    """Index of the first pose after a cusp or an in-place rotation (len(poses) if none)."""
    n = len(poses)
    if n < 3:
        return n
    d = np.diff(poses[:, :2], axis=0)
    trans = fmath.hypot(d[:, 0], d[:, 1])
    inversion = n
    if enforce_inversion:
        moving = np.flatnonzero(trans > _EPS_TRANS)
        if moving.size > 1:
            dots = fmath.dot_rows(d[moving[1:]], d[moving[:-1]])
            cusp = np.flatnonzero(dots < 0.0)
            if cusp.size:
                inversion = int(moving[cusp[0] + 1]) + 1
    rotation = n
    if abs(rotation_threshold) > 1e-6:
        still = trans < _EPS_TRANS
        turn = np.abs(angle_diff(poses[1:, 2], poses[:-1, 2]))
        # Runs of consecutive in-place segments; the first whose accumulated turn crosses the threshold.
        run_id = np.cumsum(~still)  # constant within a run of still segments
        acc = np.where(still, turn, 0.0)
        cums = np.cumsum(acc)
        run_start_cum = np.zeros_like(cums)
        starts = np.flatnonzero(still & np.r_[True, ~still[:-1]])
        run_start_cum_vals = cums[starts] - acc[starts]
        run_start_cum[still] = run_start_cum_vals[np.searchsorted(run_id[starts], run_id[still])]
        over = np.flatnonzero(still & (cums - run_start_cum > rotation_threshold))
        if over.size:
            rotation = int(over[0]) + 1
    return min(rotation, inversion)


class PathHandler(Plugin):
    """Base of every `path_handler` plugin (nav2_core::PathHandler)."""

    class Params(ParamsModel):
        pass

    def __init__(self, name: str = "PathHandler", params: ParamsModel | None = None) -> None:
        super().__init__(name, params)

    def set_plan(self, path: Path) -> None:
        raise NotImplementedError

    def transform_global_plan(
        self, pose: Pose2D, costmap: Costmap2D, plan_to_costmap: Pose2D | None = None
    ) -> Path:
        raise NotImplementedError

    def transformed_goal(self, plan_to_costmap: Pose2D | None = None) -> Pose2D:
        raise NotImplementedError


@register("path_handler", "nav2_controller::FeasiblePathHandler")
class FeasiblePathHandler(PathHandler):
    class Params(ParamsModel):
        prune_distance: float = Field(2.0, ge=0.0)
        #: None: half the costmap's larger side, as Nav2 defaults it; negative: search the whole plan.
        max_robot_pose_search_dist: float | None = None
        enforce_path_inversion: bool = False
        enforce_path_rotation: bool = False
        inversion_xy_tolerance: float = Field(0.2, ge=0.0)
        inversion_yaw_tolerance: float = Field(0.4, ge=0.0)
        minimum_rotation_angle: float = Field(0.785, ge=0.0)
        reject_unit_path: bool = False

    params: Params

    def __init__(self, name: str = "PathHandler", params: ParamsModel | None = None) -> None:
        super().__init__(name, params)
        self.global_plan = Path(0.0, np.zeros((0, 3)))
        self.plan_up_to_constraint = self.global_plan.poses
        self.constraint_locale = 0
        #: segment_lengths(plan_up_to_constraint), and the array they belong to
        self._seg: NDArray[np.float64] | None = None
        self._seg_of: NDArray[np.float64] | None = None

    @property
    def _rotation_threshold(self) -> float:
        p = self.params
        return p.minimum_rotation_angle if p.enforce_path_rotation else 0.0

    @property
    def _constrained(self) -> bool:
        return self.params.enforce_path_inversion or self.params.enforce_path_rotation

    def _crop(self) -> None:
        poses = self.global_plan.poses
        self.plan_up_to_constraint = poses
        self.constraint_locale = 0
        if self._constrained:
            idx = first_path_constraint(
                poses, self.params.enforce_path_inversion, self._rotation_threshold
            )
            if idx < len(poses):
                self.plan_up_to_constraint = poses[:idx]
                self.constraint_locale = idx

    def set_plan(self, path: Path) -> None:
        self.global_plan = Path(
            path.stamp, np.asarray(path.poses, float).reshape(-1, 3), path.frame_id
        )
        self._crop()

    def _search_dist(self, costmap: Costmap2D) -> float:
        d = self.params.max_robot_pose_search_dist
        if d is None:
            return max(costmap.size_in_meters) / 2.0
        return math.inf if d < 0 else d

    def transform_global_plan(
        self, pose: Pose2D, costmap: Costmap2D, plan_to_costmap: Pose2D | None = None
    ) -> Path:
        """The local plan in the costmap's frame; `pose` is the robot in the plan's frame and
        `plan_to_costmap` the plan frame's pose in the costmap frame (identity if None)."""
        poses = self.plan_up_to_constraint
        if len(poses) == 0:
            raise InvalidPath("Received plan with zero length")
        if self.params.reject_unit_path and len(poses) == 1:
            raise InvalidPath("Received plan with length of one")
        seg = self._seg
        if self._seg_of is not poses or seg is None:
            seg = segment_lengths(poses)
        # closest_index and integrated_index on running sums of the cached lengths: one
        # cumsum from the start (and one from the closest pose when that is not the first)
        along = np.cumsum(seg)
        closest = closest_within(poses, along, pose.x, pose.y, self._search_dist(costmap))
        if len(poses) > 1 and closest == len(poses) - 1:
            closest -= 1
        if closest:
            along = np.cumsum(seg[closest:])
        end = window_end(len(poses), closest, along, self.params.prune_distance)
        local = poses[closest:end]
        if plan_to_costmap is not None:
            local = compose_arrays(plan_to_costmap.as_array(), local)
        # Cut where the plan leaves the costmap (costmap.world_to_map's cells, tested as
        # floats: the same verdicts)
        res = costmap.resolution
        ny, nx = costmap.costs.shape
        fx = np.floor((local[:, 0] - costmap.origin_x) / res)
        fy = np.floor((local[:, 1] - costmap.origin_y) / res)
        inside = (fx >= 0) & (fx < nx) & (fy >= 0) & (fy < ny)
        off = np.flatnonzero(~inside)
        if off.size:
            local = local[: off[0]]
        self.plan_up_to_constraint = poses[closest:]
        self._seg, self._seg_of = seg[closest:], self.plan_up_to_constraint
        if self._constrained and self.constraint_locale:
            last = self.plan_up_to_constraint[-1]
            near = (
                fmath.hypot(pose.x - last[0], pose.y - last[1])
                <= self.params.inversion_xy_tolerance
            )
            if near and abs(angle_diff(pose.yaw, last[2])) <= self.params.inversion_yaw_tolerance:
                g = self.global_plan
                self.global_plan = Path(g.stamp, g.poses[self.constraint_locale :], g.frame_id)
                self._crop()
        if len(local) == 0:
            raise InvalidPath("Resulting plan has 0 poses in it.")
        return Path(self.global_plan.stamp, local, costmap.frame_id)

    def transformed_goal(self, plan_to_costmap: Pose2D | None = None) -> Pose2D:
        if len(self.global_plan) == 0:
            raise InvalidPath("Received plan with zero length")
        goal = Pose2D.from_array(self.global_plan.poses[-1])
        return plan_to_costmap @ goal if plan_to_costmap is not None else goal
