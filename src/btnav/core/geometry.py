"""SE(2) poses and vectorised transforms of point arrays.

`Pose2D` is the one pose type in btnav (x, y in metres, yaw in radians, yaw kept in
(-pi, pi]). Composition follows the TF convention: `a @ b` is "b expressed in a's
parent frame", so `map_T_odom @ odom_T_base` gives `map_T_base`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import fmath

TWO_PI = 2.0 * math.pi
_PI = math.pi
_NEG_PI = -math.pi
#: How a frozen dataclass sets its fields.
_set = object.__setattr__


def normalize_angle(a: Any) -> Any:
    """Wrap angles to (-pi, pi]; works on floats and arrays alike."""
    if isinstance(a, np.ndarray):
        if a.dtype == np.float64 and angles_in_range(a):
            return a.copy()  # what the general path gives back for angles already in range
        in_range = (a > -np.pi) & (a <= np.pi)
        out = np.mod(a + np.pi, TWO_PI) - np.pi
        out = np.where(out <= -np.pi, out + TWO_PI, out)
        # Angles already in range come back untouched (the round trip costs an ulp).
        return np.where(in_range, a, out)
    if -math.pi < a <= math.pi:
        return float(a)
    out = math.fmod(float(a) + math.pi, TWO_PI)
    if out < 0:
        out += TWO_PI
    out -= math.pi
    return out + TWO_PI if out <= -math.pi else out


def angles_in_range(a: NDArray[np.float64]) -> bool:
    """Whether a non-empty float array lies in (-pi, pi] (NaN does not): one reduction of
    |a| in the common case instead of a mask of two comparisons."""
    if not a.size:
        return False
    m = np.abs(a).max()
    return bool(m < np.pi or (m == np.pi and a.min() > -np.pi))


def angle_diff(a: Any, b: Any) -> Any:
    """The signed shortest rotation from b to a."""
    return normalize_angle(a - b)


@dataclass(frozen=True, slots=True, init=False)
class Pose2D:
    """A rigid transform in the plane: a robot pose, a sensor mount, a frame offset."""

    x: float = 0.0
    y: float = 0.0
    yaw: float = 0.0

    def __init__(self, x: float = 0.0, y: float = 0.0, yaw: float = 0.0) -> None:
        # Plain floats with the yaw in range (the common case, on hot paths) are kept as
        # given; anything else becomes floats, the yaw wrapped. (The dataclass's own
        # __init__ and a __post_init__ reading the fields back cost twice as much.)
        if not (
            type(x) is float and type(y) is float and type(yaw) is float and _NEG_PI < yaw <= _PI
        ):
            x, y, yaw = float(x), float(y), normalize_angle(float(yaw))
        _set(self, "x", x)
        _set(self, "y", y)
        _set(self, "yaw", yaw)

    @classmethod
    def from_array(cls, a: ArrayLike) -> Pose2D:
        v = np.asarray(a, dtype=float).ravel()
        if v.shape == (2,):
            x, y = v.tolist()
            return cls(x, y, 0.0)
        if v.shape != (3,):
            raise ValueError(f"a pose is [x, y] or [x, y, yaw], got {v.shape[0]} numbers")
        x, y, yaw = v.tolist()  # Python floats: the constructor takes them as they are
        return cls(x, y, yaw)

    def as_array(self) -> NDArray[np.float64]:
        return np.array([self.x, self.y, self.yaw])

    def as_matrix(self) -> NDArray[np.float64]:
        """The 3x3 homogeneous matrix."""
        s, c = fmath.sincos(self.yaw)
        return np.array([[c, -s, self.x], [s, c, self.y], [0.0, 0.0, 1.0]])

    def __matmul__(self, other: Pose2D) -> Pose2D:
        return self.compose(other)

    def compose(self, other: Pose2D) -> Pose2D:
        s, c = fmath.sincos(self.yaw)
        return Pose2D(
            self.x + c * other.x - s * other.y,
            self.y + s * other.x + c * other.y,
            self.yaw + other.yaw,
        )

    def inverse(self) -> Pose2D:
        s, c = fmath.sincos(self.yaw)
        return Pose2D(-c * self.x - s * self.y, s * self.x - c * self.y, -self.yaw)

    def relative_to(self, other: Pose2D) -> Pose2D:
        """This pose seen from `other` (both in one parent frame): `other⁻¹ @ self`."""
        return other.inverse() @ self

    def transform_points(self, points: ArrayLike) -> NDArray[np.float64]:
        """Map an (N, 2) array of points from this frame into its parent frame."""
        p = np.asarray(points, dtype=float)
        s, c = fmath.sincos(self.yaw)
        out = np.empty_like(p)
        out[..., 0] = c * p[..., 0] - s * p[..., 1] + self.x
        out[..., 1] = s * p[..., 0] + c * p[..., 1] + self.y
        return out

    def inverse_transform_points(self, points: ArrayLike) -> NDArray[np.float64]:
        """Map points from the parent frame into this frame."""
        p = np.asarray(points, dtype=float)
        dx, dy = p[..., 0] - self.x, p[..., 1] - self.y
        s, c = fmath.sincos(self.yaw)
        out = np.empty_like(p)
        out[..., 0] = c * dx + s * dy
        out[..., 1] = -s * dx + c * dy
        return out

    def distance_to(self, other: Pose2D) -> float:
        return fmath.hypot(other.x - self.x, other.y - self.y)

    def __iter__(self):  # allows `x, y, yaw = pose`
        return iter((self.x, self.y, self.yaw))


def compose_arrays(a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
    """Compose many poses at once: rows of (x, y, yaw), broadcasting like `a[i] @ b[i]`."""
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    if a.shape == (3,) and b.ndim == 2 and b.shape[1] == 3:
        # one pose composed with many: its sin and cos once, on a Python float
        ax, ay, ayaw = a.tolist()
        sa, ca = fmath.sincos(ayaw)
        bx, by = b[:, 0], b[:, 1]
        out = np.empty(b.shape)
        out[:, 0] = ax + ca * bx - sa * by
        out[:, 1] = ay + sa * bx + ca * by
        yaw = ayaw + b[:, 2]
        out[:, 2] = yaw if angles_in_range(yaw) else normalize_angle(yaw)
        return out
    s, c = fmath.sincos(a[..., 2])
    out = np.empty(np.broadcast_shapes(a.shape, b.shape))
    out[..., 0] = a[..., 0] + c * b[..., 0] - s * b[..., 1]
    out[..., 1] = a[..., 1] + s * b[..., 0] + c * b[..., 1]
    out[..., 2] = normalize_angle(a[..., 2] + b[..., 2])
    return out


def relative_arrays(a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
    """Each b[i] in a[i]'s frame, `a[i]^-1 @ b[i]`, for rows of (x, y, yaw)."""
    a = np.asarray(a, dtype=float)
    s, c = fmath.sincos(a[..., 2])
    inv = np.empty(a.shape)
    inv[..., 0] = -(c * a[..., 0] + s * a[..., 1])
    inv[..., 1] = s * a[..., 0] - c * a[..., 1]
    inv[..., 2] = -a[..., 2]
    return compose_arrays(inv, b)
