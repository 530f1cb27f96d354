"""A map_server map as a picture: `btnav map show MAP.yaml -o map.png`.

Free, occupied and unknown cells in map_saver's greys (white, black, grey), in metres
of the map frame, titled with its size, resolution and the free area it holds: the
look a user takes at a map SLAM just made before sending the robot onto it.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..maps.occupancy_grid import FREE, OCCUPIED, OccupancyGrid
from .world_plot import _matplotlib

if TYPE_CHECKING:
    from matplotlib.figure import Figure

#: Grey levels of free, unknown and occupied cells (map_saver's trinary PGM).
SHADES = {FREE: 0.97, OCCUPIED: 0.1}
UNKNOWN_SHADE = 0.6


def map_figure(grid: OccupancyGrid, title: str = "") -> Figure:
    """The map on a bare Agg `Figure`, ready to save (a map origin's yaw is not drawn)."""
    _matplotlib()
    from matplotlib.figure import Figure

    shade = np.full(grid.data.shape, UNKNOWN_SHADE)
    for value, grey in SHADES.items():
        shade[grid.data == value] = grey
    h, w = grid.data.shape
    x0, y0 = grid.origin.x, grid.origin.y
    extent = (x0, x0 + w * grid.resolution, y0, y0 + h * grid.resolution)
    scale = 9.0 / max(extent[1] - extent[0], extent[3] - extent[2])
    fig = Figure(
        figsize=(
            max(4.0, (extent[1] - extent[0]) * scale + 1.0),
            max(3.0, (extent[3] - extent[2]) * scale + 0.9),
        )
    )
    ax = fig.add_subplot()
    ax.imshow(
        shade,
        cmap="gray",
        vmin=0.0,
        vmax=1.0,
        origin="lower",
        extent=extent,
        interpolation="nearest",
    )
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    free = float(np.count_nonzero(grid.data == FREE)) * grid.resolution**2
    ax.set_title(
        (f"{title}: " if title else "")
        + f"{w} x {h} cells at {grid.resolution:g} m, {free:.1f} m² free",
        fontsize=10,
    )
    fig.tight_layout()
    return fig
