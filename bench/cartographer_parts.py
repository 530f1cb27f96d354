"""Where btnav's Cartographer spends its CPU time on a recorded log, part by part.

    python bench/cartographer_parts.py [LOG] [--lua F] [--scans N]

Runs `btnav slam LOG --lua F`'s engine (`run_cartographer`, default log
../shared/slam_logs/intel.clf, default options params/cartographer_2d.lua, the first N
scans with --scans) with each part timed in CPU seconds (time.process_time: a shared
machine stretches wall time, not CPU time): the loop-closure searches (how many, how
many batches, how many found), their Ceres refinements, the real-time correlative and
Ceres matches of local SLAM, the submap insertions and the global optimisations; the
rest is everything else (range data, voxel filters, motion filter, bookkeeping). The
timers cost a few microseconds a call; the results are the engine's own.
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMEXPR_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import dataclasses  # noqa: E402
import time  # noqa: E402
from collections import Counter  # noqa: E402
from collections.abc import Callable  # noqa: E402
from pathlib import Path  # noqa: E402
from typing import Any  # noqa: E402

from btnav.slam.cartographer import slam as cartographer_slam  # noqa: E402
from btnav.slam.cartographer import submaps  # noqa: E402
from btnav.slam.cartographer.config import load_cartographer_config  # noqa: E402
from btnav.slam.cartographer.offline import run_cartographer  # noqa: E402
from btnav.slam.logs import read_log  # noqa: E402

REPO = Path(__file__).resolve().parents[1]
CPU: Counter[str] = Counter()
COUNT: Counter[str] = Counter()


def timed(name: str, f: Callable[..., Any], count: Callable[..., int] | None = None) -> Callable[..., Any]:  # fmt: skip
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        t = time.process_time()
        out = f(*args, **kwargs)
        CPU[name] += time.process_time() - t
        COUNT[name] += count(*args) if count else 1
        return out

    return wrapper


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("log", nargs="?", type=Path, default=REPO.parent / "shared/slam_logs/intel.clf")  # fmt: skip
    ap.add_argument("--lua", default=str(REPO / "params/cartographer_2d.lua"))
    ap.add_argument("--scans", type=int, default=0, help="only the first N scans")
    args = ap.parse_args()
    from slam_logs import fix_geometry  # bench/slam_logs.py: the family's scan geometry

    log = read_log(args.log)
    note = fix_geometry(log, "auto")
    if args.scans:
        log = dataclasses.replace(log, scans=log.scans[: args.scans])
    cs = cartographer_slam
    found = Counter()
    search = cs.match_batch

    def batch(queries: Any, *rest: Any) -> Any:
        out = search(queries, *rest)
        found["found"] += sum(f is not None for f in out)
        found["batches"] += 1
        return out

    cs.match_batch = timed("loop-closure searches", batch, lambda q, *_: len(q))
    ceres = cs.ceres_match
    cs.ceres_match = timed("Ceres matches", ceres)
    cs.real_time_correlative_match = timed("real-time correlative matches", cs.real_time_correlative_match)  # fmt: skip
    cs.optimize_huber = timed("global optimisations", cs.optimize_huber)
    submaps.ActiveSubmaps.insert = timed("submap insertions", submaps.ActiveSubmaps.insert)
    t = time.process_time()
    result = run_cartographer(log, load_cartographer_config(args.lua))
    total = time.process_time() - t
    duration = log.scans[-1].stamp - log.scans[0].stamp
    print(f"{args.log.name}: {len(log.scans)} scans ({note}), {duration:.0f} s of log, "
          f"{len(result.mapper.scans)} nodes, {result.mapper.loop_closures} loop closures")  # fmt: skip
    print(f"  {total:.1f} s CPU, {duration / total:.2f}x real time")
    for name, cpu in CPU.most_common():
        calls = f"{COUNT[name]} calls"
        if name == "loop-closure searches":
            calls = f"{COUNT[name]} searches in {found['batches']} batches, {found['found']} found"
        print(f"  {name:<32} {cpu:7.1f} s  {100 * cpu / total:5.1f}%  ({calls})")
    rest = total - sum(CPU.values())
    print(f"  {'the rest':<32} {rest:7.1f} s  {100 * rest / total:5.1f}%")


if __name__ == "__main__":
    main()
