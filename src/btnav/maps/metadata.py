"""The map YAML of map_server, as a pydantic model with located errors.

map_server reads `image`, `resolution`, `origin`, `negate`, `occupied_thresh`,
`free_thresh` (all required) and `mode` (optional, trinary by default). btnav reads the
same keys with the same conversions (mode is case-insensitive, negate is an integer
or a boolean, numbers may be quoted) and is stricter where map_server would load
nonsense: an unknown key is an error with the closest spelling (map_server would
ignore a misspelt `mode` and silently use trinary), numbers must be finite,
resolution positive and the thresholds within 0..1 with free <= occupied.
"""

from __future__ import annotations

import math
from os import PathLike
from pathlib import Path
from typing import Annotated, Any

import pydantic
from pydantic import AfterValidator, BeforeValidator
from pydantic_core import PydanticCustomError

from ..core.errors import BtnavError, MapError
from ..core.suggest import best_match
from ..core.validation import StrictModel, validate
from ..core.yaml_io import YamlMap, line_at, load_yaml
from .map_mode import MAP_MODES, MapMode


def _invalid(message: str) -> PydanticCustomError:
    """A validation error whose message is shown as written (no "Value error, " prefix)."""
    return PydanticCustomError("map_value", message.replace("{", "{{").replace("}", "}}"))


def _no_bool(value: Any) -> Any:
    """YAML's `true` is not a number, although Python (and pydantic) would take it as 1."""
    if isinstance(value, bool):
        raise _invalid("expected a number, not a boolean")
    return value


def _finite(value: float) -> float:
    if not math.isfinite(value):
        raise _invalid("must be a finite number")
    return value


def _positive(value: float) -> float:
    if value <= 0:
        raise _invalid("must be greater than 0")
    return value


def _unit_interval(value: float) -> float:
    if not 0.0 <= value <= 1.0:
        raise _invalid("must be between 0.0 and 1.0 (a fraction of full darkness)")
    return value


Number = Annotated[float, BeforeValidator(_no_bool), AfterValidator(_finite)]
Threshold = Annotated[Number, AfterValidator(_unit_interval)]


class MapMetadata(StrictModel):
    """The contents of a map_server `.yaml` file (paths as written, not resolved)."""

    image: str
    mode: MapMode = "trinary"
    resolution: Annotated[Number, AfterValidator(_positive)]
    origin: tuple[Number, Number, Number]
    negate: bool
    occupied_thresh: Threshold
    free_thresh: Threshold

    @pydantic.field_validator("image", mode="before")
    @classmethod
    def _image(cls, value: Any) -> Any:
        if isinstance(value, str):
            if not value:
                raise _invalid("the image is empty; name the .pgm or .png file")
            if "\x00" in value:
                raise _invalid("the image path contains a NUL character")
        return value

    @pydantic.field_validator("mode", mode="before")
    @classmethod
    def _mode(cls, value: Any) -> Any:
        if not isinstance(value, str):
            raise _invalid(f"mode is one of {', '.join(MAP_MODES)}")
        lowered = value.lower()  # map_server lower-cases the mode
        if lowered not in MAP_MODES:
            hint = best_match(lowered, MAP_MODES)
            tail = f" (did you mean '{hint}'?)" if hint else ""
            raise _invalid(f"unknown mode '{value}'; use one of {', '.join(MAP_MODES)}{tail}")
        return lowered

    @pydantic.field_validator("origin", mode="before")
    @classmethod
    def _origin(cls, value: Any) -> Any:
        if not isinstance(value, list | tuple) or len(value) != 3:
            n = f"{len(value)} items" if isinstance(value, list | tuple) else "a single value"
            raise _invalid(f"origin is [x, y, yaw]: a list of 3 numbers, not {n}")
        return value

    @pydantic.field_validator("negate", mode="before")
    @classmethod
    def _negate(cls, value: Any) -> Any:
        if isinstance(value, bool):
            return value
        if isinstance(value, int):  # map_server reads an int; any non-zero value negates
            return value != 0
        raise _invalid("negate is 0 or 1 (or false/true)")

    @pydantic.model_validator(mode="after")
    def _thresholds(self) -> MapMetadata:
        if self.free_thresh > self.occupied_thresh:
            raise _invalid(
                f"free_thresh ({self.free_thresh}) is above occupied_thresh "
                f"({self.occupied_thresh}); free_thresh must be the smaller one"
            )
        return self

    def image_path(self, yaml_path: str | PathLike[str]) -> Path:
        """Where map_server looks for the image: absolute as written, else beside the YAML."""
        image = Path(self.image)
        if self.image.startswith("/") or image.is_absolute():
            return image
        return Path(yaml_path).parent / image


_KINDS = ((list, "a list"), (str, "a string"), (bool, "a boolean"), (int | float, "a number"))


def read_map_metadata(yaml_path: str | PathLike[str]) -> MapMetadata:
    """Read and validate a map YAML; every problem is a `MapError` with file, line and key."""
    path = Path(yaml_path).expanduser()  # map_server expands a leading `~/` too
    try:
        doc = load_yaml(path)
    except MapError:
        raise
    except BtnavError as exc:  # a YamlError: keep its place, but as a map problem
        raise MapError(exc.message, file=exc.file, line=exc.line, key=exc.key) from None
    return metadata_from_doc(doc, file=str(path))


def metadata_from_doc(doc: Any, *, file: str | None = None) -> MapMetadata:
    """Validate an already-parsed map YAML document (from `load_yaml`)."""
    if not isinstance(doc, dict):
        kind = next((name for t, name in _KINDS if isinstance(doc, t)), "empty")
        raise MapError(
            f"a map YAML is a mapping of keys (image, resolution, origin, negate, "
            f"occupied_thresh, free_thresh, mode), but this file is {kind}",
            file=file,
            line=getattr(doc, "line", None),
        )
    if not isinstance(doc, YamlMap):
        doc = YamlMap(doc, file=file)
    try:
        return validate(MapMetadata, doc, file=file, error_cls=MapError)
    except MapError as exc:
        if not exc.key and "free_thresh" in doc:  # the cross-field threshold check
            raise MapError(
                f"free_thresh ({doc['free_thresh']}) is above occupied_thresh "
                f"({doc.get('occupied_thresh')}); free_thresh must be the smaller one",
                file=file,
                line=line_at(doc, ["free_thresh"]),
                key="free_thresh",
            ) from None
        raise
