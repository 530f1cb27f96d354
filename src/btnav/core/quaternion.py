"""Quaternions (x, y, z, w) for the few 3D rotations a dock detector and the dock plugins need, as tf2 computes them.

A detector reports a marker's 3D orientation (an apriltag's axes are not the ground
plane's), the dock plugin rotates it by `external_detection_rotation_{roll,pitch,yaw}`
and keeps only the yaw, and the pose filter blends orientations by slerp. tf2's
`setRPY`, `getYaw` and `slerp` are the reference; the trigonometry is `core.fmath`'s.
"""

from __future__ import annotations

import math

from . import fmath

Quaternion = tuple[float, float, float, float]

IDENTITY: Quaternion = (0.0, 0.0, 0.0, 1.0)


def from_rpy(roll: float, pitch: float, yaw: float) -> Quaternion:
    """tf2::Quaternion::setRPY: fixed axes x (roll), then y (pitch), then z (yaw)."""
    sr, cr = fmath.sincos(0.5 * float(roll))
    sp, cp = fmath.sincos(0.5 * float(pitch))
    sy, cy = fmath.sincos(0.5 * float(yaw))
    return (
        sr * cp * cy - cr * sp * sy,
        cr * sp * cy + sr * cp * sy,
        cr * cp * sy - sr * sp * cy,
        cr * cp * cy + sr * sp * sy,
    )


def from_yaw(yaw: float) -> Quaternion:
    s, c = fmath.sincos(0.5 * float(yaw))
    return (0.0, 0.0, s, c)


def multiply(a: Quaternion, b: Quaternion) -> Quaternion:
    """a * b: rotate by b, then by a (tf2's operator*)."""
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
        aw * bw - ax * bx - ay * by - az * bz,
    )


def from_matrix(m: tuple[tuple[float, float, float], ...]) -> Quaternion:
    """The unit quaternion of a rotation matrix (rows), by the largest diagonal term."""
    (m00, m01, m02), (m10, m11, m12), (m20, m21, m22) = m
    trace = m00 + m11 + m22
    if trace > 0.0:
        s = 2.0 * math.sqrt(trace + 1.0)
        return ((m21 - m12) / s, (m02 - m20) / s, (m10 - m01) / s, 0.25 * s)
    if m00 >= m11 and m00 >= m22:
        s = 2.0 * math.sqrt(1.0 + m00 - m11 - m22)
        return (0.25 * s, (m01 + m10) / s, (m02 + m20) / s, (m21 - m12) / s)
    if m11 >= m22:
        s = 2.0 * math.sqrt(1.0 + m11 - m00 - m22)
        return ((m01 + m10) / s, 0.25 * s, (m12 + m21) / s, (m02 - m20) / s)
    s = 2.0 * math.sqrt(1.0 + m22 - m00 - m11)
    return ((m02 + m20) / s, (m12 + m21) / s, 0.25 * s, (m10 - m01) / s)


def yaw_of(q: Quaternion) -> float:
    """tf2::getYaw: the z angle of the ZYX Euler decomposition (0 at gimbal lock)."""
    x, y, z, w = q
    n = x * x + y * y + z * z + w * w
    s = 2.0 / n if n > 0.0 else 0.0
    r20 = s * (x * z - w * y)
    if abs(r20) >= 1.0:  # pitch of +-90 degrees: tf2 returns yaw 0
        return 0.0
    r00 = 1.0 - s * (y * y + z * z)
    r10 = s * (x * y + w * z)
    return float(fmath.arctan2(r10, r00))


def slerp(a: Quaternion, b: Quaternion, t: float) -> Quaternion:
    """tf2::Quaternion::slerp: the shorter arc from a (t = 0) to b (t = 1)."""
    dot = sum(p * q for p, q in zip(a, b, strict=True))
    norm = math.sqrt(sum(p * p for p in a) * sum(q * q for q in b))
    cosine = max(-1.0, min(1.0, abs(dot) / norm)) if norm > 0.0 else 1.0
    half = float(fmath.arctan2(math.sqrt(max(0.0, 1.0 - cosine * cosine)), cosine))
    if half == 0.0:
        return a
    inv = 1.0 / fmath.sin(half)
    s0 = fmath.sin((1.0 - t) * half) * inv
    s1 = fmath.sin(t * half) * inv
    if dot < 0.0:
        s1 = -s1
    return (
        a[0] * s0 + b[0] * s1,
        a[1] * s0 + b[1] * s1,
        a[2] * s0 + b[2] * s1,
        a[3] * s0 + b[3] * s1,
    )
