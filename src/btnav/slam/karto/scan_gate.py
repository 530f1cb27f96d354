"""slam_toolbox's shouldProcessScan: which scans reach the mapper at all.

The first scan always passes; after it, a scan passes when it is the `throttle_scans`-th,
at least `minimum_time_interval` after the last one that passed, at least
sqrt(0.8) x `minimum_travel_distance` from it (slam_toolbox allows 10% for odometry
error; turning alone never passes here), and not among the first five scans seen.
Karto's own gate (`Mapper.has_moved_enough`) comes after this one.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ...params.localization import SlamToolboxParams


class ScanGate:
    def __init__(self, params: SlamToolboxParams) -> None:
        self.params = params
        self.count = 0
        self.last: tuple[float, np.ndarray] | None = None

    def __call__(self, stamp: float, odom_pose: ArrayLike) -> bool:
        p = self.params
        odom = np.asarray(odom_pose, float)
        self.count += 1
        if self.last is None:
            self.last = (stamp, odom)
            return True
        if self.count % p.throttle_scans != 0:
            return False
        last_stamp, last_odom = self.last
        if stamp - last_stamp < p.minimum_time_interval:
            return False
        d2 = float(((odom[:2] - last_odom[:2]) ** 2).sum())
        if d2 < 0.8 * p.minimum_travel_distance**2 or self.count < 5:
            return False
        self.last = (stamp, odom)
        return True
