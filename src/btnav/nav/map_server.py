"""Nav2's map_server: serves the mission's map (or `yaml_filename`) to the static layers.

`MapServer(params, map=grid, base_dir=...)` holds the map: the one the mission names
wins over `yaml_filename`, as Nav2's launch files do. `load_map(path)` is Nav2's
LoadMap service: the new map goes to every subscriber (the global costmap's static
layer), as the latched `map` topic would deliver it.
"""

from __future__ import annotations

from collections.abc import Callable
from os import PathLike
from pathlib import Path

from ..core.errors import ConfigError
from ..maps.map_io import load_map
from ..maps.occupancy_grid import OccupancyGrid
from ..params.map_io import MapServerParams


class MapServer:
    def __init__(
        self,
        params: MapServerParams | None = None,
        *,
        map: OccupancyGrid | None = None,
        base_dir: str | PathLike[str] | None = None,
    ) -> None:
        self.params = params if params is not None else MapServerParams()
        self._subscribers: list[Callable[[OccupancyGrid], None]] = []
        self.map: OccupancyGrid | None = map
        if map is None and self.params.yaml_filename:
            path = Path(self.params.yaml_filename)
            if not path.is_absolute() and base_dir is not None:
                path = Path(base_dir) / path
            self.map = load_map(path)

    @property
    def frame_id(self) -> str:
        return self.params.frame_id

    def subscribe(self, callback: Callable[[OccupancyGrid], None]) -> None:
        """Call `callback(map)` now (if a map is loaded) and on every new map (a latched topic)."""
        self._subscribers.append(callback)
        if self.map is not None:
            callback(self.map)

    def load_map(self, map_or_path: OccupancyGrid | str | PathLike[str]) -> OccupancyGrid:
        """Nav2's LoadMap service: serve a new map (a grid or a map_server .yaml)."""
        grid = map_or_path if isinstance(map_or_path, OccupancyGrid) else load_map(map_or_path)
        self.map = grid
        for cb in self._subscribers:
            cb(grid)
        return grid

    def require_map(self) -> OccupancyGrid:
        if self.map is None:
            raise ConfigError(
                "map_server has no map: give the mission a `map`, or set "
                "map_server.yaml_filename in the params"
            )
        return self.map
