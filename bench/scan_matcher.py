"""Karto's correlative scan matcher (btnav.slam.karto.scan_matcher): milliseconds per match.

    python bench/scan_matcher.py [--repeat 20]

Scans are cast in the small office world (worlds/small_office.yaml, 360 beams, 8 m),
from poses along a walk through the left room and the doorway into the lower right
room. Timed, best and median of `--repeat`:

1. the sequential matcher (slam_toolbox's correlation_search_space_*: 0.5 m at 0.01 m,
   smear 0.1 m, +-0.349 rad at 0.0349, penalised, refined) matching a scan against the
   10 scans before it, guess off by (0.123, -0.087, 0.05). Target: well under 50 ms.
2. the loop matcher (loop_search_space_*: 8 m at 0.05 m, smear 0.03 m, not penalised,
   not refined, as Karto's TryCloseLoop runs it) matching a scan 2 m / 0.3 rad off
   against chains of 10 and 30 scans. Target: under 150 ms.

Each line also prints the pose error of the match, as a check that it timed real work.
numpy runs single-threaded: one core.
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMEXPR_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import math  # noqa: E402
import time  # noqa: E402
from collections.abc import Callable  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from btnav.core import fmath  # noqa: E402
from btnav.core.geometry import Pose2D, angle_diff  # noqa: E402
from btnav.sim.raycast import cast_from_pose  # noqa: E402
from btnav.sim.world import World  # noqa: E402
from btnav.slam.karto.scan_matcher import MatcherParams, MatchResult, ScanMatcher  # noqa: E402

REPO = Path(__file__).resolve().parents[1]
WORLD = REPO / "worlds" / "small_office.yaml"
BEAMS, RANGE = 360, 8.0
SEQUENTIAL_TARGET_MS, LOOP_TARGET_MS = 50.0, 150.0


def walk(n: int) -> list[tuple[float, float, float]]:
    """n poses up the left room, then right through the doorway at y 3-4 (x = 4)."""
    out = []
    for i in range(n):
        s = i / max(n - 1, 1)
        if s < 0.6:
            out.append((1.6 + 0.8 * s, 1.0 + 4.0 * s, 1.2 + 0.4 * s))
        else:
            u = (s - 0.6) / 0.4
            out.append((2.1 + 3.5 * u, 3.5, 0.2 * (1 - u)))
    return out


def scan(geometry, pose) -> np.ndarray:
    """(N, 2) end points in the robot frame (the lidar at the robot's centre)."""
    angles = -math.pi + np.arange(BEAMS) * (2 * math.pi / BEAMS)
    r = cast_from_pose(geometry, pose, angles, RANGE)
    ok = np.isfinite(r) & (r > 0.12) & (r < RANGE)
    s, c = fmath.sincos(angles[ok])
    return np.stack([r[ok] * c, r[ok] * s], axis=1)


def timed(fn: Callable[[], MatchResult], repeat: int) -> tuple[float, float, MatchResult]:
    result = fn()
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append((time.perf_counter() - t0) * 1e3)
    return min(times), float(np.median(times)), result


def error(result: MatchResult, truth) -> str:
    d = math.hypot(result.pose[0] - truth[0], result.pose[1] - truth[1])
    a = abs(angle_diff(float(result.pose[2]), truth[2]))
    return f"error {d * 100:.1f} cm {math.degrees(a):.2f} deg, response {result.response:.2f}"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=20)
    args = ap.parse_args()

    geometry = World.from_file(WORLD).geometry()
    poses = walk(31)
    scans = [scan(geometry, p) for p in poses]
    reference = [
        (Pose2D(*p).transform_points(s), np.array(p)) for p, s in zip(poses, scans, strict=True)
    ]

    sequential = ScanMatcher(MatcherParams.sequential(range_threshold=RANGE))
    truth = poses[20]
    guess = np.array(truth) - (0.123, -0.087, 0.05)
    best, med, res = timed(
        lambda: sequential.match(scans[20], guess, reference[10:20]), args.repeat
    )
    print(
        f"sequential (0.5 m @ 0.01 m, N={len(scans[20])}, 10 reference scans): "
        f"{best:.1f} ms best, {med:.1f} ms median (target < {SEQUENTIAL_TARGET_MS:.0f}); "
        + error(res, truth)
    )

    loop = ScanMatcher(MatcherParams.loop(range_threshold=RANGE))
    truth = poses[30]
    guess = np.array(truth) - (1.63, 1.17, 0.3)
    for chain in (10, 30):
        ref = reference[30 - chain : 30] if chain < 30 else reference[:30]
        best, med, res = timed(
            lambda ref=ref: loop.match(scans[30], guess, ref, penalize=False, refine=False),
            args.repeat,
        )
        print(
            f"loop (8 m @ 0.05 m, N={len(scans[30])}, chain of {len(ref)} scans): "
            f"{best:.1f} ms best, {med:.1f} ms median (target < {LOOP_TARGET_MS:.0f}); "
            + error(res, truth)
        )


if __name__ == "__main__":
    main()
