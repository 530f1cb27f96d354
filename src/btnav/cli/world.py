"""`btnav world show WORLD -o PNG`, `btnav world frames WORLD` and `btnav world convert
WORLD.sdf -o WORLD.yaml` (a Gazebo world as a btnav world file).

A folder or file that cannot be written is a `BtnavError` naming it (exit 2), as any
other mistake of the user's; the picture itself is `viz.world_plot`'s.
"""

from __future__ import annotations

from collections.abc import Sequence
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


def convert_world_main(
    world_path: str | PathLike[str],
    out_yaml: str | PathLike[str],
    robot: str | None = None,
    height_band: Sequence[float] | None = None,
    model_paths: Sequence[str] = (),
) -> int:
    """Write a Gazebo world (`.world`, `.sdf`, or a world YAML naming one with `sdf:`) as a
    btnav world YAML; `robot`, a description file, is written as its robot block and its
    lidar's height sets the band."""
    from ..core.yaml_io import YamlMap, load_yaml
    from ..sim.sdf_world_spec import convert_sdf_world, sdf_world_yaml
    from ..sim.world_spec import SDF_WORLD_SUFFIXES

    path, out = Path(world_path), Path(out_yaml)
    ref = None
    if path.suffix.lower() not in SDF_WORLD_SUFFIXES:
        ref = load_yaml(path)
        if not (isinstance(ref, dict) and "sdf" in ref):
            raise BtnavError(
                "btnav world convert reads a Gazebo world (.world, .sdf) or a world file "
                "that names one (sdf: ...); this world is a btnav world already",
                file=path,
            )
    block = None
    if robot is not None:
        block = YamlMap({"description": str(Path(robot).expanduser().resolve())}, file=None)
    conv = convert_sdf_world(
        path, block, ref=ref, height_band=height_band, model_paths=tuple(model_paths)
    )
    text = sdf_world_yaml(conv, out)
    try:
        out.parent.mkdir(parents=True, exist_ok=True)
        out.write_text(text)
    except OSError as exc:
        raise BtnavError(f"cannot write the world: {exc.strerror or exc}", file=out) from None
    moving = len(conv.source.actors)
    lo, hi = conv.band
    print(
        f"wrote {out}: {len(conv.entries)} obstacles ({moving} moving) from "
        f"{len(conv.source.collisions)} collisions, height band {lo:g}-{hi:g} m"
    )
    return EXIT_OK
