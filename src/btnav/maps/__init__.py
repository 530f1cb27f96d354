"""Occupancy grids and map_server-compatible map files (YAML + PGM/PNG)."""

from .image_io import IMAGE_FORMATS, MapImage, read_image, write_image
from .map_io import MapFile, load_map, map_yaml_text, read_map, save_map
from .map_mode import MAP_MODES, MapMode, grid_to_image, image_to_grid, occupancy_lut
from .metadata import MapMetadata, metadata_from_doc, read_map_metadata
from .occupancy_grid import FREE, OCCUPIED, UNKNOWN, OccupancyGrid
from .pgm import PgmImage, decode_pgm, encode_pgm, read_pgm, write_pgm

__all__ = [
    "FREE",
    "IMAGE_FORMATS",
    "MAP_MODES",
    "OCCUPIED",
    "UNKNOWN",
    "MapFile",
    "MapImage",
    "MapMetadata",
    "MapMode",
    "OccupancyGrid",
    "PgmImage",
    "decode_pgm",
    "encode_pgm",
    "grid_to_image",
    "image_to_grid",
    "load_map",
    "map_yaml_text",
    "metadata_from_doc",
    "occupancy_lut",
    "read_image",
    "read_map",
    "read_map_metadata",
    "read_pgm",
    "save_map",
    "write_image",
    "write_pgm",
]
