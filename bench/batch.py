"""Batch runs: the speed-up of more workers, and what a run's own process costs.

    python bench/batch.py [--runs 20] [--no-ray]

The batch: one short mission (the small office, ground-truth localisation, Nav2's
params, one NavigateToPose from (1, 1) to (3, 2), about 8 s of sim time) on seeds
0..N-1. Printed, each with its target:

- in-process: the N runs one after another in this process (`Mission.load` +
  `run_mission`), the baseline;
- 1 worker and 2 workers: `run_batch` (each run in a fresh process forked from the fork
  server, rows appended to results.csv, the summary written), wall time end to end;
- the speed-up of 2 workers over 1 (target >= 1.8x on 2 cores), beside what a bare
  Python loop gets on 2 processes at the same moment (other work on the machine lowers
  both);
- the overhead per run of a worker against in-process, as a share of a run's wall time
  (target < 10%): (1 worker - in-process) / N, checking and the fork server's start
  included;
- with Ray installed, the same batch on a local Ray with 2 CPUs, against 2 local
  workers (target overhead < 15%), with Ray's own start-up (ray.init) shown apart.

numpy runs single-threaded, so a run is one core. The machine's other load shows in
every figure: compare ratios from one invocation, not across machines.
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMEXPR_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import yaml  # noqa: E402

from btnav.batch import run_batch  # noqa: E402
from btnav.mission import Mission, run_mission  # noqa: E402

REPO = Path(__file__).resolve().parents[1]
MISSION = {
    "mission": "short",
    "world": str(REPO / "worlds" / "small_office.yaml"),
    "params": str(REPO / "params" / "nav2_params.yaml"),
    "map": str(REPO / "maps" / "small_office.yaml"),
    "localization": "ground_truth",
    "initial_pose": [1.0, 1.0, 0.0],
    "task": {"navigate_to_pose": [3.0, 2.0, 1.57]},
    "time_limit": 60,
    "seed": 0,
    "outputs": ["report", "trajectory", "bt_log"],
}
TARGET_SPEEDUP, TARGET_OVERHEAD, TARGET_RAY = 1.8, 0.10, 0.15


def in_process(path: Path, seeds: list[int], out: Path) -> float:
    t0 = time.perf_counter()
    for seed in seeds:
        run_mission(Mission.load(path, seed=seed), out / f"seed-{seed}")
    return time.perf_counter() - t0


def batch(path: Path, seeds: list[int], out: Path, workers: int, backend: str = "local") -> float:
    t0 = time.perf_counter()
    records = run_batch([path], out=out, seeds=seeds, workers=workers, backend=backend)
    wall = time.perf_counter() - t0
    assert len(records) == len(seeds), records
    failed = [r for r in records if not r.succeeded]
    if failed:
        print(f"  ({len(failed)} runs failed: {failed[0].status} {failed[0].error_msg})")
    return wall


def _spin(_: int) -> int:
    total = 0
    for i in range(10_000_000):
        total += i
    return total


def machine_speedup() -> float:
    """What 2 processes get on this machine right now, for a loop with nothing shared: the
    ceiling of the batch's speed-up while other work shares the cores."""
    import multiprocessing

    t0 = time.perf_counter()
    for i in range(4):
        _spin(i)
    serial = time.perf_counter() - t0
    with multiprocessing.get_context("spawn").Pool(2) as pool:
        pool.map(_spin, [0])  # the pool is up before the clock starts
        t0 = time.perf_counter()
        pool.map(_spin, range(4), chunksize=1)
        parallel = time.perf_counter() - t0
    return serial / parallel


def mark(ok: bool) -> str:
    return "ok" if ok else "MISSED"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=20, help="the batch's size (20)")
    parser.add_argument("--no-ray", action="store_true", help="skip the Ray backend")
    args = parser.parse_args()
    seeds = list(range(args.runs))
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        path = folder / "short.yaml"
        path.write_text(yaml.safe_dump(MISSION, sort_keys=False))
        print(f"batch of {args.runs} short missions ({os.cpu_count()} cores)")
        base = in_process(path, seeds, folder / "alone")
        per_run = base / args.runs
        print(f"  in-process      {base:7.1f} s  ({per_run:.2f} s a run)")
        one = batch(path, seeds, folder / "w1", 1)
        print(f"  1 worker        {one:7.1f} s")
        two = batch(path, seeds, folder / "w2", 2)
        print(f"  2 workers       {two:7.1f} s")
        speedup = one / two
        ceiling = machine_speedup()
        overhead = (one - base) / args.runs / per_run
        print(
            f"speed-up 2 workers / 1: {speedup:.2f}x "
            f"(target >= {TARGET_SPEEDUP}x: {mark(speedup >= TARGET_SPEEDUP)}); a bare "
            f"loop on 2 processes gets {ceiling:.2f}x on this machine now"
        )
        print(
            f"overhead of a worker per run: {(one - base) / args.runs * 1000:+.0f} ms, "
            f"{100 * overhead:+.1f}% of a run (target < {100 * TARGET_OVERHEAD:.0f}%: "
            f"{mark(overhead < TARGET_OVERHEAD)})"
        )
        if args.no_ray:
            return
        try:
            import ray
        except ImportError:
            print("ray: not installed (pip install -e '.[ray]'); skipped")
            return
        t0 = time.perf_counter()
        ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False, logging_level="ERROR")
        start = time.perf_counter() - t0
        try:
            on_ray = batch(path, seeds, folder / "ray", 2, backend="ray")
        finally:
            ray.shutdown()
        extra = on_ray / two - 1
        print(f"  ray, 2 CPUs     {on_ray:7.1f} s  (+ {start:.1f} s of ray.init)")
        print(
            f"ray overhead against 2 local workers: {100 * extra:+.1f}% "
            f"(target < {100 * TARGET_RAY:.0f}%: {mark(extra < TARGET_RAY)}); "
            f"with ray.init: {100 * ((on_ray + start) / two - 1):+.1f}%"
        )


if __name__ == "__main__":
    main()
