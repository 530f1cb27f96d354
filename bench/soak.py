"""Soak: an hour of sim time of repeated office tours in one process; memory must stay flat.

    python bench/soak.py [--hours 1.0] [--set KEY=VALUE ...]

One bring-up (`Navigator.from_mission("missions/office_tour.yaml")`, Nav2's params,
MPPI at 20 Hz, ground truth) follows the tour's waypoints and then back to the start,
again and again, with the run's recorders attached (trajectory sums, recovery and
replan counters; no files), until the sim clock passes the limit. The resident memory
(VmRSS, after a full garbage collection) at the end is compared with that after the
first minute of sim time. Target: within 10 % (ratio <= 1.10). Also printed: tours
done and failed, collisions, the Python object count, and the real-time factor.
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMEXPR_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import gc  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

from btnav.core.geometry import Pose2D  # noqa: E402
from btnav.mission import Mission  # noqa: E402
from btnav.mission.counters import NavigationCounters  # noqa: E402
from btnav.mission.trajectory import TrajectoryRecorder  # noqa: E402
from btnav.params.updates import parse_set_option  # noqa: E402

REPO = Path(__file__).resolve().parents[1]
TOUR = REPO / "missions" / "office_tour.yaml"
TARGET_RATIO = 1.10
FIRST_MINUTE = 60.0


def rss_mib() -> float:
    """Resident memory after a full collection (Linux /proc)."""
    gc.collect()
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024.0
    raise RuntimeError("no VmRSS in /proc/self/status")


def main() -> int:
    ap = argparse.ArgumentParser(
        prog="python bench/soak.py",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    ap.add_argument(
        "--hours",
        type=float,
        default=1.0,
        help="how many hours of sim time to run the tours for (default 1.0, about 10 min of "
        "wall time at 6x real time); more than a minute, since the memory at the end is "
        "compared with that after the first minute",
    )
    ap.add_argument(
        "--set",
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help="override a param or mission key, as `btnav run --set` does; repeatable",
    )
    args = ap.parse_args()
    limit = args.hours * 3600.0
    if not limit > FIRST_MINUTE:
        ap.error(f"--hours must be more than a minute ({FIRST_MINUTE / 3600:.4f} h)")

    mission = Mission.load(TOUR, overrides=dict(parse_set_option(s) for s in args.set))
    nav = mission.navigator()
    recorder = nav.runtime.add(TrajectoryRecorder(nav.runtime, nav.stack.controller_server.rate))
    counters = NavigationCounters()
    nav.bt_navigator.tick_listeners.append(counters)
    loop = [Pose2D(*p) for p in mission.spec.task.poses] + [Pose2D(*mission.spec.initial_pose)]

    print(f"soak: {args.hours:g} h of sim time of office tours ({len(loop)} waypoints each)")
    tours = failed = 0
    first: tuple[float, int] | None = None
    wall0 = time.perf_counter()
    while nav.now < limit:
        nav.follow_waypoints(loop)
        while not nav.is_task_complete():
            if first is None and nav.now >= FIRST_MINUTE:
                first = (rss_mib(), len(gc.get_objects()))
                print(f"  after {nav.now:.0f} s sim: {first[0]:.1f} MiB, {first[1]} objects")
        result = nav.get_result()
        tours += 1
        failed += not (result is not None and result.succeeded and not result.value.missed_indices)
        print(
            f"  tour {tours:3d} ended at {nav.now:7.0f} s sim ({result}), "
            f"{rss_mib():.1f} MiB, collisions {nav.world.collisions}",
            flush=True,
        )
    wall = time.perf_counter() - wall0
    assert first is not None
    end = (rss_mib(), len(gc.get_objects()))
    ratio = end[0] / first[0]
    print(f"\n  sim time                 {nav.now:10.0f} s  ({nav.now / wall:.1f}x real time)")
    print(
        f"  tours                    {tours:10d}    failed {failed}, collisions {nav.world.collisions}"
    )
    print(f"  recoveries / replans     {counters.recoveries:10d} / {counters.replans}")
    print(f"  path length              {recorder.path_length:10.0f} m")
    print(f"  objects                  {first[1]:10d} -> {end[1]}")
    print(
        f"  memory (RSS)             {first[0]:10.1f} -> {end[0]:.1f} MiB   target ratio <= "
        f"{TARGET_RATIO:.2f}  ratio {ratio:.3f} {'ok' if ratio <= TARGET_RATIO else 'ABOVE TARGET'}"
    )
    return 0 if ratio <= TARGET_RATIO else 1


if __name__ == "__main__":
    raise SystemExit(main())
