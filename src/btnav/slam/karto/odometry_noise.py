"""The odometry's noise, learnt from the log itself.

Odometry differs by an order of magnitude between robots (heading error per metre
travelled over the relations: the Freiburg hospital 0.8 degrees, MIT CSAIL 1.05, ACES
3.2, Intel 7.0, Freiburg 079 10.6), so no fixed model weighs it right against a scan
match (a fixed 0.05 rad/m helped the hospital; 0.1 rad/m broke Freiburg 079). This one
compares the odometry's increment between processed scans with the well-supported
sequential matches (the match's pose in the frame of the pose the odometry predicted)
and fits, by weighted least squares over every such pair so far, the variances

    heading:          var = A t^2 + B r^2
    position (each):  var = C t^2 + D r^2

for t metres travelled and r radians turned since the previous scan (standard
deviations proportional to travel and turn, as Karto's and AMCL's odometry models).
Each pair's squared discrepancy is one observation, weighted by the inverse square of
its predicted variance (a chi-square's variance is twice its mean squared) and capped
at `CLIP` times it (a well-supported match can still be wrong), with a prior of
`PRIOR_WEIGHT` observations at the conservative `PRIOR_*` model. Running sums, no
history: deterministic, scale-free, one 2 x 2 solve per observation.

The match's own error stays in the model (a conservative bias): Karto's covariances are
no measure of it. On ACES the good matches' positional standard deviation (Karto's, median)
is 7.5 cm, their discrepancy from the odometry 2.5 cm RMS; with the match's variance
subtracted every log's position model fell to the floor and ACES went from 5.44 to
10.82 cm. Learnt so (heading per metre, per radian; position per metre, per radian):
the hospital 0.29 deg, 0.06; 0.04 m, 0.11 m. ACES 1.2 deg, 0.13; 0.05, 0.05. MIT CSAIL
4.7 deg, 0.23; 0.06, 0.04. Intel 4.1 deg, 0.05; 0.05, 0.04. Freiburg 079 1.4 deg, 0.31;
0.05, 0.07.
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
