"""The files btnav ships stay in step with what they are made from."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from btnav.maps import load_map
from btnav.sim.rasterize import rasterize
from btnav.sim.world import World

REPO = Path(__file__).resolve().parents[1]


def test_small_office_map_is_the_rasterised_world():
    shipped = load_map(REPO / "maps" / "small_office.yaml")
    fresh = rasterize(World.from_file(REPO / "worlds" / "small_office.yaml"), resolution=0.05)
    assert shipped.resolution == fresh.resolution
    assert np.allclose(shipped.origin.as_array(), fresh.origin.as_array())
    assert np.array_equal(shipped.data, fresh.data), (
        "maps/small_office.* is stale: btnav map from-world worlds/small_office.yaml "
        "-o maps/small_office.yaml"
    )


def test_params_nav2_params_is_nav2s_file_byte_for_byte(nav2_params_file):
    assert (REPO / "params" / "nav2_params.yaml").read_bytes() == nav2_params_file.read_bytes()
