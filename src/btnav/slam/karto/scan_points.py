"""A LaserScan as Karto reads it: the end points that count, in the robot's frame."""

from __future__ import annotations

import numpy as np

from ...core import fmath
from ...core.geometry import Pose2D, compose_arrays
from ...core.messages import LaserScan


def scan_points(
    scan: LaserScan, laser: Pose2D, max_range: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(valid end points in the base frame, ranges, beam angles) of a scan, Karto's way:
    readings outside [range_min, min(range_max, max_laser_range)] make no point."""
    ranges = np.asarray(scan.ranges, np.float32)
    angles = scan.angles
    r = ranges.astype(float)
    top = min(scan.range_max, max_range)
    ok = np.isfinite(r) & (r >= scan.range_min) & (r <= top)
    s, c = fmath.sincos(angles[ok])
    local = np.column_stack([r[ok] * c, r[ok] * s, np.zeros(int(ok.sum()))])
    base = compose_arrays(laser.as_array(), local)[:, :2] if len(local) else np.zeros((0, 2))
    return base, ranges, angles
