"""The inflation layer's update compiled with numba, with its numpy path's costs.

InflationLayer.update_costs finds every window cell's nearest seed (a LETHAL cell, or
unknown with `inflate_around_unknown`) with scipy's exact Euclidean feature transform,
then looks its squared distance up in the cost table. On the local costmap's 60 x 60
cells that is ~0.15 ms, most of it fixed costs of scipy and of ~20 numpy passes; on the
global costmap's windows (150 x 120 cells) ~1 ms. Only distances up to the inflation
radius r (in cells) matter, so here the exact squared distance is found within r and
capped beyond it, in two separable passes: down each column of the region (the window
and r + 1 cells round it, as the numpy path reads) the rows to the nearest seed, then
along each window row the least dx^2 + dy^2 over |dx| <= r. The costs are written only
once every distance is known (a write can make a LETHAL cell, a seed). A squared distance is an
integer, the same whichever seed is nearest, so the table gives the numpy path's cost
and the same rule writes it (tests/costmap/test_inflation_kernel.py compares both).

`cache=True`, integers only, no fastmath, no parallel.
"""

from __future__ import annotations

import numba as nb
import numpy as np
from numpy.typing import NDArray

from ..core.fmath_kernels import JIT
from .cost_values import (
    FREE_SPACE,
    INSCRIBED_INFLATED_OBSTACLE,
    LETHAL_OBSTACLE,
    NO_INFORMATION,
)


@nb.njit(**JIT)
def inflate_window(
    costs: NDArray[np.uint8],
    x0: int,
    y0: int,
    xn: int,
    yn: int,
    r: int,
    table: NDArray[np.uint8],
    around_unknown: bool,
    inflate_unknown: bool,
) -> None:
    """InflationLayer.update_costs on cells [x0, xn) x [y0, yn) of `costs`, with the
    cost `table` of each squared cell distance 0 .. r*r (FREE beyond)."""
    ny, nx = costs.shape
    rx0, ry0 = max(x0 - r - 1, 0), max(y0 - r - 1, 0)
    rxn, ryn = min(xn + r + 1, nx), min(yn + r + 1, ny)
    h, w = ryn - ry0, rxn - rx0
    far = r + 1
    # dy^2 to the nearest seed in the same column (far^2 if farther than r), for the
    # window's rows, each padded with r cells of far^2 on both sides; row by row, with
    # the last seed row of each column above, then below
    rows = yn - y0
    g2 = np.full((rows, w + 2 * r), far * far, np.int64)
    above = np.empty((h, w), np.int64)
    last = np.full(w, -far, np.int64)
    for y in range(h):
        for c in range(w):
            v = costs[ry0 + y, rx0 + c]
            if v == LETHAL_OBSTACLE or (around_unknown and v == NO_INFORMATION):
                last[c] = y
            above[y, c] = min(y - last[c], far)
    below = np.full(w, h + far, np.int64)
    for y in range(h - 1, -1, -1):
        row = ry0 + y - y0
        for c in range(w):
            v = costs[ry0 + y, rx0 + c]
            if v == LETHAL_OBSTACLE or (around_unknown and v == NO_INFORMATION):
                below[c] = y
            if 0 <= row < rows:
                d = min(above[y, c], below[c] - y)
                g2[row, r + c] = d * d
    # along the rows: the least dx^2 + dy^2 over |dx| <= r (no farther column can do
    # better once dx^2 reaches the best so far)
    first = r + x0 - rx0  # the window's first column in the padded rows
    last_entry = table.size - 1
    threshold = FREE_SPACE + 1 if inflate_unknown else INSCRIBED_INFLATED_OBSTACLE
    for row in range(rows):
        g = g2[row]
        y = y0 + row
        for j in range(xn - x0):
            c = first + j
            squared = g[c]
            dx = 1
            while dx <= r and dx * dx < squared:
                side = min(g[c - dx], g[c + dx]) + dx * dx
                if side < squared:
                    squared = side
                dx += 1
            if squared > r * r:
                continue  # not near: nothing to write
            cost = table[min(squared, last_entry)]
            old = costs[y, x0 + j]
            take = cost >= threshold if old == NO_INFORMATION else cost > old
            if take:
                costs[y, x0 + j] = cost
