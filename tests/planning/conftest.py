"""Costmaps for planner tests: hand-made ones and a crop of Nav2's benchmark map."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy.ndimage import distance_transform_edt

from btnav.costmap.costmap_2d import Costmap2D
from btnav.maps import load_map


def inflate(
    costs: np.ndarray, resolution: float, inscribed: float, radius: float, scale: float
) -> np.ndarray:
    """Nav2's inflation (exponential decay from the inscribed radius), for test costmaps."""
    lethal = costs == 254
    d = distance_transform_edt(~lethal) * resolution
    out = np.where(d <= inscribed, 253, np.floor(252 * np.exp(-scale * (d - inscribed)))).astype(
        np.int64
    )
    out[d > radius] = 0
    out[lethal] = 254
    return np.maximum(out, costs).astype(np.uint8)


@pytest.fixture(scope="session")
def benchmark_costmap(nav2_dir: Path) -> Costmap2D:
    """A 400 x 400 crop of 100by100_20 (lethal 254 / free 0) at 0.05 m."""
    grid = load_map(nav2_dir / "benchmark_maps" / "100by100_20.yaml")
    crop = grid.data[800:1200, 800:1200]
    costs = np.where(crop >= 65, 254, 0).astype(np.uint8)
    return Costmap2D(costs, grid.resolution, 40.0, 40.0)
