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

The helpers `integrated_index` and `closest_index` (on `core.path_utils`, the one window
search) serve the controllers (DWB, RPP) that prune a plan themselves and the tree's
nodes that measure along a path.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray
from pydantic import Field

from ..core import fmath
from ..core.geometry import Pose2D, angle_diff, compose_arrays
from ..core.messages import Path
from ..core.path_utils import (
    closest_pose,
    first_after_integrated_distance,
    segment_lengths,
)
from ..costmap.costmap_2d import Costmap2D
from ..params.schema import ParamsModel
from ..plugins import Plugin, register
from .exceptions import InvalidPath

_EPS_TRANS = 1e-4

__all__ = [
    "FeasiblePathHandler",
    "PathHandler",
    "closest_index",
    "first_path_constraint",
    "integrated_index",
    "segment_lengths",
]


def integrated_index(
    poses: NDArray[np.float64],
    start: int,
    distance: float,
    seg: NDArray[np.float64] | None = None,
) -> int:
    """Index of the first pose after `start` whose path distance from `start` exceeds `distance`
    (len(poses) when none): the exclusive end of the window of that length.

    `seg`, when given, is `segment_lengths(poses)` (worked out once for a plan that is
    pruned from the front cycle after cycle: the lengths do not change)."""
    if start >= len(poses):
        return len(poses)
    return first_after_integrated_distance(
        segment_lengths(poses) if seg is None else seg, start, distance
    )


def closest_index(
    poses: NDArray[np.float64],
    x: float,
    y: float,
    search_dist: float = math.inf,
    seg: NDArray[np.float64] | None = None,
) -> int:
    """The closest pose to (x, y) among the first `search_dist` metres of the path (`seg`:
    see `integrated_index`)."""
    finite = math.isfinite(search_dist)
    upper = integrated_index(poses, 0, search_dist, seg) if finite else len(poses)
    return closest_pose(poses, x, y, 0, max(upper, 1))


def first_path_constraint(
    poses: NDArray[np.float64], enforce_inversion: bool, rotation_threshold: float
) -> int:
    """Index of the first pose after a cusp or an in-place rotation (len(poses) if none)."""
    n = len(poses)
    if n < 3:
        return n
    d = np.diff(poses[:, :2], axis=0)
    trans = segment_lengths(poses)
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
        closest = closest_index(poses, pose.x, pose.y, self._search_dist(costmap), seg)
        if len(poses) > 1 and closest == len(poses) - 1:
            closest -= 1  # (Nav2 keeps two poses: the end of the path has a direction)
        end = integrated_index(poses, closest, self.params.prune_distance, seg)
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
