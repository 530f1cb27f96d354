"""A costmap as a source (nav2_collision_monitor's CostmapSource, Nav2 main): the centre
of every cell whose cost is at or above `cost_threshold` (NO_INFORMATION excluded), and
of every unknown cell when `treat_unknown_as_obstacle`, in the base frame.

btnav hands the source the local costmap's server (Nav2's default topic
`local_costmap/costmap`); the costmap's stamp is its last update.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from ..costmap.cost_values import NO_INFORMATION
from ..costmap.costmap_2d import Costmap2D
from ..params.collision_monitor import ObservationSource
from .exclusion_zone import ExclusionZone
from .source import Source, SourceFrames

#: The costmap, its frame and its stamp (None before its first update).
CostmapReading = tuple[Costmap2D, str, float | None]


class CostmapSource(Source):
    """`costmap` source: reads the costmap it is given each cycle."""

    def __init__(
        self,
        name: str,
        params: ObservationSource,
        frames: SourceFrames,
        source_timeout: float,
        zones: list[ExclusionZone] | None = None,
        *,
        costmap: Callable[[], CostmapReading],
    ) -> None:
        super().__init__(name, params, frames, source_timeout, zones)
        self._costmap = costmap

    def source_data(self, now: float) -> NDArray[np.float64] | None:
        grid, frame, stamp = self._costmap()
        if stamp is None or not self.source_valid(stamp, now):
            return None
        costs = grid.costs
        obstacle = (costs >= self.params.cost_threshold) & (costs < NO_INFORMATION)
        if self.params.treat_unknown_as_obstacle:
            obstacle |= costs == NO_INFORMATION
        my, mx = np.nonzero(obstacle)
        centres = np.empty((len(mx), 2))
        centres[:, 0] = grid.origin_x + (mx + 0.5) * grid.resolution
        centres[:, 1] = grid.origin_y + (my + 0.5) * grid.resolution
        # a costmap lies still in its (odom) frame: no motion to correct for since its stamp
        return self.frames.tree.lookup(self.frames.base_frame, frame).transform_points(centres)
