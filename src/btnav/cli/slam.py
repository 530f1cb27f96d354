"""`btnav slam LOG [--params P | --lua F] -o OUT/`: SLAM on a recorded log, as slam_toolbox
(or, with `--lua`, cartographer_ros's offline node) on a bag.

Writes `OUT/map.yaml` + `map.pgm`, `OUT/trajectory.csv` and `OUT/pose_graph.npz`
(`slam.offline_files`). `--trajectory matched` (default) places every scan by matching
it against the final map; `odometry` places the scans between graph nodes by odometry
from the nearest node (what slam_toolbox's map -> odom gives between processed scans). Every input is read and checked before anything is written.
On a terminal a progress bar shows while the log is read and its scans matched; the
summary line is all a log file gets.
"""

from __future__ import annotations

import sys
from os import PathLike
from pathlib import Path

from ..core.errors import ConfigError
from ..slam.cartographer.config import load_cartographer_config
from ..slam.cartographer.offline import run_cartographer
from ..slam.karto.offline import run_slam
from ..slam.karto.slam_toolbox import warn_ignored
from ..slam.logs import read_log
from ..slam.offline_files import load_slam_params, write_outputs
from . import EXIT_OK


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


def slam_main(
    log_path: str | PathLike[str],
    params_path: str | PathLike[str] | None,
    out_dir: str | PathLike[str],
    *,
    scan_topic: str | None = None,
    odom_topic: str | None = None,
    trajectory: str | None = None,
    lua: str | PathLike[str] | None = None,
) -> int:
    if lua is not None and trajectory is not None:
        raise ConfigError(
            "--trajectory chooses between slam_toolbox's trajectories; with --lua "
            "every scan is placed as Cartographer's local SLAM matched it",
            key="--trajectory",
        )
    config = load_cartographer_config(lua) if lua is not None else None
    params, params_file = load_slam_params(params_path) if config is None else (None, None)
    bar, update = _progress("reading")
    if bar is not None:
        bar.start()
    try:
        log = read_log(log_path, scan_topic=scan_topic, odom_topic=odom_topic, progress=update)
        if bar is not None:
            bar.update(bar.task_ids[0], description="scans")
        if config is not None:
            result = run_cartographer(log, config, progress=update)
        else:
            assert params is not None
            if params_file is not None:  # once the inputs are read: a bad log is one error
                warn_ignored(params_file)
            result = run_slam(log, params, progress=update, trajectory=trajectory or "matched")  # type: ignore[arg-type]
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
    return EXIT_OK
