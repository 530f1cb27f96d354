"""nav2_smoother::SimpleSmoother: gradient-descent smoothing between data and neighbours.

Each iteration moves every interior point `y_i` by
`w_data * (x_i - y_i) + w_smooth * (y_{i+1} + y_{i-1} - 2 y_i)` (x: the input path),
until the summed change falls below `tolerance`. Nav2 updates points one after
the other (Gauss-Seidel); here all points move at once (Jacobi), which converges to
the same fixed point. If an iteration puts a point on a cell with cost above 252
(inscribed or lethal; unknown is allowed, as in Nav2) or off the map, the path of
the previous iteration is returned. With `do_refinement` the result is smoothed
again `refinement_num` times, each time taking the smoothed path as the data.
With `enforce_path_inversion` the path is cut at cusps (direction reversals) and
each directional segment is smoothed on its own; segments of fewer than 5 points
are left as they are. Orientations are then set along the path.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray
from pydantic import Field

from ..core import fmath
from ..core.geometry import normalize_angle
from ..core.messages import Path
from ..costmap.cost_values import MAX_NON_OBSTACLE, NO_INFORMATION
from ..costmap.costmap_2d import Costmap2D
from ..params.schema import ignored
from ..plugins import register
from .exceptions import InvalidPath, SmootherTimedOut
from .smoother import Smoothed, Smoother


@register("smoother", "nav2_smoother::SimpleSmoother", aliases=("btnav/SimpleSmoother",))
class SimpleSmoother(Smoother):
    class Params(Smoother.Params):
        tolerance: float = Field(1e-10, ge=0.0)
        max_its: int = Field(1000, ge=1)
        w_data: float = Field(0.2, ge=0.0)
        w_smooth: float = Field(0.3, ge=0.0)
        do_refinement: bool = True
        refinement_num: int = Field(2, ge=0)
        enforce_path_inversion: bool = True
        is_holonomic: bool = True
        minimum_turning_radius: float = ignored(
            0.4, "Dubins boundary conditions for non-holonomic robots are not implemented"
        )

    params: Params

    def __init__(self, name: str, params: Params | None = None) -> None:
        super().__init__(name, params)

    def smooth(
        self,
        path: Path,
        costmap: Costmap2D | None = None,
        cancel_checker: Callable[[], bool] | None = None,
    ) -> Smoothed:
        poses = np.array(path.poses, dtype=float, copy=True)
        if poses.ndim != 2 or poses.shape[1] != 3 or not np.all(np.isfinite(poses)):
            raise InvalidPath("a path is an (N, 3) array of finite x, y, yaw")
        out = Path(path.stamp, poses, path.frame_id)
        if len(poses) < 2:
            return Smoothed(out, True)
        segments = (
            directional_segments(poses[:, :2])
            if self.params.enforce_path_inversion
            else [(0, len(poses) - 1)]
        )
        success = True
        for a, b in segments:
            if b - a <= 3:
                continue
            seg = poses[a : b + 1]
            xy, ok = self._smooth_segment(seg[:, :2], costmap, cancel_checker)
            success = success and ok
            seg[:, :2] = xy
            seg[:, 2] = approximate_orientations(seg, self.params.is_holonomic)
        return Smoothed(out, success)

    def _smooth_segment(
        self,
        data: NDArray[np.float64],
        costmap: Costmap2D | None,
        cancel_checker: Callable[[], bool] | None,
    ) -> tuple[NDArray[np.float64], bool]:
        p = self.params
        rounds = 1 + (p.refinement_num if p.do_refinement else 0)
        for _ in range(rounds):
            data, converged = self._descend(data, costmap, cancel_checker)
            if not converged:
                return data, False
        return data, True

    def _descend(
        self,
        x: NDArray[np.float64],
        costmap: Costmap2D | None,
        cancel_checker: Callable[[], bool] | None,
    ) -> tuple[NDArray[np.float64], bool]:
        p = self.params
        y = x.copy()
        its = 0
        change = p.tolerance
        while change >= p.tolerance:
            its += 1
            if its >= p.max_its:
                return y, False
            if cancel_checker is not None and cancel_checker():
                raise SmootherTimedOut("Smoothing time exceeded allowed duration")
            step = p.w_data * (x[1:-1] - y[1:-1]) + p.w_smooth * (y[2:] + y[:-2] - 2.0 * y[1:-1])
            new = y.copy()
            new[1:-1] += step
            change = float(np.abs(step).sum())
            if costmap is not None and in_collision(new[1:-1], costmap):
                return y, False  # the last path before the infeasibility
            y = new
        return y, True


def in_collision(xy: NDArray[np.float64], costmap: Costmap2D) -> bool:
    """Whether any point is off the map or on a cell above MAX_NON_OBSTACLE (unknown is allowed)."""
    m, inside = costmap.world_to_map(xy)
    if not inside.all():
        return True
    cost = costmap.costs[m[:, 1], m[:, 0]]
    return bool(np.any((cost > MAX_NON_OBSTACLE) & (cost != NO_INFORMATION)))


def directional_segments(xy: NDArray[np.float64]) -> list[tuple[int, int]]:
    """Index ranges [start, end] between cusps, where the path reverses its direction."""
    d = np.diff(xy, axis=0)
    dots = np.sum(d[:-1] * d[1:], axis=1)
    cusps = (np.nonzero(dots < 0)[0] + 1).tolist()
    bounds = [0, *cusps, len(xy) - 1]
    return list(itertools.pairwise(bounds))


def approximate_orientations(poses: NDArray[np.float64], is_holonomic: bool) -> NDArray[np.float64]:
    """Yaw along the path (each pose facing the next); a reversing segment faces backwards.

    The last pose keeps its yaw, and a pose on top of the next keeps its own.
    """
    yaw = poses[:, 2].copy()
    d = np.diff(poses[:, :2], axis=0)
    theta = fmath.arctan2(d[:, 1], d[:, 0])  # fmath, not numpy: the same bits on every CPU
    reversing = False
    if not is_holonomic and len(poses) > 2:
        diff = normalize_angle(float(theta[1] - poses[1, 2]))
        reversing = abs(diff) > np.pi / 2
    if reversing:
        theta = theta + np.pi
    moving = ~((np.abs(d[:, 0]) < 1e-4) & (np.abs(d[:, 1]) < 1e-4))
    yaw[:-1] = np.where(moving, normalize_angle(theta), yaw[:-1])
    return yaw
