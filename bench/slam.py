"""SLAM's speed, with its error beside it: the corridor loop live, and a real log offline.

    python bench/slam.py [--seeds 0,1] [--log ../shared/slam_logs/intel.clf] [--skip-log]

1. The corridor loop (worlds/corridor_loop.yaml: 78 m round, 360-beam lidar at 10 Hz,
   wheel odometry drifting metres per lap), driven once round and on past the start
   while `localization: slam` maps with slam_toolbox's defaults. Timed: the SLAM
   component's own wall time (gating, matching, linking, loop closure, optimisation,
   occupancy updates, map publishing) against the sim time driven: the real-time factor
   SLAM alone would run at. Printed beside it: the trajectory's error (the optimised
   nodes and what the robot believed while driving) and odometry's, loop closures.
2. A recorded log (default the Intel Research Lab's CARMEN log) through `btnav slam`'s
   engine at its recorded rate: the log's duration over the wall time, scans processed,
   loop closures and, with `<log stem>.relations` beside the log, the trajectory's mean
   relation errors (scored by bench/slam_logs.py's rules; its full table: that script).

Target: >= 10x real time on one core. numpy runs single-threaded.
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMEXPR_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import math  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

from tests.slam.loop_drive import drive_loop  # noqa: E402  (the tests' driver, on ground truth)

from btnav.testing.slam_metrics import ate_rms  # noqa: E402

TARGET = 10.0


class Timed:
    """Wraps the SLAM component's update and adds up its wall time."""

    def __init__(self) -> None:
        self.seconds = 0.0

    def __call__(self, slam) -> None:  # type: ignore[no-untyped-def]
        update = slam.update

        def timed(now: float):  # type: ignore[no-untyped-def]
            t0 = time.perf_counter()
            out = update(now)
            self.seconds += time.perf_counter() - t0
            return out

        slam.update = timed


def loop(seed: int) -> None:
    timer = Timed()
    run = drive_loop(seed=seed, on_start=timer)
    mapper = run.slam.mapper
    sim = float(run.truth[-1, 0] - run.truth[0, 0])
    stamps = np.array([s.stamp for s in mapper.scans])
    nodes_xy, _ = ate_rms(mapper.poses, run.truth_at(stamps))
    online_xy, _ = ate_rms(run.estimate, run.truth[:, 1:])
    odom_xy, _ = ate_rms(run.odom, run.truth[:, 1:])
    rtf = sim / timer.seconds
    print(
        f"loop seed {seed}: {sim:.0f} s sim, SLAM {timer.seconds:.2f} s wall = {rtf:.0f}x real "
        f"time (target >= {TARGET:.0f}x); {len(mapper.scans)} scans processed, "
        f"{mapper.loop_closures} loop closures; ATE nodes {100 * nodes_xy:.1f} cm, "
        f"online {100 * online_xy:.1f} cm, odometry {100 * odom_xy:.0f} cm RMS"
    )


def log_run(path: Path) -> None:
    from btnav.slam.karto.offline import run_slam
    from btnav.slam.karto.slam_toolbox import default_slam_params
    from btnav.slam.logs import read_log

    t0 = time.perf_counter()
    log = read_log(path)
    read = time.perf_counter() - t0
    result = run_slam(log, default_slam_params())
    rtf = log.duration / result.wall_time
    print(
        f"{path.name}: {log.duration:.0f} s of log, {len(log.scans)} scans ({read:.1f} s to "
        f"read); SLAM {result.wall_time:.1f} s = {rtf:.0f}x real time (target >= "
        f"{TARGET:.0f}x); {result.processed} processed, {result.mapper.loop_closures} loop "
        f"closures{log_errors(path, result.stamps, result.poses)}"
    )


def log_errors(path: Path, stamps: np.ndarray, poses: np.ndarray) -> str:
    """The run's mean relation errors, scored as bench/slam_logs.py scores them, from the
    relations file it finds beside the log; "" without one."""
    from slam_logs import relations_path  # bench/slam_logs.py: which file scores a log

    from btnav.testing.slam_metrics import relation_errors, relations

    rel_path = relations_path(path)
    if not rel_path.exists():
        return ""
    rel = relations(rel_path)
    e = relation_errors(stamps, poses, rel)
    if e.used == 0:
        return f"; no relation of {rel_path.name} within 50 ms of a scan"
    return (
        f"; relation errors {100 * e.trans_mean:.2f} cm, {math.degrees(e.rot_mean):.2f} deg "
        f"(mean over {e.used} of {len(rel)} in {rel_path.name})"
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", default="0,1")
    ap.add_argument("--log", default=str(REPO.parent / "shared" / "slam_logs" / "intel.clf"))
    ap.add_argument("--skip-log", action="store_true")
    args = ap.parse_args()
    for seed in (int(s) for s in args.seeds.split(",")):
        loop(seed)
    if not args.skip_log:
        log_run(Path(args.log))


if __name__ == "__main__":
    main()
