"""Doorway robustness: the closing-door mission on many seeds with each of Nav2's controllers.

    python bench/doorway.py [--seeds 0:20] [--controllers mppi,dwb,rpp] [--workers 2]

`missions/doorway_closing.yaml`: a door closes the lower doorway 4 s into the run, the
map does not know it, and the robot must replan round by the upper doorways. Each
controller runs with its params file (Nav2's nav2_params.yaml for MPPI,
params/nav2_params_dwb.yaml and params/nav2_params_rpp.yaml for Nav2's documented DWB
and RPP sections) on every seed. A run passes when it succeeds with no contact within
the target of 90 s of sim time. Printed per controller: passes / runs (target: all),
the slowest run, and every failing seed with its status, sim time, contacts and
recoveries. A quality bound, not a timing: the ratio is passes over runs.
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMEXPR_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
from concurrent.futures import ProcessPoolExecutor  # noqa: E402
from pathlib import Path  # noqa: E402

REPO = Path(__file__).resolve().parents[1]
MISSION = REPO / "missions" / "doorway_closing.yaml"
PARAMS = {
    "mppi": REPO / "params" / "nav2_params.yaml",
    "dwb": REPO / "params" / "nav2_params_dwb.yaml",
    "rpp": REPO / "params" / "nav2_params_rpp.yaml",
}
TARGET_SIM_TIME = 90.0


def run_one(controller: str, seed: int) -> tuple[str, int, str, float, int, int]:
    """One run in a fresh process (the py_trees blackboard is process-wide)."""
    from btnav.mission import Mission, run_mission

    mission = Mission.load(
        MISSION, seed=seed, overrides={"mission.params": str(PARAMS[controller])}
    )
    r = run_mission(mission)
    return controller, seed, r.status, r.sim_time, r.collisions, r.recoveries


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", default="0:20", help="A:B, seeds A to B-1 (default 0:20)")
    ap.add_argument("--controllers", default="mppi,dwb,rpp", help="comma-separated")
    ap.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    args = ap.parse_args()
    lo, hi = (int(v) for v in args.seeds.split(":"))
    controllers = [c.strip() for c in args.controllers.split(",") if c.strip()]
    jobs = [(c, s) for c in controllers for s in range(lo, hi)]
    with ProcessPoolExecutor(args.workers) as pool:
        results = list(pool.map(run_one, *zip(*jobs, strict=True)))
    for c in controllers:
        rows = [r for r in results if r[0] == c]
        bad = [r for r in rows if r[2] != "succeeded" or r[4] > 0 or r[3] > TARGET_SIM_TIME]
        slowest = max(r[3] for r in rows)
        passes = len(rows) - len(bad)
        print(
            f"{c:5s} {passes}/{len(rows)} pass (ratio {passes / len(rows):.2f}, target 1.00); "
            f"slowest {slowest:.1f} s sim (target <= {TARGET_SIM_TIME:g})"
        )
        for _, seed, status, sim, contacts, rec in bad:
            print(
                f"      seed {seed}: {status}, {sim:.1f} s, {contacts} contacts, {rec} recoveries"
            )


if __name__ == "__main__":
    main()
