"""Pixels <-> occupancy values, exactly as Nav2's map_server reads and map_saver writes them.

The semantics are those of Nav2's `nav2_map_server/src/map_io.cpp` (main branch, the
version the maps in `shared/nav2` come from) for `trinary`, `scale` and `raw`, reading
through 8-bit grey (as GraphicsMagick does) in float32 as map_server's Eigen code. Image
row 0 is the top of the picture, grid row 0 the bottom (the map origin), so both
directions flip rows. Conversion goes through a 256-entry lookup table: exact per-pixel
semantics at numpy speed. The rules per mode: docs/decisions/0019.
"""

from __future__ import annotations

from typing import Literal

import numpy as np
from numpy.typing import NDArray

MapMode = Literal["trinary", "scale", "raw"]
MAP_MODES: tuple[MapMode, ...] = ("trinary", "scale", "raw")

#: The grey values map_saver writes in trinary mode.
TRINARY_FREE = 254
TRINARY_OCCUPIED = 0
TRINARY_UNKNOWN = 205


def _round_half_away(x: NDArray[np.float32]) -> NDArray[np.float32]:
    """std::round for non-negative float32 values, without float rounding in `x + 0.5`."""
    floor = np.floor(x)
    return floor + (x - floor >= np.float32(0.5))


def occupancy_lut(
    mode: MapMode, *, negate: bool, free_thresh: float, occupied_thresh: float
) -> NDArray[np.int8]:
    """The occupancy value of each 8-bit grey level (alpha not considered)."""
    levels = np.arange(256)
    if mode == "raw":
        return np.where(levels <= 100, levels, -1).astype(np.int8)
    grey = levels.astype(np.float32) / np.float32(255.0)
    n = grey if negate else np.float32(1.0) - grey
    occ_t = np.float32(occupied_thresh)
    free_t = np.float32(free_thresh)
    out = np.full(256, -1, dtype=np.int8)
    out[n >= occ_t] = 100
    out[n <= free_t] = 0
    if mode == "scale":
        between = (n > free_t) & (n < occ_t)
        if between.any():
            span = np.float32(occupied_thresh - free_thresh)
            scaled = ((n[between] - free_t) / span) * np.float32(100.0)
            out[between] = _round_half_away(scaled).astype(np.int8)
    return out


def image_to_grid(
    grey: NDArray[np.uint8],
    alpha: NDArray[np.uint8] | None,
    *,
    mode: MapMode,
    negate: bool,
    free_thresh: float,
    occupied_thresh: float,
) -> NDArray[np.int8]:
    """Occupancy grid data (row 0 = bottom) from an 8-bit grey image (row 0 = top)."""
    lut = occupancy_lut(
        mode, negate=negate, free_thresh=free_thresh, occupied_thresh=occupied_thresh
    )
    cells = lut[grey]
    if alpha is not None and mode != "raw":
        cells[alpha < 255] = -1
    return np.ascontiguousarray(cells[::-1])


def _saver_lut(mode: MapMode, free_thresh: float, occupied_thresh: float) -> NDArray[np.uint8]:
    """The grey value map_saver writes for each int8 cell value (indexed by value + 128)."""
    values = np.arange(-128, 128)
    valid = (values >= 0) & (values <= 100)
    if mode == "trinary":
        free_i = int(np.rint(free_thresh * 100.0))
        occ_i = int(np.rint(occupied_thresh * 100.0))
        grey = np.full(256, TRINARY_UNKNOWN)
        is_free = valid & (values <= free_i)
        grey[is_free] = TRINARY_FREE
        grey[valid & ~is_free & (values >= occ_i)] = TRINARY_OCCUPIED
    elif mode == "scale":
        shade = (100.0 - values) / 100.0
        quantum = np.trunc(shade.clip(0.0, 1.0) * 65535.0).astype(np.int64)  # ColorGray, Q16
        grey = np.where(valid, quantum // 257, int(0.5 * 65535.0) // 257)
    else:
        grey = np.where(valid, values, 255)
    return grey.astype(np.uint8)


def grid_to_image(
    data: NDArray[np.int8], *, mode: MapMode, free_thresh: float, occupied_thresh: float
) -> tuple[NDArray[np.uint8], NDArray[np.uint8] | None]:
    """The 8-bit grey image (row 0 = top) and, in scale mode, the alpha map_saver writes."""
    flipped = np.asarray(data, dtype=np.int8)[::-1]
    index = flipped.astype(np.int16) + 128
    grey = _saver_lut(mode, free_thresh, occupied_thresh)[index]
    alpha = None
    if mode == "scale":
        alpha = np.where((flipped >= 0) & (flipped <= 100), 255, 0).astype(np.uint8)
    return np.ascontiguousarray(grey), alpha
