"""`btnav world show WORLD.yaml -o PNG` and `btnav world frames WORLD.yaml`.

A folder or file that cannot be written is a `BtnavError` naming it (exit 2), as any
other mistake of the user's; the picture itself is `viz.world_plot`'s.
"""

from __future__ import annotations

from os import PathLike
from pathlib import Path
from typing import Any

from ..core.errors import BtnavError
from ..sim.frames import world_frame_tree
from ..viz.world_plot import world_figure
from . import EXIT_OK


def show_world_main(world_path: str | PathLike[str], out_png: str | PathLike[str]) -> int:
    """Draw the world, the robot at its start and one scan into `out_png`."""
    save_figure(world_figure(world_path), Path(out_png))
    return EXIT_OK


def save_figure(fig: Any, out: Path) -> None:
    """Save a figure; a folder or file that cannot be written is a located `BtnavError`."""
    try:
        out.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise BtnavError(f"cannot create the folder: {exc.strerror or exc}", file=out) from None
    try:
        fig.savefig(out, dpi=120)
    except OSError as exc:
        raise BtnavError(f"cannot write the picture: {exc.strerror or exc}", file=out) from None
    print(f"wrote {out}")


def world_frames_main(world_path: str | PathLike[str]) -> int:
    """Print the frame tree the world implies at its start (REP-105 and the sensor mounts)."""
    print(world_frame_tree(world_path).describe())
    return EXIT_OK
