"""PGM (netpbm greyscale) reading and writing, without Pillow.

map_server's maps are PGM files, so btnav reads them itself: binary (P5) and plain
ASCII (P2), 8-bit and 16-bit (big-endian) samples, `#` comments anywhere in the
header, and the netpbm whitespace rules. The raster is decoded in one numpy call
(the 2000x2000 benchmark maps load in milliseconds). Every malformed or truncated
file raises a `MapError` naming the file, never an IndexError or a numpy error.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from os import PathLike
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from ..core.errors import MapError
from ..core.files import read_bytes

#: Netpbm's whitespace: blanks, TABs, CRs, LFs (and VT, FF, which isspace() accepts).
_WHITESPACE = frozenset(b" \t\n\r\v\f")
_DIGITS = frozenset(b"0123456789")
#: Enough digits for any real width or height; more is a corrupt header, not a big image.
_MAX_DIGITS = 9
_PGM_MAGICS = (b"P2", b"P5")


@dataclass(frozen=True)
class PgmImage:
    """The samples of a PGM file, top row first (as the file stores them)."""

    data: NDArray[np.uint16]  # (height, width); uint8 when maxval < 256
    maxval: int
    plain: bool = False  # True for P2 (ASCII)

    @property
    def height(self) -> int:
        return int(self.data.shape[0])

    @property
    def width(self) -> int:
        return int(self.data.shape[1])


def is_pgm(head: bytes) -> bool:
    """Whether a file starting with `head` is a PGM (so btnav decodes it, not Pillow)."""
    return head[:2] in _PGM_MAGICS


class _Header:
    """A cursor over the header bytes that skips whitespace and comments as libnetpbm does."""

    def __init__(self, buf: bytes, name: str | None) -> None:
        self.buf = buf
        self.pos = 2  # after the magic number
        self.name = name

    def fail(self, message: str) -> MapError:
        return MapError(f"not a valid PGM file: {message}", file=self.name)

    def skip_comment(self) -> None:
        """A comment runs from `#` to the next CR or LF; that newline counts as whitespace."""
        buf, n = self.buf, len(self.buf)
        while self.pos < n and buf[self.pos] not in (0x0A, 0x0D):
            self.pos += 1
        if self.pos >= n:
            raise self.fail("the header ends inside a comment")

    def uint(self, what: str) -> int:
        buf, n = self.buf, len(self.buf)
        while self.pos < n:
            c = buf[self.pos]
            if c in _WHITESPACE:
                self.pos += 1
            elif c == 0x23:  # '#'
                self.skip_comment()
            else:
                break
        start = self.pos
        while self.pos < n and buf[self.pos] in _DIGITS:
            self.pos += 1
        if self.pos == start:
            if self.pos >= n:
                raise self.fail(f"the header ends before the {what}")
            raise self.fail(
                f"expected the {what} (a number), found {bytes(buf[start : start + 1])!r}"
            )
        if self.pos - start > _MAX_DIGITS:
            raise self.fail(f"the {what} has too many digits")
        return int(buf[start : self.pos])

    def end_of_header(self) -> int:
        """Skip the single whitespace character (or a comment) after maxval; return the raster offset."""
        buf, n = self.buf, len(self.buf)
        if self.pos >= n:
            raise self.fail("no pixel data after the header")
        c = buf[self.pos]
        if c == 0x23:
            self.skip_comment()
        elif c not in _WHITESPACE:
            raise self.fail(f"expected whitespace after maxval, found {bytes([c])!r}")
        return self.pos + 1


def decode_pgm(buf: bytes, name: str | PathLike[str] | None = None) -> PgmImage:
    """Decode the bytes of a P5 or P2 file; `name` is only used in error messages."""
    fname = None if name is None else str(name)
    if not is_pgm(buf):
        raise MapError(
            f"not a PGM file: it starts with {bytes(buf[:2])!r}, not P5 or P2", file=fname
        )
    plain = buf[:2] == b"P2"
    head = _Header(buf, fname)
    width = head.uint("width")
    height = head.uint("height")
    maxval = head.uint("maxval")
    if width == 0 or height == 0:
        raise head.fail(f"the image is empty ({width} x {height} pixels)")
    if not 0 < maxval < 65536:
        raise head.fail(f"maxval must be 1..65535, got {maxval}")
    offset = head.end_of_header()
    count = width * height
    if plain:
        samples = _plain_samples(buf[offset:], count, fname)
    else:
        dtype = np.dtype(np.uint8) if maxval < 256 else np.dtype(">u2")
        need = count * dtype.itemsize
        have = len(buf) - offset
        if have < need:
            raise MapError(
                f"truncated PGM file: {width} x {height} pixels need {need} bytes of "
                f"pixel data, found {have}",
                file=fname,
            )
        samples = np.frombuffer(buf, dtype=dtype, count=count, offset=offset)
    if (plain or maxval not in (255, 65535)) and int(samples.max()) > maxval:
        raise MapError(
            f"corrupt PGM file: a pixel value ({int(samples.max())}) exceeds maxval {maxval}",
            file=fname,
        )
    samples = samples.astype(np.uint8 if maxval < 256 else np.uint16)
    return PgmImage(samples.reshape(height, width), maxval, plain)


def _plain_samples(raster: bytes, count: int, fname: str | None) -> NDArray[np.uint32]:
    """The samples of a P2 raster: decimal numbers separated by whitespace or comments."""
    text = re.sub(rb"#[^\r\n]*", b" ", raster)
    tokens = text.split(None, count)[:count]  # anything after the last sample is ignored
    if len(tokens) < count:
        raise MapError(
            f"truncated PGM file: {count} pixel values expected, found {len(tokens)}", file=fname
        )
    arr = np.array(tokens, dtype=bytes)
    if arr.dtype.itemsize > 5 or not np.char.isdigit(arr).all():
        bad = next(t for t in tokens if not t.isdigit() or len(t) > 5)
        raise MapError(f"corrupt PGM file: {bad[:20]!r} is not a pixel value", file=fname)
    return arr.astype(np.uint32)


def read_pgm(path: str | PathLike[str]) -> PgmImage:
    """Read a PGM file; a missing or unreadable file is a `MapError` naming it."""
    return decode_pgm(read_bytes(path, error_cls=MapError, what="image file"), Path(path))


def encode_pgm(
    data: NDArray[np.integer], *, maxval: int | None = None, plain: bool = False
) -> bytes:
    """The bytes of a PGM file holding `data` (top row first).

    The header is `P5\\n<w> <h>\\n<maxval>\\n`, as GraphicsMagick (map_saver) writes it.
    `maxval` defaults to 255, or 65535 when a sample exceeds 255. Plain (P2) lines stay
    within netpbm's 70 characters.
    """
    arr = np.asarray(data)
    if arr.ndim != 2 or arr.size == 0:
        raise ValueError("a PGM image is a non-empty 2D array")
    lo, hi = int(arr.min()), int(arr.max())
    if maxval is None:
        maxval = 255 if hi <= 255 else 65535
    if not 0 < maxval < 65536:
        raise ValueError(f"maxval must be 1..65535, got {maxval}")
    if lo < 0 or hi > maxval:
        raise ValueError(f"pixel values must be 0..{maxval}, got {lo}..{hi}")
    height, width = arr.shape
    header = f"P{2 if plain else 5}\n{width} {height}\n{maxval}\n".encode("ascii")
    if not plain:
        dtype = np.uint8 if maxval < 256 else np.dtype(">u2")
        return header + arr.astype(dtype).tobytes()
    return header + _plain_raster(arr.ravel(), maxval)


def _plain_raster(flat: NDArray[np.integer], maxval: int) -> bytes:
    """Right-aligned decimal samples, a fixed number per line, built by table lookup."""
    digits = len(str(maxval))
    field = digits + 1  # a leading space separates the samples
    table = np.frombuffer(
        b"".join(f"{v:>{field}}".encode("ascii") for v in range(maxval + 1)), dtype=np.uint8
    ).reshape(maxval + 1, field)
    per_line = 69 // field
    chars = table[flat.astype(np.intp)]  # (n, field)
    full = len(flat) // per_line
    out = b""
    if full:
        lines = chars[: full * per_line].reshape(full, per_line * field)
        newline = np.full((full, 1), ord("\n"), dtype=np.uint8)
        out = np.hstack([lines, newline]).tobytes()
    rest = chars[full * per_line :]
    if len(rest):
        out += rest.tobytes() + b"\n"
    return out


def write_pgm(
    path: str | PathLike[str],
    data: NDArray[np.integer],
    *,
    maxval: int | None = None,
    plain: bool = False,
) -> None:
    """Write `data` (top row first) as a PGM file; see `encode_pgm`."""
    p = Path(path)
    payload = encode_pgm(data, maxval=maxval, plain=plain)
    try:
        p.write_bytes(payload)
    except OSError as exc:
        raise MapError(f"cannot write: {exc.strerror}", file=p) from None
