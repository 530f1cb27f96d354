"""The odometry's noise, learnt from the log itself.

Odometry differs by an order of magnitude between robots, so no fixed model weighs it
right against a scan match. This one fits, by weighted least squares over the
well-supported sequential matches so far, heading and position variances proportional to
the squares of travel and turn since the previous scan (as Karto's and AMCL's odometry
models), with capped weights and a conservative prior. Running sums, no history:
deterministic, one 2 x 2 solve per observation. The model, and what it learns on each
benchmark log: docs/decisions/0058.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

F64 = NDArray[np.float64]

#: The prior model's standard deviations: heading per metre and per radian, position
#: per metre and per radian. Conservative (noisy odometry, trust the match): the Intel and
#: Freiburg 079 level, so that until the log says otherwise the matcher decides, as Karto.
PRIOR_HEADING_PER_METRE = 0.15
PRIOR_HEADING_PER_RADIAN = 0.2
PRIOR_POSITION_PER_METRE = 0.2
PRIOR_POSITION_PER_RADIAN = 0.1
#: The prior weighs as this many observations of pure travel (1 m) and of pure turn (1 rad).
PRIOR_WEIGHT = 5.0
#: An observation counts at most this many times the variance the current model predicts.
CLIP = 9.0
#: The model is used only after this many observations (the hospital has 1030, the
#: shortest benchmark log, MIT CSAIL, 475).
MINIMUM_COUNT = 30
#: Variances never fall below these (rad^2 and m^2 per unit^2): a match's noise
#: floor, so that a few perfect pairs cannot make odometry infallible.
FLOOR_HEADING = 0.005**2
FLOOR_POSITION = 0.01**2


class _Fit:
    """var = a t^2 + b r^2, weighted least squares over running sums, a, b >= floor."""

    def __init__(self, a: float, b: float, weight: float, floor: float):
        self.floor = floor
        self.m = np.zeros((2, 2))
        self.v = np.zeros(2)
        # the prior: `weight` observations of (t, r) = (1, 0) at a and of (0, 1) at b
        self.m[0, 0] = weight / (a * a)
        self.m[1, 1] = weight / (b * b)
        self.v[0] = weight / a
        self.v[1] = weight / b
        self.a, self.b = a, b

    def predict(self, t2: float, r2: float) -> float:
        return self.a * t2 + self.b * r2

    def add(self, t2: float, r2: float, y: float) -> None:
        s = self.predict(t2, r2)
        if s <= 0.0:
            return
        y = min(max(y, 0.0), CLIP * s)
        w = 1.0 / (s * s)
        self.m[0, 0] += w * t2 * t2
        self.m[0, 1] += w * t2 * r2
        self.m[1, 1] += w * r2 * r2
        self.v[0] += w * t2 * y
        self.v[1] += w * r2 * y
        self._solve()

    def _solve(self) -> None:
        m00, m01, m11 = self.m[0, 0], self.m[0, 1], self.m[1, 1]
        det = m00 * m11 - m01 * m01
        a = (m11 * self.v[0] - m01 * self.v[1]) / det
        b = (m00 * self.v[1] - m01 * self.v[0]) / det
        if a < self.floor:  # the 2 x 2 non-negative solve: fix one, fit the other
            a = self.floor
            b = (self.v[1] - m01 * a) / m11
        elif b < self.floor:
            b = self.floor
            a = (self.v[0] - m01 * b) / m00
        self.a, self.b = max(a, self.floor), max(b, self.floor)


class OdometryNoise:
    """The odometry's noise per metre travelled and per radian turned, from
    odometry-versus-match discrepancies (see the module doc)."""

    def __init__(self) -> None:
        self.heading = _Fit(
            PRIOR_HEADING_PER_METRE**2, PRIOR_HEADING_PER_RADIAN**2, PRIOR_WEIGHT, FLOOR_HEADING
        )
        self.position = _Fit(
            PRIOR_POSITION_PER_METRE**2, PRIOR_POSITION_PER_RADIAN**2, PRIOR_WEIGHT, FLOOR_POSITION
        )
        self.count = 0

    @property
    def trusted(self) -> bool:
        return self.count >= MINIMUM_COUNT

    def observe(self, increment: F64, discrepancy: F64) -> None:
        """One well-supported match: `increment` the odometry's (x, y, yaw) since the
        previous scan, `discrepancy` the match's pose in the frame of the pose the
        odometry predicted."""
        t2 = float(increment[0] ** 2 + increment[1] ** 2)
        r2 = float(increment[2] ** 2)
        if t2 + r2 <= 0.0:
            return
        self.heading.add(t2, r2, float(discrepancy[2] ** 2))
        self.position.add(t2, r2, 0.5 * float(discrepancy[0] ** 2 + discrepancy[1] ** 2))
        self.count += 1

    def covariance(self, increment: F64) -> F64:
        """The odometry increment's (3, 3) covariance (position isotropic, in its frame)."""
        t2 = float(increment[0] ** 2 + increment[1] ** 2)
        r2 = float(increment[2] ** 2)
        p = self.position.predict(t2, r2)
        return np.diag([p, p, self.heading.predict(t2, r2)])

    def per_unit(self) -> tuple[float, float, float, float]:
        """Standard deviations: heading per metre and per radian, position per metre and
        per radian (the model, for reports)."""
        return (
            math.sqrt(self.heading.a),
            math.sqrt(self.heading.b),
            math.sqrt(self.position.a),
            math.sqrt(self.position.b),
        )
