"""`btnav slam LOG --params P -o OUT/`: SLAM on a recorded log, as slam_toolbox on a bag.

Writes `OUT/map.yaml` + `map.pgm` (map_server's format), `OUT/trajectory.csv` (t, x,
y, yaw: one row per scan, at the scan's time) and `OUT/pose_graph.npz` (the graph
`localization: slam` with `mode: localization` can load). Every input is read and
checked before anything is written.
"""

from __future__ import annotations

import sys
from os import PathLike
from pathlib import Path

import numpy as np

from ..maps.map_io import save_map
from ..params.loader import load_params
from ..params.localization import SlamToolboxParams
from .graph_io import save_pose_graph
from .logs import read_log
from .offline import OfflineResult, run_slam
from .slam_toolbox import default_slam_params


def _progress(label: str):  # type: ignore[no-untyped-def]
    """A rich bar on a terminal, nothing otherwise (a log file gets the summary line)."""
    if not sys.stdout.isatty():
        return None, None
    try:
        from rich.progress import Progress
    except ImportError:
        return None, None
    bar = Progress(transient=True)
    task = bar.add_task(label, total=None)

    def update(done: int, total: int) -> None:
        bar.update(task, completed=done, total=total)

    return bar, update


def slam_params(path: str | PathLike[str] | None) -> SlamToolboxParams:
    """The `slam_toolbox:` section of a params file (slam_toolbox's own file without one)."""
    pf = load_params(path) if path is not None else None
    if pf is None or "slam_toolbox" not in pf:
        return default_slam_params()
    return pf.server("slam_toolbox").model  # type: ignore[no-any-return]


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
    save_pose_graph(result.mapper, out / "pose_graph.npz")


def slam_main(
    log_path: str | PathLike[str],
    params_path: str | PathLike[str] | None,
    out_dir: str | PathLike[str],
    *,
    scan_topic: str | None = None,
    odom_topic: str | None = None,
) -> int:
    params = slam_params(params_path)
    bar, update = _progress("reading")
    if bar is not None:
        bar.start()
    try:
        log = read_log(log_path, scan_topic=scan_topic, odom_topic=odom_topic, progress=update)
        if bar is not None:
            bar.update(bar.task_ids[0], description="scans")
        result = run_slam(log, params, progress=update)
    finally:
        if bar is not None:
            bar.stop()
    out = Path(out_dir)
    write_outputs(result, out)
    print(
        f"{Path(log_path).name}: {len(log.scans)} scans, {result.processed} processed, "
        f"{result.mapper.loop_closures} loop closures; {log.duration:.0f} s of log in "
        f"{result.wall_time:.1f} s ({log.duration / max(result.wall_time, 1e-9):.1f}x real "
        f"time); wrote {out}/map.yaml, trajectory.csv, pose_graph.npz"
    )
    return 0
