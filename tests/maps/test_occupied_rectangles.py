"""A map's occupied cells as rectangles: exactly the cells, few shapes, on Nav2's own maps."""

from __future__ import annotations

import numpy as np
import pytest

from btnav.maps import load_map
from btnav.maps.occupied_rectangles import occupied_rectangles

from ..conftest import SHARED_NAV2

NAV2_MAPS = SHARED_NAV2 / "maps"


def cover(rects: np.ndarray, shape: tuple[int, int]) -> np.ndarray:
    """How many rectangles cover each cell."""
    out = np.zeros(shape, dtype=int)
    for r0, c0, r1, c1 in rects:
        out[r0:r1, c0:c1] += 1
    return out


@pytest.mark.parametrize(
    ("name", "most"), [("tb3_sandbox", 300), ("depot", 1500), ("warehouse", 3000)]
)
def test_nav2_maps_become_few_rectangles_covering_exactly_their_occupied_cells(name, most):
    grid = load_map(NAV2_MAPS / f"{name}.yaml")
    occupied = grid.data >= 65
    rects = occupied_rectangles(occupied)
    counts = cover(rects, occupied.shape)
    assert np.array_equal(counts > 0, occupied)
    assert counts.max() == 1  # no overlap
    assert len(rects) <= most and len(rects) < occupied.sum() / 4


def test_a_filled_room_is_one_rectangle_and_an_l_is_two():
    block = np.zeros((10, 12), bool)
    block[2:7, 3:9] = True
    assert occupied_rectangles(block).tolist() == [[2, 3, 7, 9]]
    ell = np.zeros((5, 5), bool)
    ell[0:4, 0] = True
    ell[0, 0:4] = True
    assert occupied_rectangles(ell).tolist() == [[0, 0, 1, 4], [1, 0, 4, 1]]
    assert occupied_rectangles(np.zeros((3, 3), bool)).shape == (0, 4)
