"""The files of SLAM on a recorded log: the params it reads and the folder it writes.

The folder is what slam_toolbox leaves after a bag: `map.yaml` + `map.pgm` (map_server's
format), `trajectory.csv` (t, x, y, yaw: one row per scan, at the scan's time) and
`pose_graph.npz` (the graph `localization: slam` with `mode: localization` loads; after
`--lua`, Cartographer's nodes and edges, `cartographer.graph_io.save_cartographer_graph`).
`btnav slam` (`btnav.cli.slam`) reads and checks every input before writing here.
"""

from __future__ import annotations

from os import PathLike
from pathlib import Path

import numpy as np

from ..core.errors import BtnavError
from ..maps.map_io import save_map
from ..params.loader import load_params
from ..params.localization import SlamToolboxParams
from ..params.paramsfile import ParamsFile
from ..params.tree import line_of
from .cartographer.graph_io import save_cartographer_graph
from .karto.graph_io import save_pose_graph
from .karto.mapper import Mapper
from .karto.offline import refuse_localization
from .karto.slam_toolbox import default_slam_params
from .offline_result import OfflineResult


def load_slam_params(
    path: str | PathLike[str] | None,
) -> tuple[SlamToolboxParams, ParamsFile | None]:
    """The `slam_toolbox:` section of a params file (slam_toolbox's own file without one)
    and the file, whose ignored keys the caller reports (`slam_toolbox.warn_ignored`).
    `mode: localization` is an error at its line (`karto.offline.refuse_localization`)."""
    pf = load_params(path) if path is not None else None
    if pf is None or "slam_toolbox" not in pf:
        return default_slam_params(), pf
    server = pf.server("slam_toolbox")
    try:
        refuse_localization(server.model)
    except BtnavError as err:
        raise err.located(file=pf.path, line=line_of(server.doc, "mode")) from None
    return server.model, pf


def slam_params(path: str | PathLike[str] | None) -> SlamToolboxParams:
    """The `slam_toolbox:` section of a params file (see `load_slam_params`)."""
    return load_slam_params(path)[0]


def write_outputs(result: OfflineResult, out: Path) -> None:
    out.mkdir(parents=True, exist_ok=True)
    save_map(result.grid, out / "map.yaml")
    rows = np.column_stack([result.stamps, result.poses])
    np.savetxt(
        out / "trajectory.csv",
        rows,
        delimiter=",",
        header="t,x,y,yaw",
        comments="",
        fmt=["%.6f", "%.6f", "%.6f", "%.6f"],
    )
    if isinstance(result.mapper, Mapper):
        save_pose_graph(result.mapper, out / "pose_graph.npz")
    else:
        save_cartographer_graph(result.mapper, out / "pose_graph.npz")
