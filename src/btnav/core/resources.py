"""Where btnav's bundled files (trees, worlds, maps, params, missions) are found."""

from __future__ import annotations

from pathlib import Path

BUNDLED_KINDS = ("trees", "worlds", "maps", "params", "missions", "robots", "graphs")

_PKG = Path(__file__).resolve().parents[1]


def bundled_dir(kind: str) -> Path:
    """The folder of bundled `kind` files: inside the installed package, else the checkout's root folder."""
    if kind not in BUNDLED_KINDS:
        raise ValueError(f"unknown bundled kind {kind!r}")
    installed = _PKG / "data" / kind
    if installed.is_dir():
        return installed
    return _PKG.parents[1] / kind
