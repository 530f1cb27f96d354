"""How much of a world an exploration mapped: the share of its reachable free space.

The truth is the world's own raster (`sim.rasterize`); "reachable" is the free space
4-connected to the robot's start, so a closed cupboard does not count against it.
A truly free cell counts as mapped when the map holds it as free.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from ..maps.occupancy_grid import FREE, OccupancyGrid


@dataclass(frozen=True)
class Coverage:
    mapped_m2: float  # reachable free space the map holds as free
    reachable_m2: float  # reachable free space in the world

    @property
    def fraction(self) -> float:
        return self.mapped_m2 / self.reachable_m2 if self.reachable_m2 > 0 else 0.0


def reachable_free(truth: OccupancyGrid, start: tuple[float, float]) -> np.ndarray:
    """The truth's free cells 4-connected to `start` (a boolean grid like truth.data)."""
    labels, _ = ndimage.label(truth.data == FREE)
    ((r, c),) = truth.world_to_cell(np.array([start]))
    if not truth.in_bounds(np.array([r, c])) or labels[r, c] == 0:
        return np.zeros(truth.data.shape, dtype=bool)
    return labels == labels[r, c]


def coverage(slam: OccupancyGrid, truth: OccupancyGrid, start: tuple[float, float]) -> Coverage:
    """How much of the reachable free space of `truth` the map `slam` holds as free."""
    reach = reachable_free(truth, start)
    rows, cols = np.nonzero(reach)
    centres = truth.cell_to_world(np.column_stack((rows, cols)))
    rc = slam.world_to_cell(centres)
    inside = slam.in_bounds(rc)
    mapped = np.zeros(len(rows), dtype=bool)
    mapped[inside] = slam.data[rc[inside, 0], rc[inside, 1]] == FREE
    cell = truth.resolution**2
    return Coverage(float(mapped.sum()) * cell, float(len(rows)) * cell)
