"""Load and save maps exactly as Nav2's map_server and map_saver do.

A map is a YAML file (see `metadata`) beside an image (PGM natively, PNG/BMP via
Pillow). `load_map` gives the `OccupancyGrid`; `read_map` also gives the metadata
and the resolved paths. `save_map` writes what map_saver writes (same grey values,
same YAML keys in the same order, same number formatting), so a map saved here
loads in Nav2 and the other way round.

Where map_saver's fixed 3-decimal formatting would change a value (a resolution of
0.0125, an origin of 0.0001), btnav writes the shortest exact decimal instead, so
save-then-load always gives back the same resolution and origin.
"""

from __future__ import annotations

import json
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from os import PathLike
from pathlib import Path

import numpy as np

from ..core.errors import BtnavError, MapError
from ..core.geometry import Pose2D, normalize_angle
from ..core.suggest import best_match
from ..core.yaml_io import line_at, load_yaml, load_yaml_text
from .image_io import IMAGE_FORMATS, read_image, write_image
from .map_mode import MAP_MODES, MapMode, grid_to_image, image_to_grid
from .metadata import MapMetadata, metadata_from_doc
from .occupancy_grid import OccupancyGrid

#: The thresholds map_saver writes into every trinary YAML: they separate its fixed
#: grey values 254 (free), 205 (unknown) and 0 (occupied) whatever thresholds were
#: used to classify the cells.
TRINARY_YAML_OCCUPIED_THRESH = 0.65
TRINARY_YAML_FREE_THRESH = 0.196


@dataclass(frozen=True)
class MapFile:
    """A loaded map: the grid, the YAML as validated, and where both files are."""

    grid: OccupancyGrid
    metadata: MapMetadata
    yaml_path: Path
    image_path: Path


def read_map(yaml_path: str | PathLike[str]) -> MapFile:
    """Load a map_server map: YAML, then image, then pixels -> occupancy per `mode`."""
    path = Path(yaml_path).expanduser()  # map_server expands a leading `~/` too
    try:
        doc = load_yaml(path)
    except BtnavError as exc:  # a YamlError (missing file, bad YAML): a map problem here
        raise MapError(exc.message, file=exc.file, line=exc.line, key=exc.key) from None
    meta = metadata_from_doc(doc, file=str(path))
    image_path = meta.image_path(path)
    problem = _not_a_file(image_path)
    if problem:
        raise MapError(
            f"the map image {image_path} {problem}",
            file=path,
            line=line_at(doc, ["image"]),
            key="image",
        )
    image = read_image(image_path)
    data = image_to_grid(
        image.grey,
        image.alpha,
        mode=meta.mode,
        negate=meta.negate,
        free_thresh=meta.free_thresh,
        occupied_thresh=meta.occupied_thresh,
    )
    x, y, yaw = meta.origin
    grid = OccupancyGrid(data, meta.resolution, Pose2D(x, y, yaw))
    return MapFile(grid, meta, path, image_path)


def _not_a_file(path: Path) -> str | None:
    """Why `path` cannot be read as an image file (None when it can be tried)."""
    try:
        if path.is_file():
            return None
        if path.is_dir():
            return "is a directory, not an image"
        return "is not a regular file" if path.exists() else "does not exist"
    except OSError as exc:  # a name too long, a loop of links, ...
        return f"cannot be opened ({exc.strerror or exc})"


def load_map(yaml_path: str | PathLike[str]) -> OccupancyGrid:
    """The occupancy grid of a map_server map (`read_map` for the metadata too)."""
    return read_map(yaml_path).grid


def _yaml_number(value: float, fmt: str, read_back: Callable[[float], float] = float) -> str:
    """map_saver's text for `value` when it loads back exactly, else the shortest exact one.

    `read_back` is what loading does to the number (a yaw goes through `Pose2D`'s
    normalisation), so the test is "the reloaded grid is equal", not "the text is".
    """
    value = float(value) + 0.0  # no "-0.000"
    text = format(value, fmt)
    if read_back(float(text)) == value:
        return text
    return np.format_float_positional(value, unique=True, trim="0")


def _yaml_string(value: str) -> str:
    """Plain when it reads back as the same string (as yaml-cpp emits it), else quoted."""
    try:
        if load_yaml_text(f"image: {value}") == {"image": value}:
            return value
    except BtnavError:
        pass
    return json.dumps(value, ensure_ascii=False)


def map_yaml_text(
    image_name: str,
    *,
    mode: MapMode,
    resolution: float,
    origin: Pose2D,
    free_thresh: float,
    occupied_thresh: float,
) -> str:
    """The YAML map_saver writes: its key order, its number formats, no final newline."""
    if mode == "trinary":
        occ_text, free_text = str(TRINARY_YAML_OCCUPIED_THRESH), str(TRINARY_YAML_FREE_THRESH)
    else:
        occ_text = _yaml_number(occupied_thresh, ".3f")
        free_text = _yaml_number(free_thresh, ".3f")
    x = _yaml_number(origin.x, ".3f")
    y = _yaml_number(origin.y, ".3f")
    yaw = _yaml_number(origin.yaw, ".7g", read_back=normalize_angle)
    lines = [
        f"image: {_yaml_string(image_name)}",
        f"mode: {mode}",
        f"resolution: {_yaml_number(resolution, '.3f')}",
        f"origin: [{x}, {y}, {yaw}]",
        "negate: 0",
        f"occupied_thresh: {occ_text}",
        f"free_thresh: {free_text}",
    ]
    return "\n".join(lines)


def _check_save_args(
    mode: str, free_thresh: float, occupied_thresh: float, image_format: str | None
) -> tuple[MapMode, str]:
    """map_saver's parameter checks, as errors instead of log lines."""
    lowered = str(mode).lower()
    if lowered not in MAP_MODES:
        raise MapError(
            f"unknown map mode '{mode}'; use one of {', '.join(MAP_MODES)}",
            key="mode",
            suggestion=best_match(lowered, MAP_MODES),
        )
    for name, value in (("free_thresh", free_thresh), ("occupied_thresh", occupied_thresh)):
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise MapError(f"must be a number, got {value!r}", key=name)
        if not np.isfinite(value):
            raise MapError(f"must be a finite number, got {value!r}", key=name)
    if occupied_thresh > 1.0:
        raise MapError(f"must be 1.0 or less, got {occupied_thresh}", key="occupied_thresh")
    if free_thresh < 0.0:
        raise MapError(f"must be 0.0 or greater, got {free_thresh}", key="free_thresh")
    if occupied_thresh <= free_thresh:
        raise MapError(
            f"free_thresh ({free_thresh}) must be smaller than occupied_thresh ({occupied_thresh})",
            key="free_thresh",
        )
    if image_format is None:
        fmt = "png" if lowered == "scale" else "pgm"  # map_saver's default
    else:
        fmt = str(image_format).lower().lstrip(".")
    if fmt not in IMAGE_FORMATS:
        raise MapError(
            f"unsupported image format '{image_format}'; use one of {', '.join(IMAGE_FORMATS)}",
            key="image_format",
            suggestion=best_match(fmt, IMAGE_FORMATS),
        )
    return lowered, fmt  # type: ignore[return-value]


def _map_paths(yaml_path: str | PathLike[str], fmt: str) -> tuple[Path, Path]:
    """`maps/office.yaml` -> (`maps/office.yaml`, `maps/office.pgm`); `maps/office` -> both added."""
    path = Path(yaml_path).expanduser()
    if path.suffix.lower() in (".yaml", ".yml"):
        base = path.with_suffix("")
    else:
        base, path = path, Path(f"{path}.yaml")
    return path, Path(f"{base}.{fmt}")


def save_map(
    grid: OccupancyGrid,
    yaml_path: str | PathLike[str],
    *,
    mode: MapMode | str = "trinary",
    free_thresh: float = 0.25,
    occupied_thresh: float = 0.65,
    image_format: str | None = None,
) -> tuple[Path, Path]:
    """Write `grid` as map_saver would; returns the paths of the YAML and the image.

    `mode` trinary writes 254/205/0 (cells <= free_thresh*100 are free, >=
    occupied_thresh*100 occupied, the rest unknown); scale keeps every value 0..100
    (and unknown as transparency, so it needs PNG: the default image format for
    scale); raw writes the values themselves. Exact on reload: trinary for cells in
    {-1, 0, 100}, raw for -1..100, scale for -1..100 when saved with free_thresh=0 and
    occupied_thresh=1 (other thresholds re-map the in-between values on load, as
    they do in Nav2).
    """
    if not isinstance(grid, OccupancyGrid):
        raise TypeError(f"save_map takes an OccupancyGrid, not {type(grid).__name__}")
    map_mode, fmt = _check_save_args(mode, free_thresh, occupied_thresh, image_format)
    yaml_file, image_file = _map_paths(yaml_path, fmt)
    if grid.data.size == 0:
        raise MapError("cannot save an empty map (0 cells)", file=yaml_file)
    if not all(np.isfinite([grid.origin.x, grid.origin.y, grid.origin.yaw])):
        raise MapError(f"the map origin must be finite, got {grid.origin}", file=yaml_file)
    grey, alpha = grid_to_image(
        grid.data, mode=map_mode, free_thresh=free_thresh, occupied_thresh=occupied_thresh
    )
    if alpha is not None and fmt != "png" and bool((alpha < 255).any()):
        warnings.warn(
            f"scale mode marks unknown cells by transparency, which {fmt.upper()} cannot "
            f"hold: they will load as 50% occupied; save with image_format='png'",
            stacklevel=2,
        )
    if fmt == "pgm":
        alpha = None
    try:  # `-o out/office.yaml` into a folder that does not exist yet: make it
        yaml_file.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise MapError(f"cannot create the folder: {exc.strerror}", file=yaml_file) from None
    write_image(image_file, grey, alpha, image_format=fmt)
    text = map_yaml_text(
        image_file.name,
        mode=map_mode,
        resolution=grid.resolution,
        origin=grid.origin,
        free_thresh=free_thresh,
        occupied_thresh=occupied_thresh,
    )
    try:
        yaml_file.write_text(text, encoding="utf-8")
    except OSError as exc:
        raise MapError(f"cannot write: {exc.strerror}", file=yaml_file) from None
    return yaml_file, image_file
