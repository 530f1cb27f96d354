"""What every critic sees in one optimisation iteration (mppi::CriticData), plus shared lookups.

Batch arrays are `(batch_size, time_steps)` float32 views. Lazily computed and
shared between critics (as Nav2 caches them in CriticData and State): the length
of the pruned path, the path point the batch reaches furthest, and which path
points are in collision.

"Near the goal" is judged by the length of the pruned path still ahead
(`local_path_length`, Nav2's `state.local_path_length`), never by the straight-line
distance: around a bend or an obstacle the goal can be close in a straight line
while the path to it is still long, and the path critics must keep the robot on
the path until the path itself is short.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from ...core import fmath
from ...core.errors import ParamsError
from ...core.kernel_switch import Method, default_method
from ...costmap.cost_values import INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE, NO_INFORMATION
from ...costmap.costmap_2d import Costmap2D
from ...costmap.footprint_cost import footprint_costs
from .furthest_point_kernel import furthest_reached

F32 = NDArray[np.float32]

#: How MPPI's hot loops run: "kernel" (numba) unless the environment says
#: BTNAV_MPPI=numpy (the reference, the same bits); the optimizer and critics read it.
DEFAULT_METHOD: Method = default_method("BTNAV_MPPI")


@dataclass
class CriticData:
    # State: velocities the rollouts actually follow (vx[:, 0] is the robot's current speed)
    # and the sampled controls after constraints (cvx).
    vx: F32
    vy: F32
    wz: F32
    cvx: F32
    cvy: F32
    cwz: F32
    # Rollouts in the costmap's frame.
    x: F32
    y: F32
    yaws: F32
    #: (P, 3) pruned path (x, y, yaw) in the costmap's frame, from the point nearest the robot.
    path: NDArray[np.float32]
    #: The global goal (x, y, yaw): the last pose of the whole plan (or its next cusp).
    goal: NDArray[np.float64]
    robot: NDArray[np.float64]  # x, y, yaw
    robot_speed: tuple[float, float, float]  # vx, vy, wz
    costmap: Costmap2D
    model_dt: float
    costs: F32
    is_holonomic: bool = False
    goal_checker: Any = None
    vx_max: float = 0.5
    vx_min: float = -0.35
    vy_max: float = 0.5
    wz_max: float = 1.9
    min_turning_r: float | None = None
    fail_flag: bool = False
    #: DEFAULT_METHOD (BTNAV_MPPI=numpy): how `furthest_reached_path_point` runs; the
    #: same integer either way.
    method: ClassVar[Method] = DEFAULT_METHOD
    _furthest: int | None = field(default=None, repr=False)
    _valid: NDArray[np.bool_] | None = field(default=None, repr=False)
    _path_length: float | None = field(default=None, repr=False)

    @property
    def batch_size(self) -> int:
        return int(self.x.shape[0])

    @property
    def time_steps(self) -> int:
        return int(self.x.shape[1])

    def local_path_length(self) -> float:
        """Length of the pruned path (what `threshold_to_consider` and `near_goal_distance`
        are compared with, as Nav2's critics compare `state.local_path_length`).

        Summed in float64 from the float32 points: along a straight path the partial
        sums telescope exactly, so a 1.5 m path measures 1.5, not 1.5000001."""
        if self._path_length is None:
            p = self.path[:, :2].astype(np.float64)
            d = p[1:] - p[:-1]
            self._path_length = float(fmath.hypot(d[:, 0], d[:, 1]).sum()) if len(d) else 0.0
        return self._path_length

    def path_end(self) -> NDArray[np.float32]:
        """The pruned path's last pose (x, y, yaw): what GoalCritic and GoalAngleCritic
        approach (Nav2's `utils::getLastPathPose`); the goal once the path reaches it."""
        return self.path[-1] if len(self.path) else self.goal.astype(np.float32)

    def furthest_reached_path_point(self) -> int:
        """The furthest path index any rollout reaches (Nav2's findPathFurthestReachedPoint).

        Per rollout: the path point nearest its end, among the points no further along
        the path than the rollout's own length (so a rollout cannot "reach" the far leg
        of a bend or a U-turn by cutting across); the largest over the batch."""
        if self._furthest is None:
            px, py = self.path[:, 0], self.path[:, 1]
            n = len(px)
            if n == 0:
                self._furthest = 0
                return 0
            if self.method == "kernel" and self._kernel_ready():
                self._furthest = int(furthest_reached(self.x, self.y, px, py))
                return self._furthest
            seg = fmath.hypot(px[1:] - px[:-1], py[1:] - py[:-1])
            path_s = np.concatenate([[np.float32(0.0)], np.cumsum(seg, dtype=np.float32)])
            dx, dy = self.x[:, 1:] - self.x[:, :-1], self.y[:, 1:] - self.y[:, :-1]
            travelled = fmath.hypot(dx, dy).sum(axis=1, dtype=np.float32)
            # lower_bound: the first path point at least as far along as the rollout went
            reach = np.minimum(np.searchsorted(path_s, travelled, side="left"), n - 1)
            ex, ey = self.x[:, -1], self.y[:, -1]
            # (B, P) squared distances from each rollout's end to each path point.
            d = (ex[:, None] - px[None, :]) ** 2 + (ey[:, None] - py[None, :]) ** 2
            d[np.arange(n)[None, :] > reach[:, None]] = np.inf
            self._furthest = int(np.argmin(d, axis=1).max())
        return self._furthest

    def _kernel_ready(self) -> bool:
        """The compiled search takes float32 rollouts and paths and at least one rollout
        (numpy's max over an empty batch raises; other dtypes keep numpy's promotions)."""
        f32 = np.dtype(np.float32)
        return (
            self.x.dtype == f32
            and self.y.dtype == f32
            and self.path.dtype == f32
            and self.x.ndim == 2
            and self.x.shape == self.y.shape
            and self.x.shape[0] > 0
        )

    def path_points_valid(self) -> NDArray[np.bool_]:
        """Per path point: not in collision on the costmap (the last point is always valid)."""
        if self._valid is None:
            costs = cell_costs(self.costmap, self.path[:, 0], self.path[:, 1])
            valid = ~in_collision(
                costs, consider_footprint=False, tracking_unknown=tracking_unknown(self.costmap)
            )
            if len(valid):
                valid[-1] = True
            self._valid = valid
        return self._valid


def tracking_unknown(costmap: Costmap2D) -> bool:
    """Whether NO_INFORMATION cells are traversable (Nav2: the layered costmap tracks unknown space)."""
    flag = getattr(costmap, "track_unknown_space", None)
    if flag is not None:
        return bool(flag)
    return int(costmap.default_value) == NO_INFORMATION


#: Maps up to this many cells are copied with one NO_INFORMATION cell appended, which
#: points off the map then read (cheaper than masking them after the gather).
_SENTINEL_CELLS = 1 << 18


def cell_costs(costmap: Costmap2D, x: NDArray[Any], y: NDArray[Any]) -> NDArray[np.uint8]:
    """Costs of the cells under world points of any shape, by one fancy-indexing gather.

    Points off the map read NO_INFORMATION.
    """
    res = np.float32(1.0 / costmap.resolution)
    mx = np.floor((x - np.float32(costmap.origin_x)) * res).astype(np.int32)
    my = np.floor((y - np.float32(costmap.origin_y)) * res).astype(np.int32)
    w, h = costmap.size_x, costmap.size_y
    # 0 <= m < size as one unsigned comparison (a negative int32 is >= 2**31 as uint32)
    inside = mx.view(np.uint32) < np.uint32(w)
    inside &= my.view(np.uint32) < np.uint32(h)
    flat = costmap.costs.reshape(-1)
    n = w * h
    if n <= _SENTINEL_CELLS:
        # points off the map index one extra cell holding NO_INFORMATION
        ext = np.empty(n + 1, flat.dtype)
        ext[:n] = flat[:n]
        ext[n] = NO_INFORMATION
        my *= w
        my += mx
        return ext[np.where(inside, my, n)]
    idx = np.where(inside, my * w + mx, 0)
    out = flat[idx]
    out[~inside] = NO_INFORMATION
    return out


def in_collision(
    costs: NDArray[np.uint8], *, consider_footprint: bool, tracking_unknown: bool
) -> NDArray[np.bool_]:
    """Nav2's collision rule on the costs it checks: lethal; inscribed unless those costs
    are the footprint's (`consider_footprint`: a footprint merely over inscribed cells
    touches nothing); unknown unless tracked."""
    hit = costs == LETHAL_OBSTACLE
    if not consider_footprint:
        hit |= costs == INSCRIBED_INFLATED_OBSTACLE
    if not tracking_unknown:
        hit |= costs == NO_INFORMATION
    return hit


def collision_check(
    costmap_ros: Any,
    costmap: Costmap2D,
    centre: NDArray[np.uint8],
    x: NDArray[Any],
    y: NDArray[Any],
    yaw: NDArray[Any],
    *,
    consider_footprint: bool,
    inflation_layer_name: str = "",
    skip_free: bool = False,
) -> tuple[NDArray[np.uint8], NDArray[np.bool_], NDArray[np.bool_]]:
    """Nav2's critics' collision check at every point: the costs checked, where they are
    the footprint's, and which points collide.

    With `consider_footprint` (and a costmap server to give the footprint) a point whose
    centre cost reaches the circumscribed cost (every point without an inflation layer;
    with `skip_free`, never a free one) is judged by its footprint's cost; otherwise the
    centre's cost is checked, as for a circular robot."""
    use = np.zeros(centre.shape, bool)
    checked = centre
    footprint = consider_footprint and costmap_ros is not None
    if footprint:
        possible = costmap_ros.circumscribed_cost(inflation_layer_name)
        use = centre >= possible if possible >= 1.0 else np.ones(centre.shape, bool)
        if skip_free:
            use &= centre > 0
        checked = centre.copy()
        if use.any():
            checked[use] = footprint_costs(costmap, costmap_ros.footprint, x[use], y[use], yaw[use])
    hit = in_collision(
        checked, consider_footprint=footprint, tracking_unknown=tracking_unknown(costmap)
    )
    return checked, use, hit


def check_footprint_setting(costmap_ros: Any, critic: str, consider_footprint: bool) -> None:
    """Nav2 refuses `consider_footprint` on a robot the costmap knows only by its radius."""
    if consider_footprint and costmap_ros is not None and costmap_ros.use_radius:
        raise ParamsError(
            f"true, but {costmap_ros.name} has no footprint (it uses robot_radius): give "
            "the costmap a `footprint` polygon, or set consider_footprint: false (Nav2 "
            "refuses this too)",
            key=f"{critic}.consider_footprint",
        )
