"""`btnav map from-world WORLD.yaml -o MAP.yaml [--resolution R]`: a world as map_server's map;
`btnav map show MAP.yaml [-o PNG]`: a map as a picture (the viz extra)."""

from __future__ import annotations

from os import PathLike
from pathlib import Path

import numpy as np

from ..maps.map_io import load_map, save_map
from ..maps.occupancy_grid import OCCUPIED
from ..sim.rasterize import rasterize
from ..sim.world_spec import load_world_spec
from . import EXIT_OK


def from_world_main(
    world_path: str | PathLike[str], out_yaml: str | PathLike[str], resolution: float = 0.05
) -> int:
    """Write the map a perfect mapper would make of the world's static scene.

    A mistake in the world file raises its located `BtnavError` (the CLI prints it
    and exits 2); success prints what was written and returns 0.
    """
    spec = load_world_spec(world_path)
    grid = rasterize(spec, resolution)
    save_map(grid, Path(out_yaml))
    occupied = int(np.count_nonzero(grid.data == OCCUPIED))
    print(
        f"wrote {out_yaml}: {grid.width} x {grid.height} cells at {resolution:g} m, "
        f"origin [{grid.origin.x:g}, {grid.origin.y:g}, 0], {occupied} occupied"
    )
    return EXIT_OK


def map_show_main(map_yaml: str | PathLike[str], out_png: str | PathLike[str] | None = None) -> int:
    """Draw the map into `out_png` (default: beside it, `<map>.png`)."""
    from ..viz.map_plot import map_figure
    from .world import save_figure

    path = Path(map_yaml)
    fig = map_figure(load_map(path), title=path.name)
    save_figure(fig, Path(out_png) if out_png is not None else path.with_suffix(".png"))
    return EXIT_OK
