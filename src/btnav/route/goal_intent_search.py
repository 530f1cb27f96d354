"""Which nearby graph node is nearest by the costmap, not only in a straight line
(nav2_route's GoalIntentSearch): a line-of-sight check, then a breadth-first search.

A cell blocks when its cost is at least INSCRIBED (253) and not unknown (255), as in
Nav2. The search spreads from the pose's cell through the 8 neighbours of each cell,
a whole wavefront at a time, and answers the first candidate node's cell it reaches
(in one wavefront, the earliest candidate in the list).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..costmap.cost_values import INSCRIBED_INFLATED_OBSTACLE, NO_INFORMATION
from .context import CostmapView
from .line_cells import line_cells


def _blocked(costs: np.ndarray) -> np.ndarray:
    return (costs >= INSCRIBED_INFLATED_OBSTACLE) & (costs != NO_INFORMATION)


def line_of_sight_blocked(view: CostmapView, a: Sequence[float], b: Sequence[float]) -> bool | None:
    """Whether the straight line a -> b crosses a blocking cell; None if an end is off the map."""
    cells, inside = view.cells([a, b])
    if not inside.all():
        return None
    mx, my = line_cells(int(cells[0, 0]), int(cells[0, 1]), int(cells[1, 0]), int(cells[1, 1]))
    return bool(_blocked(view.costmap.costs[my, mx]).any())


def breadth_first_search(
    view: CostmapView,
    reference: Sequence[float],
    candidates: Sequence[Sequence[float]],
    max_iterations: int | None = None,
) -> int | None:
    """The index in `candidates` of the first one the search from `reference` reaches, or
    None (off the map, walled off, or past `max_iterations` cells expanded)."""
    cells, inside = view.cells([reference, *candidates])
    if not inside[0]:
        return None
    costmap = view.costmap
    nx, ny = costmap.size_x, costmap.size_y
    flat = cells[:, 1] * nx + cells[:, 0]
    on_map = np.flatnonzero(inside[1:])
    if len(on_map) == 0:
        return None
    goal_cells = flat[1:][on_map]
    free = ~_blocked(costmap.costs).ravel()
    visited = np.zeros(nx * ny, dtype=bool)
    frontier = flat[:1].astype(np.int64)
    visited[frontier] = True
    expanded = 0
    offsets = np.array([(-1, 0), (1, 0), (0, -1), (0, 1), (-1, -1), (1, -1), (-1, 1), (1, 1)])
    while len(frontier):
        hits = np.isin(goal_cells, frontier)
        if hits.any():
            return int(on_map[np.argmax(hits)])
        expanded += len(frontier)
        if max_iterations is not None and expanded >= max_iterations:
            return None
        fx, fy = frontier % nx, frontier // nx
        x = (fx[:, None] + offsets[:, 0]).ravel()
        y = (fy[:, None] + offsets[:, 1]).ravel()
        ok = (x >= 0) & (x < nx) & (y >= 0) & (y < ny)
        idx = np.unique(y[ok] * nx + x[ok])
        idx = idx[~visited[idx] & free[idx]]
        visited[idx] = True
        frontier = idx
    return None
