"""Frontiers on a costmap: where known free space meets unknown space, and which to visit.

explore_lite's frontier search, on whole arrays: a frontier cell is an unknown cell
(NO_INFORMATION) with a 4-neighbour the robot can stand in (known, below INSCRIBED);
frontier cells join into frontiers 8-connected. Unlike explore_lite's straight-line
`min_distance`, a frontier's distance is the cost of the cheapest path to it through
known space (a Dijkstra over the costmap, each step weighted up by the cell's cost as
NavFn weighs it), so a frontier behind a wall is as far as the way round, and one the
robot cannot reach through known space is no frontier at all. Each frontier's goal is
the reachable free cell beside the frontier cell nearest its centroid, facing that
cell. A frontier's cost is explore_lite's: `potential_scale * distance -
gain_scale * size` (metres); the cheapest comes first.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy import ndimage
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra

from ..core.geometry import Pose2D
from ..costmap.cost_values import INSCRIBED_INFLATED_OBSTACLE, NO_INFORMATION
from ..costmap.costmap_2d import Costmap2D

#: A step through a cell of cost c costs (1 + COST_WEIGHT * c / 252) times its length.
COST_WEIGHT = 3.0
#: The 4 neighbours (dy, dx): a frontier cell's goal is one of them.
_NEIGHBOURS_4 = ((0, 1), (1, 0), (0, -1), (-1, 0))
#: The yaw that faces the frontier cell from its goal cell, by neighbour.
_FACING = (math.pi, -math.pi / 2, 0.0, math.pi / 2)
#: Half the 8 neighbours (dy, dx, length in cells); the graph is undirected.
_EDGES = ((0, 1, 1.0), (1, 0, 1.0), (1, 1, 2.0**0.5), (1, -1, 2.0**0.5))


@dataclass(frozen=True)
class Frontier:
    """One frontier: its size, where it is, the goal that visits it and what that costs."""

    size: float  # m: frontier cells times the resolution (explore_lite's size)
    centroid: tuple[float, float]
    goal: Pose2D  # a free cell beside the frontier, facing the unknown
    distance: float  # m: the cheapest path from the robot to `goal`, cost-weighted
    cost: float  # potential_scale * distance - gain_scale * size
    cells: NDArray[np.float64]  # (k, 2) world x, y of its frontier cells


def find_frontiers(
    costmap: Costmap2D,
    robot: tuple[float, float],
    *,
    min_frontier_size: float,
    potential_scale: float,
    gain_scale: float,
    blacklist: Sequence[tuple[float, float]] = (),
    blacklist_radius: float = 0.5,
) -> list[Frontier]:
    """Every reachable frontier at least `min_frontier_size` long, cheapest first.

    A frontier whose goal lies within `blacklist_radius` of a blacklisted point is left
    out (explore_lite's blacklist of frontiers the robot failed to reach).
    """
    costs = costmap.costs
    known = costs != NO_INFORMATION
    if not known.any():
        return []
    # Work on the known part only (padded by a cell): the rest holds no frontier.
    rows, cols = np.nonzero(known)
    r0, r1 = max(int(rows.min()) - 1, 0), min(int(rows.max()) + 2, costs.shape[0])
    c0, c1 = max(int(cols.min()) - 1, 0), min(int(cols.max()) + 2, costs.shape[1])
    sub = costs[r0:r1, c0:c1]
    res = costmap.resolution
    ox, oy = costmap.origin_x + c0 * res, costmap.origin_y + r0 * res

    passable = sub < INSCRIBED_INFLATED_OBSTACLE
    start = _robot_cell(robot, ox, oy, res, sub.shape)
    if start is None or not passable.any():
        return []
    if not passable[start]:
        # A robot in an inflated ring (pushed there, or its footprint padded more than
        # its body) searches from the nearest cell it could stand in, as explore_lite's
        # nearestCell: from its own cell every neighbour would be blocked, and the whole
        # map would look explored.
        _, (iy, ix) = ndimage.distance_transform_edt(~passable, return_indices=True)
        start = (int(iy[start]), int(ix[start]))
    dist = _path_costs(sub, passable, start, res)

    # frontier cells, and the cheapest passable 4-neighbour of each (its goal cell)
    unknown = sub == NO_INFORMATION
    best = np.full(sub.shape, np.inf)
    best_dir = np.full(sub.shape, -1, dtype=np.int8)
    for k, (dy, dx) in enumerate(_NEIGHBOURS_4):
        shifted = _shift(dist, dy, dx, np.inf)
        better = unknown & (shifted < best)
        best[better] = shifted[better]
        best_dir[better] = k
    frontier = best_dir >= 0  # unknown, beside a cell the robot can reach
    labels, count = ndimage.label(frontier, structure=np.ones((3, 3), dtype=bool))
    if count == 0:
        return []

    fy, fx = np.nonzero(labels)
    lab = labels[fy, fx] - 1
    size_cells = np.bincount(lab, minlength=count)
    cx = (np.bincount(lab, weights=fx, minlength=count) / size_cells + 0.5) * res + ox
    cy = (np.bincount(lab, weights=fy, minlength=count) / size_cells + 0.5) * res + oy
    wx, wy = (fx + 0.5) * res + ox, (fy + 0.5) * res + oy
    # per frontier: its cell nearest its centroid
    d2 = (wx - cx[lab]) ** 2 + (wy - cy[lab]) ** 2
    order = np.lexsort((fx, fy, d2, lab))
    first = order[np.r_[True, lab[order][1:] != lab[order][:-1]]]

    out = []
    for i in first:  # one per frontier (a handful), not per cell
        f = int(lab[i])
        size = float(size_cells[f]) * res
        if size < min_frontier_size:
            continue
        dy, dx = _NEIGHBOURS_4[int(best_dir[fy[i], fx[i]])]
        gy, gx = int(fy[i]) + dy, int(fx[i]) + dx
        gxy = ((gx + 0.5) * res + ox, (gy + 0.5) * res + oy)
        if any(
            (gxy[0] - bx) ** 2 + (gxy[1] - by) ** 2 <= blacklist_radius**2 for bx, by in blacklist
        ):
            continue
        yaw = _FACING[int(best_dir[fy[i], fx[i]])]
        distance = float(dist[gy, gx])
        mine = lab == f
        out.append(
            Frontier(
                size=size,
                centroid=(float(cx[f]), float(cy[f])),
                goal=Pose2D(gxy[0], gxy[1], yaw),
                distance=distance,
                cost=potential_scale * distance - gain_scale * size,
                cells=np.column_stack((wx[mine], wy[mine])),
            )
        )
    out.sort(key=lambda fr: (fr.cost, fr.goal.x, fr.goal.y))
    return out


def _robot_cell(
    robot: tuple[float, float], ox: float, oy: float, res: float, shape: tuple[int, ...]
) -> tuple[int, int] | None:
    mx = int(np.floor((robot[0] - ox) / res))
    my = int(np.floor((robot[1] - oy) / res))
    if 0 <= my < shape[0] and 0 <= mx < shape[1]:
        return my, mx
    return None


def _path_costs(
    costs: NDArray[np.uint8], passable: NDArray[np.bool_], start: tuple[int, int], res: float
) -> NDArray[np.float64]:
    """The cheapest cost-weighted path length (m) from `start` to every passable cell."""
    n = int(passable.sum())
    index = np.full(costs.shape, -1, dtype=np.int64)
    index[passable] = np.arange(n)
    weight = 1.0 + COST_WEIGHT * np.minimum(costs, 252).astype(float) / 252.0
    src, dst, w = [], [], []
    for dy, dx, length in _EDGES:
        a, b = _neighbours(passable, dy, dx)
        both = a & b
        ia, ib = (v[both] for v in _neighbours(index, dy, dx))
        wa, wb = (v[both] for v in _neighbours(weight, dy, dx))
        src.append(ia)
        dst.append(ib)
        w.append(0.5 * (wa + wb) * (length * res))
    graph = coo_matrix((np.concatenate(w), (np.concatenate(src), np.concatenate(dst))), (n, n))
    along = dijkstra(graph.tocsr(), directed=False, indices=int(index[start]))
    out = np.full(costs.shape, np.inf)
    out[passable] = along
    return out


def _neighbours(a: NDArray[Any], dy: int, dx: int) -> tuple[NDArray[Any], NDArray[Any]]:
    """Two views of `a` of one shape: each cell, and its neighbour (dy, dx) at the same place."""
    ny, nx = a.shape
    here = a[max(-dy, 0) : ny - max(dy, 0), max(-dx, 0) : nx - max(dx, 0)]
    there = a[max(dy, 0) : ny - max(-dy, 0), max(dx, 0) : nx - max(-dx, 0)]
    return here, there


def _shift(a: NDArray[np.float64], dy: int, dx: int, fill: float) -> NDArray[np.float64]:
    """`out[y, x] = a[y + dy, x + dx]` (fill off the grid)."""
    out = np.full_like(a, fill)
    _neighbours(out, dy, dx)[0][...] = _neighbours(a, dy, dx)[1]
    return out
