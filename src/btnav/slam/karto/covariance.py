"""3 x 3 pose covariances in closed form: the same bits on every CPU (no LAPACK)."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

F64 = NDArray[np.float64]


def largest_variance(covariance: F64) -> float:
    """The positional covariance's largest eigenvalue: the variance along the direction
    the match is least sure of (a corridor's length), closed form (no LAPACK)."""
    a, b, c = float(covariance[0, 0]), float(covariance[0, 1]), float(covariance[1, 1])
    h = 0.5 * (a - c)
    return 0.5 * (a + c) + math.sqrt(h * h + b * b)


def inv3(m: F64) -> F64:
    """Inverse of a 3 x 3 matrix by cofactors (no LAPACK: the same bits on every CPU)."""
    a = np.asarray(m, float)
    cof = np.empty((3, 3))
    for i in range(3):
        for j in range(3):
            r = [k for k in range(3) if k != i]
            q = [k for k in range(3) if k != j]
            minor = a[r[0], q[0]] * a[r[1], q[1]] - a[r[0], q[1]] * a[r[1], q[0]]
            cof[i, j] = minor if (i + j) % 2 == 0 else -minor
    det = a[0, 0] * cof[0, 0] + a[0, 1] * cof[0, 1] + a[0, 2] * cof[0, 2]
    if det == 0.0:
        raise np.linalg.LinAlgError("singular covariance")
    return cof.T / det
