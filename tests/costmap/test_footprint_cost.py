"""The footprint's cost at a pose, as Nav2's FootprintCollisionChecker finds it: the highest
cost on the oriented outline, each edge rasterised with Bresenham's line between its
vertices' cells; a vertex off the map is LETHAL; the inside does not count."""

from __future__ import annotations

import math

import numpy as np

from btnav.costmap.cost_values import LETHAL_OBSTACLE, NO_INFORMATION
from btnav.costmap.costmap_2d import Costmap2D
from btnav.costmap.footprint_cost import footprint_costs

RECT = np.array([[0.5, 0.15], [0.5, -0.15], [-0.5, -0.15], [-0.5, 0.15]])


def grid() -> Costmap2D:
    cm = Costmap2D.empty(100, 100, 0.05, 0.0, 0.0)
    cm.costs[:] = 0
    return cm


def line_iterator(x0: int, y0: int, x1: int, y1: int) -> list[tuple[int, int]]:
    """nav2_util::LineIterator, step by step (the reference)."""
    dx, dy = abs(x1 - x0), abs(y1 - y0)
    sx, sy = (1 if x1 >= x0 else -1), (1 if y1 >= y0 else -1)
    x, y, cells = x0, y0, []
    if dx >= dy:
        num, den, add, n = dx // 2, dx, dy, dx
        for _ in range(n + 1):
            cells.append((x, y))
            num += add
            if num >= den:
                num -= den
                y += sy
            x += sx
    else:
        num, den, add, n = dy // 2, dy, dx, dy
        for _ in range(n + 1):
            cells.append((x, y))
            num += add
            if num >= den:
                num -= den
                x += sx
            y += sy
    return cells


def reference_cost(cm: Costmap2D, fp: np.ndarray, x: float, y: float, yaw: float) -> int:
    c, s = math.cos(yaw), math.sin(yaw)
    pts = [(x + px * c - py * s, y + px * s + py * c) for px, py in fp]
    cells = [
        (int((wx - cm.origin_x) / cm.resolution), int((wy - cm.origin_y) / cm.resolution))
        for wx, wy in pts
    ]
    cost = 0
    for (x0, y0), (x1, y1) in zip(cells, cells[1:] + cells[:1], strict=True):
        for cx, cy in line_iterator(x0, y0, x1, y1):
            cost = max(cost, int(cm.costs[cy, cx]))
    return cost


def test_matches_nav2s_line_iterator_on_random_costs_and_poses():
    rng = np.random.default_rng(3)
    cm = grid()
    cm.costs[:] = rng.integers(0, 253, cm.costs.shape)
    n = 300
    x, y = rng.uniform(1.0, 4.0, n), rng.uniform(1.0, 4.0, n)
    yaw = rng.uniform(-math.pi, math.pi, n)
    got = footprint_costs(cm, RECT, x, y, yaw)
    want = [reference_cost(cm, RECT, *pose) for pose in zip(x, y, yaw, strict=True)]
    assert got.tolist() == want


def test_only_the_outline_counts_and_lethal_wins():
    cm = grid()
    cm.costs[50, 50] = LETHAL_OBSTACLE  # under the centre: inside, not on the outline
    assert footprint_costs(cm, RECT, [2.525], [2.525], [0.0]).tolist() == [0]
    cm.costs[50, 60] = LETHAL_OBSTACLE  # under the front edge
    cm.costs[50, 40] = NO_INFORMATION  # under the back edge
    assert footprint_costs(cm, RECT, [2.525], [2.525], [0.0]).tolist() == [LETHAL_OBSTACLE]


def test_a_vertex_off_the_map_is_lethal():
    cm = grid()
    assert footprint_costs(cm, RECT, [0.3, 2.5], [2.5, 2.5], [0.0, 0.0]).tolist() == [
        LETHAL_OBSTACLE,
        0,
    ]


def test_keeps_the_shape_of_the_poses():
    cm = grid()
    x = np.full((3, 4), 2.5)
    assert footprint_costs(cm, RECT, x, x, np.zeros((3, 4))).shape == (3, 4)
    none = np.zeros((2, 0))
    assert footprint_costs(cm, RECT, none, none, none).shape == (2, 0)
