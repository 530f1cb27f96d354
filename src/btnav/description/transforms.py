"""Rigid 3D transforms (URDF's xyz + rpy, SDF's pose), composed exactly the same way on any CPU.

A transform is (R, t): a 3x3 rotation as nested tuples and a translation, the child's
pose in its parent. Products are plain float arithmetic in a fixed order and the
trigonometry is `core.fmath`'s, because the mounting poses read from a description
place the simulated lidar, whose readings a run's trajectory depends on.
"""

from __future__ import annotations

from collections.abc import Sequence

from ..core import fmath

Vec3 = tuple[float, float, float]
Mat3 = tuple[Vec3, Vec3, Vec3]
Transform = tuple[Mat3, Vec3]

IDENTITY: Transform = (((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)), (0.0, 0.0, 0.0))


def rpy_matrix(roll: float, pitch: float, yaw: float) -> Mat3:
    """URDF's fixed-axis roll, pitch, yaw: R = Rz(yaw) Ry(pitch) Rx(roll)."""
    sr, cr = fmath.sincos(float(roll))
    sp, cp = fmath.sincos(float(pitch))
    sy, cy = fmath.sincos(float(yaw))
    return (
        (cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr),
        (sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr),
        (-sp, cp * sr, cp * cr),
    )


def from_xyz_rpy(xyz: Sequence[float], rpy: Sequence[float]) -> Transform:
    return rpy_matrix(*rpy), (float(xyz[0]), float(xyz[1]), float(xyz[2]))


def rotate(r: Mat3, v: Sequence[float]) -> Vec3:
    return (
        r[0][0] * v[0] + r[0][1] * v[1] + r[0][2] * v[2],
        r[1][0] * v[0] + r[1][1] * v[1] + r[1][2] * v[2],
        r[2][0] * v[0] + r[2][1] * v[1] + r[2][2] * v[2],
    )


def apply(t: Transform, v: Sequence[float]) -> Vec3:
    """A point given in the child frame, in the parent frame."""
    x, y, z = rotate(t[0], v)
    return (x + t[1][0], y + t[1][1], z + t[1][2])


def compose(a: Transform, b: Transform) -> Transform:
    """a then b: the pose of b's child in a's parent frame."""
    ra, rb = a[0], b[0]
    cols = [rotate(ra, (rb[0][j], rb[1][j], rb[2][j])) for j in range(3)]
    r: Mat3 = (
        (cols[0][0], cols[1][0], cols[2][0]),
        (cols[0][1], cols[1][1], cols[2][1]),
        (cols[0][2], cols[1][2], cols[2][2]),
    )
    return r, apply(a, b[1])


def inverse(t: Transform) -> Transform:
    r = t[0]
    rt: Mat3 = (
        (r[0][0], r[1][0], r[2][0]),
        (r[0][1], r[1][1], r[2][1]),
        (r[0][2], r[1][2], r[2][2]),
    )
    x, y, z = rotate(rt, t[1])
    return rt, (-x, -y, -z)


def yaw_of(t: Transform) -> float:
    """The heading of the child's x axis seen from above (its 2D yaw)."""
    r = t[0]
    return float(fmath.arctan2(r[1][0], r[0][0]))


def up_of(t: Transform) -> float:
    """How vertical the child's z axis is: 1 upright, -1 upside down, 0 on its side."""
    return t[0][2][2]
