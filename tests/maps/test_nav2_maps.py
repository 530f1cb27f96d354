"""Every map Nav2 ships loads as map_server loads it, and survives a save-then-load."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from btnav.maps import load_map, read_map, read_pgm, save_map

# name: (width, height, resolution, origin, mode, negate)
NAV2_MAPS = {
    "maps/depot": (604, 307, 0.05, (0.0, 0.0, 0.0), "trinary", False),
    "maps/depot_keepout": (604, 307, 0.05, (0.0, 0.0, 0.0), "trinary", False),
    "maps/depot_speed": (604, 307, 0.05, (0.0, 0.0, 0.0), "scale", False),
    "maps/tb3_sandbox": (384, 384, 0.05, (-10.0, -10.0, 0.0), "trinary", False),
    "maps/warehouse": (1006, 1674, 0.03, (-15.1, -25.0, 0.0), "trinary", False),
    "maps/warehouse_keepout": (1006, 1674, 0.03, (-15.1, -25.0, 0.0), "trinary", False),
    "maps/warehouse_speed": (1006, 1674, 0.03, (-15.1, -25.0, 0.0), "scale", False),
    "benchmark_maps/100by100_10": (2000, 2000, 0.05, (0.0, 0.0, 0.0), "trinary", True),
    "benchmark_maps/100by100_20": (2000, 2000, 0.05, (0.0, 0.0, 0.0), "trinary", True),
    "benchmark_maps/smoothers_world": (300, 300, 0.05, (0.0, 0.0, 0.0), "trinary", False),
}

# What each grey level of the picture must become, per map (map_server's rules with the
# thresholds in each YAML; Pillow decodes the picture independently of btnav).
EXPECTED_LEVELS = {
    # free_thresh 0.25: map_saver's "unknown" grey 205 (occ 0.196) reads as free here.
    "maps/depot": {0: 100, 205: 0, 254: 0},
    "maps/depot_keepout": {0: 100, 205: 0, 254: 0},
    # scale with thresholds 0 and 1: the value is round((1 - grey/255) * 100).
    "maps/depot_speed": {0: 100, 127: 50, 191: 25, 205: 20, 254: 0},
    # no `mode` key: trinary; free_thresh 0.196 keeps 205 unknown.
    "maps/tb3_sandbox": {0: 100, 205: -1, 254: 0},
    "maps/warehouse": {0: 100, 205: -1, 254: 0, 255: 0},
    "maps/warehouse_keepout": {0: 100, 205: -1, 254: 0, 255: 0},
    "maps/warehouse_speed": {0: 100, 204: 20, 205: 20, 254: 0, 255: 0},
    # negate: 1 -> black is free, white occupied.
    "benchmark_maps/100by100_10": {0: 0, 255: 100},
    "benchmark_maps/100by100_20": {0: 0, 255: 100},
    "benchmark_maps/smoothers_world": {0: 100, 8: 100, 19: 100, 255: 0},
}


@pytest.fixture(params=sorted(NAV2_MAPS))
def nav2_map(request: pytest.FixtureRequest, nav2_dir: Path) -> tuple[str, Path]:
    return request.param, nav2_dir / f"{request.param}.yaml"


def test_every_nav2_map_is_covered(nav2_dir: Path) -> None:
    found = {
        f"{p.parent.name}/{p.stem}"
        for folder in ("maps", "benchmark_maps")
        for p in (nav2_dir / folder).glob("*.yaml")
    }
    assert found == set(NAV2_MAPS)


def test_nav2_map_loads_with_its_size_resolution_origin(nav2_map: tuple[str, Path]) -> None:
    name, yaml_path = nav2_map
    width, height, resolution, origin, mode, negate = NAV2_MAPS[name]
    loaded = read_map(yaml_path)
    grid = loaded.grid
    assert (grid.width, grid.height) == (width, height)
    assert grid.resolution == resolution
    assert tuple(grid.origin) == origin
    assert loaded.metadata.mode == mode
    assert loaded.metadata.negate is negate
    assert loaded.image_path == yaml_path.with_suffix(".pgm")
    assert grid.data.dtype == np.int8 and grid.data.flags.c_contiguous


def test_nav2_map_pixels_map_as_map_server_reads_them(nav2_map: tuple[str, Path]) -> None:
    name, yaml_path = nav2_map
    picture = np.asarray(Image.open(yaml_path.with_suffix(".pgm")))
    expected = EXPECTED_LEVELS[name]
    assert set(np.unique(picture).tolist()) == set(expected)
    lut = np.zeros(256, dtype=np.int8)
    for grey, value in expected.items():
        lut[grey] = value
    grid = load_map(yaml_path)
    # Image row 0 is the top of the picture, grid row 0 the bottom (the map origin).
    np.testing.assert_array_equal(grid.data, lut[picture[::-1]])


def test_tb3_sandbox_corners_and_origin(nav2_dir: Path) -> None:
    grid = load_map(nav2_dir / "maps" / "tb3_sandbox.yaml")
    assert grid.data[0, 0] == -1  # the corners of the sandbox are unexplored
    row, col = grid.world_to_cell([[-10.0 + 0.025, -10.0 + 0.025]])[0]
    assert (row, col) == (0, 0)
    # The world origin lies inside the explored arena (the sandbox is centred on it).
    r0, c0 = grid.world_to_cell([[0.0, 0.0]])[0]
    assert (r0, c0) == (200, 200)
    rows, cols = np.nonzero(grid.data >= 0)
    assert rows.min() < r0 < rows.max() and cols.min() < c0 < cols.max()


def test_nav2_map_resaves_exactly(nav2_map: tuple[str, Path], tmp_path: Path) -> None:
    name, yaml_path = nav2_map
    grid = load_map(yaml_path)
    if NAV2_MAPS[name][4] == "scale":
        saved, image = save_map(
            grid, tmp_path / "copy.yaml", mode="scale", free_thresh=0.0, occupied_thresh=1.0
        )
        assert image.suffix == ".png"
    else:
        saved, image = save_map(grid, tmp_path / "copy.yaml")
        assert image.suffix == ".pgm"
    assert load_map(saved) == grid


def test_tb3_sandbox_resaved_raster_is_byte_identical(nav2_dir: Path, tmp_path: Path) -> None:
    """The sandbox was made by map_saver: 254/205/0 come back as the same bytes."""
    original = nav2_dir / "maps" / "tb3_sandbox.pgm"
    _, image = save_map(load_map(original.with_suffix(".yaml")), tmp_path / "sandbox.yaml")
    assert image.read_bytes().startswith(b"P5\n384 384\n255\n")
    np.testing.assert_array_equal(read_pgm(image).data, read_pgm(original).data)
