"""Map images as map_server sees them: 8-bit grey plus an optional alpha channel.

PGM files are decoded by `pgm` (no dependency); every other format (PNG, BMP, ...) goes
through Pillow, imported only when such a file is met, so the core install stays
light. map_server reduces every image to 8-bit grey with GraphicsMagick (16-bit
builds); this module reproduces that reduction: 16-bit samples keep their high byte
(`v // 257`), other maxvals are rescaled, colour pixels take Rec.601 luma.
"""

from __future__ import annotations

import io
from dataclasses import dataclass
from os import PathLike
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..core.errors import MapError
from ..core.files import read_bytes
from .pgm import decode_pgm, encode_pgm, is_pgm

#: The formats map_saver recommends; btnav writes these and nothing else.
IMAGE_FORMATS = ("pgm", "png", "bmp")
_PILLOW_FORMATS = {"png": "PNG", "bmp": "BMP"}


@dataclass(frozen=True)
class MapImage:
    """An image reduced to what map_server uses: grey levels and alpha, top row first."""

    grey: NDArray[np.uint8]
    alpha: NDArray[np.uint8] | None = None  # None when the image has no alpha channel

    @property
    def height(self) -> int:
        return int(self.grey.shape[0])

    @property
    def width(self) -> int:
        return int(self.grey.shape[1])


def _pillow(path: Path, doing: str) -> Any:
    """Pillow's Image module, or an error that says how to install it."""
    try:
        from PIL import Image
    except ImportError:
        raise MapError(
            f"{doing} {path.suffix or 'non-PGM'} images needs Pillow; install it with "
            "`pip install btnav[viz]` (or save the map as .pgm)",
            file=path,
        ) from None
    return Image


def to_8bit(samples: NDArray[np.integer], maxval: int) -> NDArray[np.uint8]:
    """Scale samples of any maxval to 0..255 as GraphicsMagick (Q16) exports them."""
    if maxval == 255:
        return samples.astype(np.uint8)
    wide = samples.astype(np.int64)
    if maxval != 65535:
        wide = (wide * 65535 + maxval // 2) // maxval  # to the 16-bit quantum, rounded
    return (wide // 257).astype(np.uint8)


def _luma(rgb: NDArray[np.uint8]) -> NDArray[np.uint8]:
    """Grey from RGB as GraphicsMagick's grayscale conversion: exact for grey pixels."""
    r, g, b = (rgb[..., i] for i in range(3))
    luma = 0.299 * r + 0.587 * g + 0.114 * b
    grey = np.floor(luma + 0.5).clip(0, 255).astype(np.uint8)
    return np.where((r == g) & (g == b), r, grey)


def _decode_with_pillow(buf: bytes, path: Path) -> MapImage:
    image_mod = _pillow(path, "reading")
    try:
        with image_mod.open(io.BytesIO(buf)) as im:
            im.load()
            bands = im.getbands()
            has_alpha = "A" in bands or "a" in bands or "transparency" in im.info
            if im.mode in ("I;16", "I;16B", "I;16L", "I;16N", "I") and not has_alpha:
                samples = np.asarray(im).astype(np.int64).clip(0, 65535)
                return MapImage(to_8bit(samples, 65535))
            if im.mode in ("1", "L") and not has_alpha:
                return MapImage(np.asarray(im.convert("L"), dtype=np.uint8).copy())
            rgba = np.asarray(im.convert("RGBA" if has_alpha else "RGB"), dtype=np.uint8)
    except Exception as exc:  # Pillow raises many types for a corrupt file
        reason = str(exc) or type(exc).__name__
        raise MapError(f"cannot read the image: {reason}", file=path) from None
    grey = _luma(rgba)
    alpha = rgba[..., 3].copy() if has_alpha else None
    return MapImage(grey, alpha)


def read_image(path: str | PathLike[str]) -> MapImage:
    """Read a map image (PGM natively, anything else via Pillow) as grey + alpha."""
    p = Path(path)
    buf = read_bytes(p, error_cls=MapError, what="image file")
    if is_pgm(buf):
        pgm = decode_pgm(buf, p)
        return MapImage(to_8bit(pgm.data, pgm.maxval))
    if not buf:
        raise MapError("the image file is empty", file=p)
    return _decode_with_pillow(buf, p)


def write_image(
    path: str | PathLike[str],
    grey: NDArray[np.uint8],
    alpha: NDArray[np.uint8] | None = None,
    *,
    image_format: str = "pgm",
) -> None:
    """Write an 8-bit grey image (with alpha: RGBA, as map_saver's scale mode does)."""
    p = Path(path)
    if image_format == "pgm":
        payload = encode_pgm(grey, maxval=255)  # PGM has no alpha; map_saver drops it too
        try:
            p.write_bytes(payload)
        except OSError as exc:
            raise MapError(f"cannot write: {exc.strerror}", file=p) from None
        return
    if image_format not in _PILLOW_FORMATS:
        raise MapError(f"unknown image format '{image_format}'", file=p)
    image_mod = _pillow(p, "writing")
    if alpha is None:
        im = image_mod.fromarray(np.ascontiguousarray(grey, dtype=np.uint8))
    else:
        rgba = np.stack([grey, grey, grey, alpha], axis=-1).astype(np.uint8)
        im = image_mod.fromarray(rgba)
    try:
        im.save(p, format=_PILLOW_FORMATS[image_format])
    except OSError as exc:
        raise MapError(f"cannot write: {exc.strerror or exc}", file=p) from None
