"""nav2_graceful_controller's SmoothControlLaw: a smooth, curvature-limited path to a pose.

Park and Kuipers' control law: in egocentric polar coordinates of the target (`r` the
distance, `phi` the target's heading relative to the line of sight, `delta` the robot's),
the curvature that steers the robot onto a spiral ending at the target's heading is

    kappa = -(k_delta * (delta - atan(-k_phi * phi)) + (1 + k_phi / (1 + (k_phi * phi)^2)) * sin(delta)) / r

The speed falls with the curvature (`v_linear_max / (1 + beta * |kappa|^lambda)`),
inside `slowdown_radius` of the target and within `deceleration_max`, clamped to
[`v_linear_min`, `v_linear_max`]; the turn rate `kappa * v` is bounded by
`v_angular_max` and the speed follows the curvature. Backward motion flips the line
of sight and the signs. (Nav2 computes r, phi and delta in float; here in double.)
"""

from __future__ import annotations

import math

from ..core import fmath
from ..core.geometry import Pose2D, normalize_angle
from ..core.messages import Twist


class SmoothControlLaw:
    def __init__(
        self,
        k_phi: float,
        k_delta: float,
        beta: float,
        lambda_: float,
        slowdown_radius: float,
        deceleration_max: float,
        v_linear_min: float,
        v_linear_max: float,
        v_angular_max: float,
    ) -> None:
        self.k_phi, self.k_delta, self.beta, self.lambda_ = k_phi, k_delta, beta, lambda_
        self.slowdown_radius = slowdown_radius
        self.deceleration_max = deceleration_max
        self.v_linear_min, self.v_linear_max = v_linear_min, v_linear_max
        self.v_angular_max = v_angular_max

    def curvature(self, r: float, phi: float, delta: float) -> float:
        k_phi = self.k_phi
        kp = k_phi * phi
        steer = self.k_delta * (delta - _atan(-kp)) + (1.0 + k_phi / (1.0 + kp * kp)) * fmath.sin(
            delta
        )
        if r > 0.0:
            return -steer / r
        return 0.0 if steer == 0.0 else math.copysign(math.inf, -steer)  # C++'s -x / 0

    def velocity(
        self, target: Pose2D, current: Pose2D | None = None, backward: bool = False
    ) -> Twist:
        """The command from `current` (default: the origin, a target in the robot's frame)."""
        cur = current if current is not None else Pose2D()
        dx, dy = target.x - cur.x, target.y - cur.y
        sight = fmath.arctan2(-dy, dx)
        if backward:
            sight += math.pi
        r = math.sqrt(dx * dx + dy * dy)
        phi = normalize_angle(target.yaw + sight)
        delta = normalize_angle(cur.yaw + sight)
        kappa = self.curvature(r, phi, delta)
        if backward:
            kappa = -kappa
        v = self.v_linear_max / (1.0 + self.beta * _pow(abs(kappa), self.lambda_))
        v = min(self.v_linear_max * (r / self.slowdown_radius), v)
        v = min(math.sqrt(2.0 * r * self.deceleration_max), v)
        v = min(max(v, self.v_linear_min), self.v_linear_max)
        if backward:
            v = -v
        w = kappa * v
        w_bound = min(max(w, -self.v_angular_max), self.v_angular_max)
        if kappa != 0.0:
            v = w_bound / kappa
        return Twist(linear_x=v, angular_z=w_bound)

    def next_pose(
        self, dt: float, target: Pose2D, current: Pose2D, backward: bool = False
    ) -> Pose2D:
        """One step of `dt` along the command from `current` (the trajectory's next pose)."""
        cmd = self.velocity(target, current, backward)
        s, c = fmath.sincos(current.yaw)
        return Pose2D(
            current.x + cmd.linear_x * dt * c,
            current.y + cmd.linear_x * dt * s,
            current.yaw + cmd.angular_z * dt,
        )


def _atan(x: float) -> float:
    return float(fmath.arctan2(x, 1.0))


def _pow(x: float, y: float) -> float:
    """x ** y for x >= 0 through core.fmath (libm's pow is CPU-dependent)."""
    if x == 0.0:
        return 0.0 if y > 0.0 else 1.0
    if y == 2.0:
        return x * x
    if y == 1.0:
        return x
    return float(fmath.exp(y * fmath.log(x)))
