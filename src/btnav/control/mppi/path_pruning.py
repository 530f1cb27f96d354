"""The part of the plan MPPI looks at (mppi::PathHandler): from the robot, `prune_distance` ahead.

The plan is given in the costmap's frame (the controller server transforms it).
Each cycle the point nearest the robot is searched forward from the last one,
within `max_robot_pose_search_dist` of path length, so a path that loops back
near itself is not cut short; passed points are dropped. With
`enforce_path_inversion`, the plan ends at its first cusp (a reversal of
direction) until the robot is within the inversion tolerances of it.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from ...core import fmath


def first_inversion(poses: NDArray[np.float64]) -> int | None:
    """Index of the first cusp (the direction of travel reverses there), or None."""
    if len(poses) < 3:
        return None
    d = np.diff(poses[:, :2], axis=0)
    dot = (d[:-1] * d[1:]).sum(axis=1)
    cusps = np.nonzero(dot < 0)[0]
    return int(cusps[0]) + 1 if len(cusps) else None


class PathPruner:
    def __init__(
        self,
        prune_distance: float,
        max_search_dist: float | None,
        enforce_inversion: bool = False,
        inversion_xy_tolerance: float = 0.2,
        inversion_yaw_tolerance: float = 0.4,
    ) -> None:
        self.prune_distance = prune_distance
        self.max_search_dist = max_search_dist
        self.enforce_inversion = enforce_inversion
        self.xy_tol = inversion_xy_tolerance
        self.yaw_tol = inversion_yaw_tolerance
        self.plan = np.zeros((0, 3))
        self.start = 0
        self.inversion: int | None = None

    def set_plan(self, poses: NDArray[np.float64]) -> None:
        self.plan = np.asarray(poses, dtype=np.float64)
        self.start = 0
        self.inversion = first_inversion(self.plan) if self.enforce_inversion else None

    def local_path(self, robot: NDArray[np.float64], default_search: float) -> NDArray[np.float32]:
        """(P, 3) float32: the plan from its point nearest the robot, up to `prune_distance` on."""
        plan = self.plan
        end = len(plan) if self.inversion is None else self.inversion + 1
        if self.inversion is not None:
            cusp = plan[self.inversion]
            dyaw = abs((robot[2] - cusp[2] + math.pi) % (2 * math.pi) - math.pi)
            if (
                fmath.hypot(robot[0] - cusp[0], robot[1] - cusp[1]) < self.xy_tol
                and dyaw < self.yaw_tol
            ):
                # Reached the cusp: continue on the rest of the plan.
                self.plan = plan = plan[self.inversion :]
                self.start = 0
                self.inversion = first_inversion(plan)
                end = len(plan) if self.inversion is None else self.inversion + 1
        seg = fmath.hypot(*np.diff(plan[:, :2], axis=0).T)
        s = np.concatenate([[0.0], np.cumsum(seg)])
        search = self.max_search_dist or default_search
        stop = int(np.searchsorted(s, s[self.start] + search, side="right"))
        stop = max(min(stop, end), self.start + 1)
        window = plan[self.start : stop, :2]
        nearest = self.start + int(np.argmin(fmath.hypot(*(window - robot[:2]).T)))
        self.start = nearest
        last = int(np.searchsorted(s, s[nearest] + self.prune_distance, side="right"))
        last = max(min(last, end), nearest + 1)
        return plan[nearest:last].astype(np.float32)

    def goal(self) -> NDArray[np.float64]:
        """The goal the critics approach: the plan's end, or its next cusp."""
        if self.inversion is not None:
            return self.plan[self.inversion]
        return self.plan[-1]
