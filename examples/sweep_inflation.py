"""Ten goal sets across inflation radii: which radius gets the robot through the office best?

    python examples/sweep_inflation.py [--radii 0.35:0.75:0.2] [--seeds 0:1] [--workers N]
                                       [--out out/sweep_inflation] [--amcl] [--sets N]

The intermediate engineer's loop (change the costmap's inflation radius, rerun ten sets
of goals, compare) as one batch: ten missions in the small office, each from (1, 1)
through two of the demo tour's waypoints in a different order, run for every value of
the global costmap's `inflation_layer.inflation_radius` (and, with `--local`, every
pair of it with the local costmap's), then the summary table. The same batch from the shell:

    btnav batch out/sweep_inflation/missions/*.yaml --seeds 0:1 \\
        --sweep global_costmap.global_costmap.inflation_layer.inflation_radius=0.35:0.75:0.2 \\
        --out out/sweep_inflation

Interrupt it and run it again: only the missing runs run.
"""

from __future__ import annotations

import argparse
import itertools
import sys
from pathlib import Path

import yaml

from btnav.batch import parse_seeds, parse_values, run_batch
from btnav.batch.summary import markdown, summarize
from btnav.cli.batch_progress import default_progress

REPO = Path(__file__).resolve().parents[1]
GLOBAL = "global_costmap.global_costmap.inflation_layer.inflation_radius"
LOCAL = "local_costmap.local_costmap.inflation_layer.inflation_radius"
#: The demo tour's waypoints (missions/office_tour.yaml): the rooms and doorways.
POINTS = [(3.0, 2.0, 1.57), (6.0, 3.0, 0.0), (9.0, 1.5, 0.0), (2.5, 6.5, 3.14)]


def goal_sets() -> list[list[tuple[float, float, float]]]:
    """Ten ordered pairs of the tour's waypoints."""
    return [list(pair) for pair in itertools.permutations(POINTS, 2)][:10]


def write_missions(folder: Path, localization: str, sets: int = 10) -> list[Path]:
    folder.mkdir(parents=True, exist_ok=True)
    paths = []
    for n, goals in enumerate(goal_sets()[:sets], start=1):
        doc = {
            "mission": f"goals-{n:02d}",
            "world": str(REPO / "worlds" / "small_office.yaml"),
            "params": str(REPO / "params" / "nav2_params.yaml"),
            "map": str(REPO / "maps" / "small_office.yaml"),
            "localization": localization,
            "initial_pose": [1.0, 1.0, 0.0],
            "task": {"follow_waypoints": [list(p) for p in goals]},
            "time_limit": 180,
            "seed": 0,
            "outputs": ["report", "trajectory"],
        }
        path = folder / f"goals-{n:02d}.yaml"
        path.write_text(yaml.safe_dump(doc, sort_keys=False))
        paths.append(path)
    return paths


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--radii", default="0.35:0.75:0.2", help="values or START:STOP:STEP")
    parser.add_argument("--seeds", default="0:1", help="seeds, START:STOP (STOP excluded)")
    parser.add_argument("--workers", type=int, help="runs at once (default: every core)")
    parser.add_argument("--out", default="out/sweep_inflation", help="the batch's folder")
    parser.add_argument("--amcl", action="store_true", help="AMCL instead of ground truth")
    parser.add_argument(
        "--local", action="store_true", help="sweep the local costmap's too (every pair)"
    )
    parser.add_argument(
        "--sets", type=int, default=10, help="the first N goal sets only (a quick look)"
    )
    args = parser.parse_args()
    out = Path(args.out)
    missions = write_missions(out / "missions", "amcl" if args.amcl else "ground_truth", args.sets)
    radii = parse_values(args.radii, origin=f"--radii {args.radii}")
    sweep = {GLOBAL: radii, **({LOCAL: radii} if args.local else {})}
    records = run_batch(
        missions,
        out=out,
        seeds=parse_seeds(args.seeds),
        sweep=sweep,
        workers=args.workers,
        progress=default_progress(sys.stdout),
    )
    # one line per radius over all the goal sets, then the per-mission table
    label = "all ten" if len(missions) == 10 else f"all {len(missions)}"
    pooled = [type(r)(**{**r.__dict__, "mission": label}) for r in records]
    print()
    print(markdown(summarize(pooled)), end="")
    print(f"\nper goal set: {out / 'summary.md'}; every run: {out / 'results.csv'}")
    return 0 if all(r.succeeded for r in records) else 1


if __name__ == "__main__":
    sys.exit(main())
