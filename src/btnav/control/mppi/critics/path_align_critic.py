"""PathAlignCritic: keeps rollouts on the path, point by point at equal travelled distance."""

from __future__ import annotations

import numpy as np
from pydantic import Field

from ....core import fmath
from ....core.kernel_switch import Method
from ....plugins import register
from ..angles import abs_angle_diff
from ..critic_data import DEFAULT_METHOD, CriticData
from ..critic_function import NAMESPACE, CriticFunction
from ..path_align_kernel import arc_length_table, path_align_costs

#: Arc-length lookup resolution: the path's length in this many bins.
LOOKUP_BINS = 2048


def nearest_by_arc_length(path_s: np.ndarray, s: np.ndarray) -> np.ndarray:
    """Index of the path point whose travelled distance is nearest each value of `s`.

    A binary search per rollout point (`np.searchsorted` on ~26k keys) costs ~1 ms;
    instead a table over `LOOKUP_BINS` uniform bins of the path's length is built
    with one sorted search and read by integer division (nearest to within
    length / 4096, about half a millimetre on a 2 m path).
    """
    table, inv_ds = arc_length_table(path_s, LOOKUP_BINS)
    if inv_ds == 0.0:  # a path of no length
        return np.zeros(s.shape, np.intp)
    bins = np.minimum((s * inv_ds + np.float32(0.5)).astype(np.int32), LOOKUP_BINS)
    return table[bins]


@register("critic", NAMESPACE + "PathAlignCritic")
class PathAlignCritic(CriticFunction):
    """Mean distance from every `trajectory_point_step`-th rollout point to the path point
    at the same distance travelled (arc length along the rollout vs along the path).

    Applied only while tracking the path: while the pruned path is at least
    `threshold_to_consider` long, once the batch reaches `offset_from_furthest` points
    along the path, and while at most `max_path_occupancy_ratio` of the path up to the
    furthest reached point is blocked (so the robot may leave the path around a new
    obstacle). Only that reached part of the path is aligned with: a rollout that
    travels further is compared with its last point. Path points in collision are
    skipped. `use_path_orientations` adds the heading error to the path's yaw, as a
    third coordinate of the distance.
    """

    class Params(CriticFunction.Params):
        cost_weight: float = Field(10.0, ge=0.0)
        threshold_to_consider: float = Field(0.5, ge=0.0)
        offset_from_furthest: int = Field(20, ge=0)
        max_path_occupancy_ratio: float = Field(0.07, ge=0.0, le=1.0)
        trajectory_point_step: int = Field(4, ge=1)
        use_path_orientations: bool = False

    #: "kernel" (path_align_kernel.py) or "numpy" (the reference), the optimizer's
    #: DEFAULT_METHOD (BTNAV_MPPI=numpy); the same bits either way.
    method: Method = DEFAULT_METHOD

    def score(self, data: CriticData) -> None:
        p = self.params
        n = len(data.path)
        if not self.enabled or n < 2 or data.local_path_length() < p.threshold_to_consider:
            return
        # Align only with the path the batch reaches: points before the furthest one.
        furthest = data.furthest_reached_path_point()
        if furthest < max(p.offset_from_furthest, 1):
            return
        valid = data.path_points_valid()[:furthest]
        blocked = int((~valid).sum())
        if blocked > 2 and blocked / furthest > p.max_path_occupancy_ratio:
            return
        path = data.path[:furthest]
        seg = fmath.hypot(np.diff(path[:, 0]), np.diff(path[:, 1]))
        path_s = np.concatenate([[0.0], np.cumsum(seg)]).astype(np.float32)
        step = p.trajectory_point_step
        if self.method == "kernel":
            table, inv_ds = arc_length_table(path_s, LOOKUP_BINS)
            cost = np.empty(len(data.costs), np.float32)
            path_align_costs(
                data.x.T, data.y.T, data.yaws.T, step, np.ascontiguousarray(path), valid,
                table, inv_ds, p.use_path_orientations, cost,
            )  # fmt: skip
            self.add(data, cost)
            return
        # Work time-major, (K, B): each sampled time step is one contiguous row.
        xs = np.ascontiguousarray(data.x.T[::step])
        ys = np.ascontiguousarray(data.y.T[::step])
        seg_t = fmath.hypot(xs[1:] - xs[:-1], ys[1:] - ys[:-1])
        for k in range(1, len(seg_t)):
            seg_t[k] += seg_t[k - 1]
        traj_s = seg_t  # travelled distance at sampled points 1..K-1
        xs, ys = xs[1:], ys[1:]
        idx = nearest_by_arc_length(path_s, traj_s)
        px, py = np.ascontiguousarray(path[:, 0]), np.ascontiguousarray(path[:, 1])
        dx, dy = xs - px[idx], ys - py[idx]
        if p.use_path_orientations:
            yaws = data.yaws.T[::step][1:]
            dyaw = abs_angle_diff(yaws, np.ascontiguousarray(path[:, 2])[idx])
            d = np.sqrt(dx * dx + dy * dy + dyaw * dyaw)
        else:
            d = fmath.hypot(dx, dy)
        if len(d) and valid.all():  # every point counts: the same sums without the masks
            count = np.full(d.shape[1], len(d), np.intp)
            total = d.sum(axis=0)
        else:
            ok = valid[idx]
            count = ok.sum(axis=0)
            total = np.where(ok, d, np.float32(0.0)).sum(axis=0)
        cost = np.where(count > 0, total / np.maximum(count, 1), np.float32(0.0))
        self.add(data, cost.astype(np.float32))
