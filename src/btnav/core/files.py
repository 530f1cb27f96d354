"""Reading a user's file: every way it can fail is a located btnav error."""

from __future__ import annotations

from os import PathLike
from pathlib import Path

from .errors import BtnavError


def read_bytes(
    path: str | PathLike[str], *, error_cls: type[BtnavError] = BtnavError, what: str = "file"
) -> bytes:
    """The file's bytes; a missing file, a folder or a read error raises `error_cls` naming it."""
    p = Path(path)
    try:
        return p.read_bytes()
    except FileNotFoundError:
        raise error_cls(f"{what} not found", file=p) from None
    except IsADirectoryError:
        raise error_cls(f"is a directory, not a {what}", file=p) from None
    except OSError as exc:
        raise error_cls(f"cannot read: {exc.strerror or exc}", file=p) from None
