"""Occupancy grids and map_server-compatible map files."""

from .occupancy_grid import FREE, OCCUPIED, UNKNOWN, OccupancyGrid

__all__ = ["FREE", "OCCUPIED", "UNKNOWN", "OccupancyGrid"]
