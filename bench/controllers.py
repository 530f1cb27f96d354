"""Compute time per control cycle of btnav's controllers, against the 20 Hz control period.

    python bench/controllers.py [--cycles 200] [--no-profile]

- MPPI (`nav2_mppi_controller::MPPIController`) from Nav2's own nav2_params.yaml
  FollowPath section: 2000 rollouts x 56 steps, the 8 critics Nav2 lists.
  Target: <= 10 ms per cycle on one core.
- DWB (`dwb_core::DWBLocalPlanner`) with 20 x 40 velocity samples. Target: one 20 Hz
  control period, 50 ms.
- Regulated Pure Pursuit. Target: <= 10 ms per cycle (it is a geometric controller).

Each prints its ratio to its own target (below 1.00 is within it); a controller not
registered is skipped with a message. (These bounds were timed asserts in
tests/control; a benchmark is not a timed test.)

Each runs on a free 3 m x 3 m rolling-style local costmap (0.05 m, Nav2's local
costmap) with an obstacle beside a curved path, the robot mid-path so every critic
is active. numpy runs single-threaded. A short profile of MPPI's cycle follows:
the share of each stage (noise, motion model, rollouts, each critic, softmax).
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMEXPR_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import math  # noqa: E402
import time  # noqa: E402
from collections import defaultdict  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from btnav import plugins  # noqa: E402
from btnav.core.errors import PluginError  # noqa: E402
from btnav.core.geometry import Pose2D  # noqa: E402
from btnav.core.messages import Path as PathMsg  # noqa: E402
from btnav.core.messages import Twist  # noqa: E402
from btnav.costmap.cost_values import INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE  # noqa: E402
from btnav.costmap.costmap_2d import Costmap2D  # noqa: E402
from btnav.params import load_params  # noqa: E402

NAV2_PARAMS = (
    Path(__file__).resolve().parents[1].parent / "shared" / "nav2" / "params" / "nav2_params.yaml"
)
PERIOD_MS = 1000.0 / 20.0
MPPI_TARGET_MS = 10.0
DWB_TARGET_MS = PERIOD_MS
RPP_TARGET_MS = 10.0


def scene() -> tuple[PathMsg, Costmap2D, Pose2D, Twist]:
    """A curved path, a 3 m local costmap around the robot with an inflated obstacle."""
    step = 0.025
    t = np.arange(0.0, math.pi / 2, step / 3.0)
    poses = np.stack([3.0 * np.sin(t), 3.0 * (1 - np.cos(t)), t], axis=-1)
    robot = Pose2D(0.5, 0.05, 0.15)
    cm = Costmap2D.empty(60, 60, 0.05, robot.x - 1.5, robot.y - 1.5, frame_id="odom")
    mx, my = np.meshgrid(np.arange(60), np.arange(60))
    wx, wy = cm.origin_x + (mx + 0.5) * 0.05, cm.origin_y + (my + 0.5) * 0.05
    d = np.hypot(wx - 1.3, wy - 0.85) - 0.1
    cost = np.where(d <= 0, LETHAL_OBSTACLE, np.where(d <= 0.22, INSCRIBED_INFLATED_OBSTACLE, 0))
    ring = (d > 0.22) & (d < 0.55)
    cost = np.where(ring, np.floor(252 * np.exp(-3.0 * (d - 0.22))), cost)
    cm.costs[:] = cost.astype(np.uint8)
    return PathMsg(0.0, poses, "odom"), cm, robot, Twist(linear_x=0.3, angular_z=0.1)


def build(name: str, section: str | None, overrides: dict | None = None):
    try:
        cls = plugins.lookup("controller", name)
    except PluginError:
        return None
    params = None
    if section is not None and NAV2_PARAMS.is_file():
        found = load_params(NAV2_PARAMS).servers["controller_server"].plugin(section)
        if found.cls is cls:
            params = found.params
    if params is None:
        params = cls.Params()
    if overrides:
        params = params.model_copy(
            update={k: v for k, v in overrides.items() if k in type(params).model_fields}
        )
    return cls("FollowPath", params)


def time_cycles(controller, cycles: int) -> float:
    path, cm, robot, vel = scene()
    controller.set_plan(path)
    for _ in range(5):
        controller.compute_velocity_commands(robot, vel, cm)
    times = []
    for _ in range(cycles):
        controller.set_plan(path)  # same state every cycle: the robot stays put
        t0 = time.perf_counter()
        controller.compute_velocity_commands(robot, vel, cm)
        times.append(time.perf_counter() - t0)
    return float(np.median(times)) * 1e3


def set_mppi_method(controller, method: str) -> None:
    """MPPI's compiled kernels ("kernel") or the numpy reference ("numpy"), the same bits."""
    from btnav.control.mppi.critic_data import CriticData

    controller.optimizer.method = method
    CriticData.method = method  # the furthest reached path point (class-wide)
    for critic in controller.optimizer.critics:
        if hasattr(critic, "method"):
            critic.method = method


def time_mppi_methods(cycles: int) -> dict[str, float]:
    """Median cycle of each path, A B A B B A (the machine may be shared), best of 3."""
    best = {"numpy": math.inf, "kernel": math.inf}
    for method in ("numpy", "kernel", "numpy", "kernel", "kernel", "numpy"):
        controller = build("nav2_mppi_controller::MPPIController", "FollowPath")
        set_mppi_method(controller, method)
        best[method] = min(best[method], time_cycles(controller, cycles))
    set_mppi_method(controller, "kernel")
    return best


FIRST_CYCLE = """
import time
t0 = time.perf_counter()
import sys
sys.path.insert(0, {bench!r})
import controllers as c
c.plugins.load_entry_points()
ctl = c.build("nav2_mppi_controller::MPPIController", "FollowPath")
path, cm, robot, vel = c.scene()
ctl.set_plan(path)
ctl.compute_velocity_commands(robot, vel, cm)
print(time.perf_counter() - t0)
"""


def compile_cost() -> tuple[float, float]:
    """Seconds from a fresh interpreter to MPPI's first cycle done: with an empty numba
    cache (every kernel compiled: the first run after an install) and then cached."""
    import subprocess
    import sys
    import tempfile

    code = FIRST_CYCLE.format(bench=str(Path(__file__).parent))
    with tempfile.TemporaryDirectory() as cache:
        env = {**os.environ, "NUMBA_CACHE_DIR": cache}
        runs = [
            float(subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                                 text=True, check=True).stdout.split()[-1])
            for _ in range(2)
        ]  # fmt: skip
    return runs[0], runs[1]


def mppi_stage_profile(controller, cycles: int) -> dict[str, float]:
    """Wall time per stage of MPPI's cycle, by wrapping the optimizer's steps and critics."""
    opt = controller.optimizer
    spent: dict[str, float] = defaultdict(float)

    def timed(label, fn):
        def run(*a, **k):
            t0 = time.perf_counter()
            try:
                return fn(*a, **k)
            finally:
                spent[label] += time.perf_counter() - t0

        return run

    opt.noise.sample = timed("noise sampling", opt.noise.sample)
    opt.model.predict = timed("motion model (acceleration loop)", opt.model.predict)
    opt._rollouts = timed("rollout integration", opt._rollouts)
    opt._rollouts_compiled = timed("motion model + rollouts (compiled)", opt._rollouts_compiled)
    opt.noise.sample_controls = timed("noise sampling (compiled add)", opt.noise.sample_controls)
    opt._update_control_sequence = timed("softmax + control update", opt._update_control_sequence)
    opt._trajectory_valid = timed("optimal trajectory validator", opt._trajectory_valid)
    for critic in opt.critics:
        critic.score = timed(f"critic {critic.name}", critic.score)
    path, cm, robot, vel = scene()
    total = 0.0
    for _ in range(cycles):
        controller.set_plan(path)
        t0 = time.perf_counter()
        controller.compute_velocity_commands(robot, vel, cm)
        total += time.perf_counter() - t0
    spent["other (path pruning, smoothing, glue)"] = total - sum(spent.values())
    return {k: v / cycles * 1e3 for k, v in spent.items()}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cycles", type=int, default=200)
    ap.add_argument("--no-profile", action="store_true")
    ap.add_argument(
        "--compile-cost",
        action="store_true",
        help="also time MPPI's first cycle in a fresh interpreter, numba cache empty then warm",
    )
    args = ap.parse_args()
    plugins.load_entry_points()
    print(f"control period at 20 Hz: {PERIOD_MS:.0f} ms; numpy single-threaded\n")
    rows = [
        (
            "MPPI 2000 x 56",
            "nav2_mppi_controller::MPPIController",
            "FollowPath",
            None,
            MPPI_TARGET_MS,
        ),
        (
            "DWB 20 x 40",
            "dwb_core::DWBLocalPlanner",
            "FollowPath",
            {"vx_samples": 20, "vtheta_samples": 40},
            DWB_TARGET_MS,
        ),
        (
            "Regulated Pure Pursuit",
            "nav2_regulated_pure_pursuit_controller::RegulatedPurePursuitController",
            "FollowPath",
            None,
            RPP_TARGET_MS,
        ),
    ]
    mppi = None
    for label, name, section, overrides, target_ms in rows:
        controller = build(name, section, overrides)
        if controller is None:
            print(f"{label:24s} skipped: '{name}' is not registered yet")
            continue
        if name.startswith("nav2_mppi"):
            p = controller.params
            assert (p.batch_size, p.time_steps) == (2000, 56), (p.batch_size, p.time_steps)
            mppi = controller
        if name.startswith("nav2_mppi"):
            both = time_mppi_methods(args.cycles)
            ms = both["kernel"]
            print(
                f"{'  numpy reference':24s} {both['numpy']:8.2f} ms/cycle  compiled "
                f"{ms:.2f} ms: {both['numpy'] / ms:.2f}x faster (best of 3, interleaved)"
            )
        else:
            ms = time_cycles(controller, args.cycles)
        ratio = ms / target_ms
        line = f"{label:24s} {ms:8.2f} ms/cycle  {ms / PERIOD_MS:6.1%} of the 20 Hz period"
        line += f"  target {target_ms:4.0f} ms  ratio {ratio:5.2f}"
        print(line + ("  ok" if ratio <= 1.0 else "  ABOVE TARGET"))
    if mppi is not None and not args.no_profile:
        stages = mppi_stage_profile(build(rows[0][1], "FollowPath"), max(args.cycles // 2, 20))
        total = sum(stages.values())
        print(f"\nMPPI cycle by stage ({total:.2f} ms, timers included):")
        for label, ms in sorted(stages.items(), key=lambda kv: -kv[1]):
            print(f"  {label:40s} {ms:6.2f} ms  {ms / total:6.1%}")
        top = max(stages, key=stages.get)  # type: ignore[arg-type]
        print(f"dominant: {top}")
    if args.compile_cost:
        cold, warm = compile_cost()
        print(f"\nMPPI first cycle in a fresh interpreter: {cold:.1f} s with an empty numba")
        print(f"cache (every kernel compiled), {warm:.1f} s cached")


if __name__ == "__main__":
    main()
