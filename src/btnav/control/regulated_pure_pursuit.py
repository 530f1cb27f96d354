"""nav2_regulated_pure_pursuit_controller::RegulatedPurePursuitController.

Pure pursuit drives on the circle through the robot and a carrot point
`lookahead_dist` ahead on the path (or `lookahead_time` x speed, clamped to
[min, max]_lookahead_dist, with `use_velocity_scaled_lookahead_dist`). The
regulations slow the robot down on tight curves (radius below
`regulated_linear_scaling_min_radius`), near obstacles (distance to the
obstacle estimated from the inflated cost at the robot, below
`cost_scaling_dist`) and when approaching the end of the path (within
`approach_velocity_scaling_dist`), never below `regulated_linear_scaling_min_speed`
(except for approach scaling, never below `min_approach_linear_velocity`). It
rotates in place towards the path when the carrot is more than
`rotate_to_heading_min_angle` off the heading, and towards the goal heading once
the goal checker says the position is reached. The arc ahead is checked for
collision up to the carrot (at most `max_allowed_time_to_collision_up_to_carrot`
seconds); a collision raises NoValidControl, as Nav2 does.

The plan given to `set_plan` must be in the frame of the pose passed to
`compute_velocity_commands` (the local costmap's frame); the controller prunes
it itself each cycle (poses passed are dropped).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray
from pydantic import Field, model_validator

from ..core import fmath
from ..core.geometry import Pose2D, angle_diff, angles_in_range, normalize_angle
from ..core.messages import Path, Twist
from ..costmap.cost_values import FREE_SPACE, INSCRIBED_INFLATED_OBSTACLE, NO_INFORMATION
from ..costmap.costmap_2d import Costmap2D
from ..params.schema import Why, ignored
from ..plugins import register
from .controller import Controller
from .exceptions import InvalidPath, NoValidControl
from .goal_checkers import path_length
from .path_handler import closest_index, integrated_index, segment_lengths

_DW = "used only by use_dynamic_window, which btnav's RPP does not implement yet"


def lookahead_point(local: NDArray[np.float64], dist: float) -> NDArray[np.float64]:
    """The point at `dist` from the robot (origin) on the robot-frame path, interpolated on the
    segment that crosses the circle; the last pose when the path ends inside the circle."""
    r = fmath.hypot(local[:, 0], local[:, 1])
    beyond = np.flatnonzero(r >= dist)
    if beyond.size == 0:
        return local[-1, :2].copy()
    i = int(beyond[0])
    if i == 0:
        return local[0, :2].copy()
    # Scalar arithmetic on the crossing segment (the same operations as on 2-vectors).
    px, py = local[i - 1, :2].tolist()
    qx, qy = local[i, :2].tolist()
    dx, dy = qx - px, qy - py
    # |p + t d| = dist, t in [0, 1]
    a, b, c = dx * dx + dy * dy, 2 * (px * dx + py * dy), px * px + py * py - dist * dist
    if a < 1e-12:
        return np.array([qx, qy])
    t = (-b + math.sqrt(max(b * b - 4 * a * c, 0.0))) / (2 * a)
    t = min(max(t, 0.0), 1.0)
    return np.array([px + t * dx, py + t * dy])


def curvature_to(x: float, y: float) -> float:
    """Curvature of the circle through the origin, tangent to +x, through (x, y)."""
    d2 = x * x + y * y
    return 2.0 * y / d2 if d2 > 1e-3 else 0.0


#: Nav2's documented FollowPath section for this controller (docs.nav2.org), for a
#: params file that swaps it in (the tests and bench/closed_loop.py do).
NAV2_DOCS_SECTION: dict[str, object] = {
    "plugin": "nav2_regulated_pure_pursuit_controller::RegulatedPurePursuitController",
    "desired_linear_vel": 0.5,
    "lookahead_dist": 0.6,
    "min_lookahead_dist": 0.3,
    "max_lookahead_dist": 0.9,
    "lookahead_time": 1.5,
    "rotate_to_heading_angular_vel": 1.8,
    "transform_tolerance": 0.1,
    "use_velocity_scaled_lookahead_dist": False,
    "min_approach_linear_velocity": 0.05,
    "approach_velocity_scaling_dist": 0.6,
    "use_collision_detection": True,
    "max_allowed_time_to_collision_up_to_carrot": 1.0,
    "use_regulated_linear_velocity_scaling": True,
    "use_fixed_curvature_lookahead": False,
    "curvature_lookahead_dist": 0.25,
    "use_cost_regulated_linear_velocity_scaling": False,
    "regulated_linear_scaling_min_radius": 0.9,
    "regulated_linear_scaling_min_speed": 0.25,
    "use_rotate_to_heading": True,
    "allow_reversing": False,
    "rotate_to_heading_min_angle": 0.785,
    "max_angular_accel": 3.2,
    "max_robot_pose_search_dist": 10.0,
}


@register(
    "controller",
    "nav2_regulated_pure_pursuit_controller::RegulatedPurePursuitController",
)
class RegulatedPurePursuitController(Controller):
    class Params(Controller.Params):
        max_linear_vel: float = Field(0.5, gt=0.0)
        #: Nav2's older name of max_linear_vel (still accepted by Nav2, with a deprecation warning).
        desired_linear_vel: float | None = Field(None, gt=0.0)
        min_linear_vel: float = -0.5
        max_angular_vel: float = 2.5
        min_angular_vel: float = -2.5
        lookahead_dist: float = Field(0.6, gt=0.0)
        min_lookahead_dist: float = Field(0.3, gt=0.0)
        max_lookahead_dist: float = Field(0.9, gt=0.0)
        lookahead_time: float = Field(1.5, gt=0.0)
        rotate_to_heading_angular_vel: float = Field(1.8, gt=0.0)
        use_velocity_scaled_lookahead_dist: bool = False
        min_approach_linear_velocity: float = Field(0.05, ge=0.0)
        approach_velocity_scaling_dist: float = Field(0.6, ge=0.0)
        use_collision_detection: bool = True
        max_allowed_time_to_collision_up_to_carrot: float = Field(1.0, ge=0.0)
        min_distance_to_obstacle: float = -1.0
        use_regulated_linear_velocity_scaling: bool = True
        use_cost_regulated_linear_velocity_scaling: bool = True
        cost_scaling_dist: float = Field(0.6, gt=0.0)
        cost_scaling_gain: float = Field(1.0, ge=0.0)
        inflation_cost_scaling_factor: float = Field(3.0, gt=0.0)
        regulated_linear_scaling_min_radius: float = Field(0.9, gt=0.0)
        regulated_linear_scaling_min_speed: float = Field(0.25, ge=0.0)
        use_fixed_curvature_lookahead: bool = False
        curvature_lookahead_dist: float = Field(0.6, gt=0.0)
        use_rotate_to_heading: bool = True
        rotate_to_heading_min_angle: float = Field(0.785, ge=0.0)
        max_angular_accel: float = Field(3.2, gt=0.0)
        allow_reversing: bool = False
        max_robot_pose_search_dist: float | None = None
        interpolate_curvature_after_goal: bool = False
        use_cancel_deceleration: bool = False
        cancel_deceleration: float = Field(3.2, gt=0.0)
        use_dynamic_window: bool = ignored(
            False, "the dynamic-window variant of RPP is not implemented yet"
        )
        max_linear_accel: float = ignored(2.5, _DW)
        max_linear_decel: float = ignored(-2.5, _DW)
        max_angular_decel: float = ignored(-3.2, _DW)
        allow_obstacle_checking_beyond_goal: bool = False
        transform_tolerance: float = ignored(0.1, Why.TF)
        use_interpolation: bool = ignored(True, "btnav always interpolates the carrot on the path")

        @model_validator(mode="after")
        def _older_name(self) -> RegulatedPurePursuitController.Params:
            if self.desired_linear_vel is not None:
                object.__setattr__(self, "max_linear_vel", self.desired_linear_vel)
            if self.use_rotate_to_heading and self.allow_reversing:
                raise ValueError(
                    "use_rotate_to_heading and allow_reversing cannot both be true (Nav2 refuses it)"
                )
            return self

    params: Params

    def __init__(self, name: str = "FollowPath", params: Params | None = None) -> None:
        super().__init__(name, params)
        #: The control period (1 / controller_frequency); the controller server sets it.
        self.control_duration = 0.05
        self.max_linear_vel = self.params.max_linear_vel
        self._plan = np.zeros((0, 3))
        #: segment_lengths(self._plan), and the array they belong to
        self._seg: NDArray[np.float64] | None = None
        self._seg_of: NDArray[np.float64] | None = None
        self.carrot = np.zeros(2)
        self.is_rotating_to_heading = False

    # --- nav2_core::Controller -------------------------------------------------------------
    def set_plan(self, path: Path) -> None:
        poses = np.asarray(path.poses, float).reshape(-1, 3)
        if len(poses) == 0:
            raise InvalidPath("Received plan with zero length")
        self._plan = poses

    def set_speed_limit(self, speed_limit: float, percentage: bool) -> None:
        base = self.params.max_linear_vel
        if speed_limit <= 0.0:
            self.max_linear_vel = base
        else:
            self.max_linear_vel = base * speed_limit / 100.0 if percentage else speed_limit

    def reset(self) -> None:
        self.is_rotating_to_heading = False

    def local_plan(self, pose: Pose2D) -> np.ndarray | None:
        """The pruned plan up to the lookahead point (the carrot, Nav2's
        `lookahead_point`), in the costmap frame."""
        plan = self._plan
        if not len(plan):
            return None
        carrot = pose.transform_points(np.asarray(self.carrot, dtype=float).reshape(1, 2))[0]
        nearest = int(np.argmin((plan[:, 0] - carrot[0]) ** 2 + (plan[:, 1] - carrot[1]) ** 2))
        end = np.array([[carrot[0], carrot[1], plan[nearest, 2]]])
        return np.vstack([plan[: nearest + 1], end])

    def _local_plan(self, pose: Pose2D, costmap: Costmap2D) -> NDArray[np.float64]:
        """Prune the plan behind the robot; the part within the costmap, in the robot frame."""
        plan = self._plan
        if len(plan) == 0:
            raise InvalidPath("Received plan with zero length")
        extent = max(costmap.costs.shape) * costmap.resolution / 2.0
        search = self.params.max_robot_pose_search_dist
        search = extent if search is None else (math.inf if search < 0 else search)
        x, y, yaw = pose.x, pose.y, pose.yaw
        # the plan's segment lengths, worked out once per plan (pruning keeps them)
        seg = self._seg
        if self._seg_of is not plan or seg is None:
            seg = segment_lengths(plan)
        closest = closest_index(plan, x, y, search, seg)
        if closest:
            plan = self._plan = plan[closest:]
            seg = seg[closest:]
        self._seg, self._seg_of = seg, plan
        end = integrated_index(plan, 0, 2.0 * extent, seg)
        window = plan[:end]
        dx = window[:, 0] - x
        dy = window[:, 1] - y
        far = np.flatnonzero(fmath.hypot(dx, dy) > extent)
        if far.size:
            k = max(int(far[0]), 1)
            window, dx, dy = window[:k], dx[:k], dy[:k]
        # pose.inverse_transform_points and angle_diff, on the differences already taken
        local = np.empty_like(window)
        s, c = fmath.sincos(yaw)
        local[:, 0] = c * dx + s * dy
        local[:, 1] = -s * dx + c * dy
        dyaw = window[:, 2] - yaw
        if angles_in_range(dyaw):
            local[:, 2] = dyaw  # already in range: what normalize_angle gives back
        else:
            local[:, 2] = normalize_angle(dyaw)
        return local

    def compute_velocity_commands(
        self, pose: Pose2D, velocity: Twist, costmap: Costmap2D, goal_checker=None
    ) -> Twist:
        p = self.params
        local = self._local_plan(pose, costmap)
        lookahead = p.lookahead_dist
        if p.use_velocity_scaled_lookahead_dist:
            lookahead = min(
                max(abs(velocity.linear_x) * p.lookahead_time, p.min_lookahead_dist),
                p.max_lookahead_dist,
            )
        carrot = lookahead_point(local, lookahead)
        self.carrot = carrot
        carrot_x, carrot_y = carrot.tolist()
        curvature = curvature_to(carrot_x, carrot_y)
        rotate_x, rotate_y = carrot_x, carrot_y
        if p.use_fixed_curvature_lookahead:
            rotate_x, rotate_y = lookahead_point(local, p.curvature_lookahead_dist).tolist()
            curvature = curvature_to(rotate_x, rotate_y)
        sign = 1.0
        if p.allow_reversing:
            sign = 1.0 if carrot_x >= 0.0 else -1.0

        goal = Pose2D(*self._plan[-1].tolist())
        transformed = Path(0.0, local, costmap.frame_id)
        length = path_length(local)
        angle_to_path = fmath.arctan2(rotate_y, rotate_x)
        if sign < 0:
            angle_to_path = angle_diff(angle_to_path + math.pi, 0.0)
        if p.use_rotate_to_heading and self._goal_xy_reached(
            pose, goal, velocity, transformed, goal_checker
        ):
            self.is_rotating_to_heading = True
            linear, angular = self._rotate(float(local[-1, 2]), velocity)
        elif p.use_rotate_to_heading and abs(angle_to_path) > p.rotate_to_heading_min_angle:
            self.is_rotating_to_heading = True
            linear, angular = self._rotate(angle_to_path, velocity)
        else:
            self.is_rotating_to_heading = False
            cost = float(costmap.cost_at_point(pose.x, pose.y))
            linear = self._constrained_linear(curvature, cost, local, length) * sign
            angular = linear * curvature

        if p.use_collision_detection:
            carrot_dist = fmath.hypot(carrot_x, carrot_y)
            if self._collision_imminent(pose, linear, angular, carrot_dist, length, costmap):
                raise NoValidControl("RegulatedPurePursuitController detected collision ahead!")
        return Twist(linear_x=float(linear), angular_z=float(angular))

    # --- pieces ----------------------------------------------------------------------------
    @staticmethod
    def _goal_xy_reached(pose, goal, velocity, transformed, goal_checker) -> bool:
        if goal_checker is not None and hasattr(goal_checker, "is_goal_xy_reached"):
            return bool(goal_checker.is_goal_xy_reached(pose, goal, velocity, transformed))
        return pose.distance_to(goal) <= 0.25

    def _rotate(self, angle: float, velocity: Twist) -> tuple[float, float]:
        p = self.params
        sign = 1.0 if angle > 0.0 else -1.0
        w = sign * p.rotate_to_heading_angular_vel
        dw = p.max_angular_accel * self.control_duration
        w = min(max(w, velocity.angular_z - dw), velocity.angular_z + dw)
        stop = math.sqrt(2.0 * p.max_angular_accel * abs(angle))
        if abs(w) > stop:
            w = sign * stop
        return 0.0, w

    def _constrained_linear(
        self,
        curvature: float,
        pose_cost: float,
        local: NDArray[np.float64],
        length: float | None = None,
    ) -> float:
        p = self.params
        v = self.max_linear_vel
        curvature_vel = cost_vel = v
        if p.use_regulated_linear_velocity_scaling and abs(curvature) > 1e-9:
            radius = abs(1.0 / curvature)
            min_r = p.regulated_linear_scaling_min_radius
            if radius < min_r:
                curvature_vel = v * (1.0 - abs(radius - min_r) / min_r)
        if p.use_cost_regulated_linear_velocity_scaling and pose_cost not in (
            NO_INFORMATION,
            FREE_SPACE,
        ):
            # Nav2 reads the layered costmap's inscribed radius (0 without a costmap server)
            inscribed = self.costmap_ros.inscribed_radius if self.costmap_ros is not None else 0.0
            k = p.inflation_cost_scaling_factor
            dist = (k * inscribed - fmath.log(float(pose_cost)) + fmath.log(253.0)) / k
            if dist < p.cost_scaling_dist:
                cost_vel = v * (p.cost_scaling_gain * dist / p.cost_scaling_dist)
        v = max(min(cost_vel, curvature_vel), p.regulated_linear_scaling_min_speed)
        # Approach scaling: only once the remaining path is shorter than the scaling distance.
        if length is None:
            length = path_length(local)
        if length < p.approach_velocity_scaling_dist:
            scale = fmath.hypot(local[-1, 0], local[-1, 1]) / p.approach_velocity_scaling_dist
            v = min(v, max(v * scale, p.min_approach_linear_velocity))
        return min(max(abs(v), 0.0), self.max_linear_vel)

    def _collision_imminent(
        self,
        pose: Pose2D,
        linear: float,
        angular: float,
        carrot_dist: float,
        dist_to_end: float,
        costmap: Costmap2D,
    ) -> bool:
        """Forward-simulate the command on the arc (vectorised) and look for lethal/inscribed cells."""
        p = self.params
        here = costmap.cost_at_point(pose.x, pose.y)
        if here >= INSCRIBED_INFLATED_OBSTACLE and here != NO_INFORMATION:
            return True
        res = costmap.resolution
        if abs(linear) < 0.01 and abs(angular) > 0.01:
            radius = float(getattr(costmap, "circumscribed_radius", 0.0) or res)
            dt = 2.0 * fmath.sin((res / 2.0) / max(radius, res)) / abs(angular)
        elif abs(linear) >= 1e-9:
            dt = res / abs(linear)
        else:
            return False
        horizon = p.max_allowed_time_to_collision_up_to_carrot
        limit = carrot_dist
        if p.min_distance_to_obstacle > 0.0:
            horizon = max(
                horizon,
                p.min_distance_to_obstacle / max(abs(linear), p.min_approach_linear_velocity),
            )
            if p.use_velocity_scaled_lookahead_dist:
                min_d = p.min_distance_to_obstacle
                base = max(
                    carrot_dist,
                    min_d if p.allow_obstacle_checking_beyond_goal else min(min_d, dist_to_end),
                )
                limit = min(base, p.max_lookahead_dist)
        n = max(math.ceil(horizon / dt) - 1, 0)
        n = min(n, 10_000)
        if n == 0:
            return False
        # the arc's n steps of |dt linear| stay within that distance of the robot: with no
        # inscribed cell that near (most cycles), no step can be in collision
        if not _inscribed_near(costmap, pose.x, pose.y, n * abs(dt * linear) + res):
            return False
        if n <= _SCALAR_STEPS:
            return _arc_collides(costmap, pose, dt * linear, dt, angular, n, limit)
        k = np.arange(n)
        theta = pose.yaw + k * dt * angular  # heading before each step
        sin, cos = fmath.sincos(theta)
        x = pose.x + np.cumsum(dt * linear * cos)
        y = pose.y + np.cumsum(dt * linear * sin)
        inside = fmath.hypot(x - pose.x, y - pose.y) <= limit
        stop = np.flatnonzero(~inside)
        m = int(stop[0]) if stop.size else n
        if m == 0:
            return False
        return bool(_in_collision(costmap, np.stack([x[:m], y[:m]], axis=-1)).any())


#: Up to this many forward-simulated steps, the arc is walked point by point.
_SCALAR_STEPS = 64


def _arc_collides(
    costmap: Costmap2D,
    pose: Pose2D,
    step: float,
    dt: float,
    angular: float,
    n: int,
    limit: float,
) -> bool:
    """The vectorised check of `_collision_imminent` for a short arc, one point at a time
    (the same arithmetic: headings, fmath's sin and cos, running sums, distances, cells;
    so the same answer, bit for bit)."""
    x0, y0, yaw = pose.x, pose.y, pose.yaw
    # costmap.cost_at_point, inlined
    costs = costmap.costs
    ny, nx = costs.shape
    ox, oy, res = costmap.origin_x, costmap.origin_y, costmap.resolution
    # |(dx, dy)| <= limit as fmath.hypot decides it: squared distances clearly on one side
    # decide without it (hypot is within an ulp, the squares within a few)
    near, far = -1.0, math.inf  # (always fmath.hypot for extreme limits)
    if 1e-100 < limit < 1e100:
        near, far = limit * limit * (1.0 - 1e-9), limit * limit * (1.0 + 1e-9)
    sum_x = sum_y = 0.0
    for k in range(n):
        theta = yaw + k * dt * angular  # heading before each step
        s, c = fmath.sincos(theta)
        sum_x += step * c
        sum_y += step * s
        x, y = x0 + sum_x, y0 + sum_y
        dx, dy = x - x0, y - y0
        d2 = dx * dx + dy * dy
        if not d2 <= near and (d2 > far or not fmath.hypot(dx, dy) <= limit):
            return False  # the rest is beyond the carrot
        mx = math.floor((x - ox) / res)
        my = math.floor((y - oy) / res)
        if 0 <= mx < nx and 0 <= my < ny:
            cost = int(costs[my, mx])
            if cost >= INSCRIBED_INFLATED_OBSTACLE and cost != NO_INFORMATION:
                return True
    return False


def _inscribed_near(costmap: Costmap2D, x: float, y: float, radius: float) -> bool:
    """Whether a cell of the square of half-side `radius` around (x, y) is inscribed or
    worse (unknown is not): the cells the arc's points can fall in (floor is monotone)."""
    res = costmap.resolution
    ny, nx = costmap.costs.shape
    x0 = max(math.floor((x - radius - costmap.origin_x) / res), 0)
    x1 = min(math.floor((x + radius - costmap.origin_x) / res) + 1, nx)
    y0 = max(math.floor((y - radius - costmap.origin_y) / res), 0)
    y1 = min(math.floor((y + radius - costmap.origin_y) / res) + 1, ny)
    if x0 >= x1 or y0 >= y1:
        return False
    window = costmap.costs[y0:y1, x0:x1]
    return bool(((window >= INSCRIBED_INFLATED_OBSTACLE) & (window != NO_INFORMATION)).any())


def _in_collision(costmap: Costmap2D, xy: NDArray[np.float64]) -> NDArray[np.bool_]:
    """A circular robot centred in an inscribed-or-worse cell collides (unknown does not)."""
    c = costmap.cost_at(xy)
    return (c >= INSCRIBED_INFLATED_OBSTACLE) & (c != NO_INFORMATION)
