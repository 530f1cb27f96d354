"""btnav's slam_toolbox engine on real laser logs, scored as published SLAM systems are.

    python bench/slam_logs.py [LOG ...] [--params P | --lua F]
                              [--angle-increment-deg auto|declared|X]
                              [--trajectory matched|odometry]

Default logs: ../shared/slam_logs/intel.clf (relative to the repo) and, when `rosbags`
is installed, intel.bag beside it. Each log runs through `btnav.slam.karto.offline.run_slam`,
the engine `btnav slam` runs, with the params `btnav slam` would use (slam_toolbox's
own mapper_params_online_async.yaml without --params; with --lua, Cartographer's engine,
`btnav.slam.cartographer.offline.run_cartographer`, configured by that file, as `btnav slam
--lua`). Printed per log: the relation
errors (Kümmerle et al. 2009: mean and standard deviation of the absolute translational
and rotational errors over the ground-truth relations in `<log stem>.relations`) of

- btnav's trajectory (one pose per scan, as `btnav slam` writes it),
- the same map with every scan placed by `map -> odom` times the odometry (what
  slam_toolbox publishes between processed scans),
- the odometry alone,

beside the published figures for the Intel Research Lab data set; then the log's
duration against the wall time (the real-time factor), processed scans, loop closures.
No assertions: it reports.

Scan geometry (`--angle-increment-deg`): the Intel logs declare 180 beams from -90 to
+90 degrees, pi/179 apart, but their scans are consistent only at 1 degree apart (from
-90 to +89): matching pairs of scans against the relations, the heading error grows by
0.56% of the turn (= 180/179 - 1) with pi/179 and by -0.08% with 1 degree. The CARMEN
reader reads the .clf at 1 degree (CARMEN's default resolution); the bags of the family
(INESC TEC's conversions) declare pi/(n-1) for n = 180 or 360 beams, and `auto`
(default) applies 180/n degrees to such a scan, and says so; `declared` keeps the log's
geometry; a number sets every scan's beam spacing.

The other logs of the family (ACES, MIT CSAIL, MIT Killian Court, Freiburg 079, the
Freiburg hospital) run the same way; their relations file is found beside the log as
`<name>.relations`, with `name` the file name up to its first dot or underscore
(`fr-clinic_robotlaser.orig.bag` -> `fr-clinic.relations`). When some relations span
more than a minute (the hospital's global ones, start and end of a 1400 m tour), the
errors over the local ones (t2 - t1 <= 60 s) are printed too, as Kümmerle et al. report
the hospital. A log whose clock is not the relations' (no relation within 50 ms of a
scan) says so instead of printing NaN.
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMEXPR_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import importlib.util  # noqa: E402
import math  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from btnav.slam.cartographer.config import load_cartographer_config  # noqa: E402
from btnav.slam.cartographer.offline import run_cartographer  # noqa: E402
from btnav.slam.karto.mapper import Mapper  # noqa: E402
from btnav.slam.karto.offline import odometry_trajectory, run_slam  # noqa: E402
from btnav.slam.logs import RecordedLog, read_log  # noqa: E402
from btnav.slam.offline_files import slam_params  # noqa: E402
from btnav.testing.slam_metrics import RelationErrors, relation_errors, relations  # noqa: E402

REPO = Path(__file__).resolve().parents[1]
LOGS = REPO.parent / "shared" / "slam_logs"

#: Published relation errors on the Intel Research Lab log: (name, source, mean
#: translational error m, its std, mean rotational error deg, its std).
#: Kümmerle, Steder, Dornhege, Ruhnke, Grisetti, Stachniss, Kleiner, "On measuring the
#: accuracy of SLAM algorithms", Autonomous Robots 27(4), 2009 (graph mapping, RBPF =
#: GMapping with 50 particles, sequential scan matching); Hess, Kohler, Rapp, Andor,
#: "Real-Time Loop Closure in 2D LIDAR SLAM", ICRA 2016, Table I (Cartographer, quoting
#: Kümmerle et al. for the others).
PUBLISHED_INTEL = (
    ("Cartographer", "Hess et al. 2016", 0.0229, 0.0239, 0.453, 1.335),
    ("graph mapping", "Kümmerle et al. 2009", 0.031, 0.026, 1.3, 4.7),
    ("GMapping (RBPF)", "Kümmerle et al. 2009", 0.070, 0.083, 3.0, 5.3),
    ("scan matching", "Kümmerle et al. 2009", 0.220, 0.296, 1.7, 4.8),
)
#: Scans of 180 or 360 beams over a half turn are 1 or 0.5 degrees apart (CARMEN's
#: resolutions), whatever spacing a bag declares for them.
HALF_TURN_BEAMS = 180
#: Relations at most this far apart in time are the local ones (Kümmerle et al.'s split).
LOCAL_SPAN = 60.0


def default_logs() -> list[Path]:
    logs = [LOGS / "intel.clf"]
    if importlib.util.find_spec("rosbags") is not None:
        logs.append(LOGS / "intel.bag")
    return logs


def fix_geometry(log: RecordedLog, how: str) -> str:
    """Set the beam spacing as `--angle-increment-deg` says; a note of what was done."""
    if how == "declared" or not log.scans:
        return "declared beam spacing"
    first = log.scans[0]
    declared_deg = math.degrees(first.angle_increment)
    if how == "auto":
        n = first.ranges.size
        declared = n % HALF_TURN_BEAMS == 0 and math.isclose(
            first.angle_increment, math.pi / (n - 1), rel_tol=1e-3
        )
        if not declared:
            return "declared beam spacing"
        inc = math.pi / n
    else:
        inc = math.radians(float(how))
    for s in log.scans:
        s.angle_increment = inc
        s.angle_max = s.angle_min + (s.ranges.size - 1) * inc
    return (
        f"beam spacing {math.degrees(inc):g} deg from {math.degrees(first.angle_min):g} deg "
        f"(declared {declared_deg:.4f} deg)"
    )


def relations_path(log: Path) -> Path:
    """`<log stem>.relations` beside the log, else `<name up to the first . or _>.relations`."""
    first = log.with_suffix(".relations")
    if first.exists():
        return first
    return log.parent / (log.name.split(".")[0].split("_")[0] + ".relations")


def line(label: str, e: RelationErrors) -> str:
    return (
        f"  {label:<40} {100 * e.trans_mean:6.2f} ± {100 * e.trans_std:6.2f} cm   "
        f"{math.degrees(e.rot_mean):5.2f} ± {math.degrees(e.rot_std):5.2f} deg"
    )


def score(
    rel_path: Path,
    what: str,
    rel: np.ndarray,
    stamps: np.ndarray,
    trajectories: list[tuple[str, np.ndarray]],
) -> None:
    """One block of relation errors, one line per trajectory."""
    errors = [(label, relation_errors(stamps, poses, rel)) for label, poses in trajectories]
    used = errors[0][1].used
    if used == 0:
        print(f"  none of the {len(rel)} relations of {rel_path.name} fall within 50 ms of a "
              "scan: the log's clock is not the relations'")  # fmt: skip
        return
    note = f", {len(rel) - used} off the log's stamps" if used < len(rel) else ""
    print(f"  {what}relation errors over {used} relations ({rel_path.name}{note})"
          "           translation          rotation")  # fmt: skip
    for label, e in errors:
        print(line(label, e))


def bench(
    path: Path, params_path: str | None, geometry: str, trajectory: str, lua: str | None = None
) -> None:
    rel_path = relations_path(path)
    log = read_log(path)
    note = fix_geometry(log, geometry)
    cpu0 = time.process_time()  # a shared machine stretches wall time; CPU time does not
    if lua is not None:
        result = run_cartographer(log, load_cartographer_config(lua))
        engine, trajectory = "Cartographer", "local SLAM"
    else:
        result = run_slam(log, slam_params(params_path), trajectory=trajectory)  # type: ignore[arg-type]
        engine = "slam_toolbox"
    cpu = time.process_time() - cpu0
    stamps = result.stamps
    odom = log.odom_at(stamps)
    node_stamps = np.array([s.stamp for s in result.mapper.scans])
    node_of = np.searchsorted(node_stamps, stamps, side="right") - 1
    config = lua or params_path or "default"
    print(f"{path.name}: {len(log.scans)} scans, {note}, {engine} with {config}")
    if rel_path.exists():
        rel = relations(rel_path)
        trajectories = [(f"btnav {engine} ({trajectory})", result.poses)]
        if trajectory == "matched" and isinstance(result.mapper, Mapper):
            by_odom = odometry_trajectory(result.mapper, odom, node_of)
            trajectories.append(("  same map, map->odom x odometry", by_odom))
        trajectories.append(("odometry", odom))
        span = rel[:, 1] - rel[:, 0]
        sets = [("", rel)]
        if (span > LOCAL_SPAN).any():
            sets.append((f"local (t2 - t1 <= {LOCAL_SPAN:g} s) ", rel[span <= LOCAL_SPAN]))
        for what, subset in sets:
            score(rel_path, what, subset, stamps, trajectories)
        if path.name.startswith("intel."):
            for name, source, tm, ts, rm, rs in PUBLISHED_INTEL:
                print(
                    f"  {name + ' (' + source + ')':<40} {100 * tm:6.2f} ± {100 * ts:6.2f} cm   "
                    f"{rm:5.2f} ± {rs:5.2f} deg"
                )
    else:
        print(f"  no {rel_path.name}: no relation errors")
    factor = log.duration / max(result.wall_time, 1e-9)
    print(
        f"  {log.duration:.0f} s of log in {result.wall_time:.1f} s wall ({factor:.1f}x real "
        f"time; {cpu:.1f} s CPU, {log.duration / max(cpu, 1e-9):.1f}x); {result.processed} "
        f"scans processed, {result.mapper.loop_closures} loop closures"
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("logs", nargs="*", type=Path)
    engine = ap.add_mutually_exclusive_group()
    engine.add_argument("--params", help="a Nav2-style params file with a slam_toolbox: section")
    engine.add_argument("--lua", help="run Cartographer's engine with this .lua options file")
    ap.add_argument("--angle-increment-deg", default="auto", help="auto, declared or degrees")
    ap.add_argument("--trajectory", choices=("matched", "odometry"), default="matched")
    args = ap.parse_args()
    for path in args.logs or default_logs():
        bench(path, args.params, args.angle_increment_deg, args.trajectory, args.lua)


if __name__ == "__main__":
    main()
