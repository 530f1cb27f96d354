"""What SLAM on a recorded log gives, whichever engine ran it (`btnav slam`)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from ..maps.occupancy_grid import OccupancyGrid

if TYPE_CHECKING:
    from .cartographer.slam import CartographerMapper
    from .karto.mapper import Mapper

F64 = NDArray[np.float64]


@dataclass
class OfflineResult:
    stamps: F64  # (S,) every scan's time
    poses: F64  # (S, 3) every scan's robot pose in the map frame
    mapper: Mapper | CartographerMapper  # slam_toolbox's (Karto's) or Cartographer's graph
    grid: OccupancyGrid
    wall_time: float

    @property
    def processed(self) -> int:
        return len(self.mapper.scans)
