"""AMCL's cost: one filter update, and the office tour's real-time factor with AMCL.

    python bench/localization.py [--runs 3] [--repeat 200] [--skip-tour]

1. One AMCL update on the office map (maps/small_office.yaml) with Nav2's amcl section:
   2000 particles spread round the robot's start (0.3 m, 0.2 rad), a 360-beam scan of
   the world thinned to 60 beams, the likelihood_field model. Timed: the laser model
   alone (particles x beams), and the whole update (motion model, laser model,
   weights, low-variance KLD resampling, clustering). Beside them the same laser model
   written plainly in numpy (the floor: np.sin/np.cos of every particle x beam angle,
   an np.exp per beam end, the distance field gathered by cell), which is what any
   vectorised version pays at least, less the tables. Target: the whole update <= 5 ms.
2. The office tour (the demo mission, MPPI, seed 0) with ground truth and with AMCL
   (`mission.localization=amcl`): the real-time factor (sim / wall seconds, best of
   `--runs`) of each and their ratio. Target: AMCL keeps >= 85% of ground truth's RTF.

numpy runs single-threaded: one core.
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMEXPR_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from btnav.localization.amcl import Amcl  # noqa: E402
from btnav.localization.amcl.laser_models import LaserData  # noqa: E402
from btnav.localization.amcl.likelihood_field import MapField  # noqa: E402
from btnav.mission.mission import Mission  # noqa: E402
from btnav.mission.runner import run_mission  # noqa: E402

REPO = Path(__file__).resolve().parents[1]
TOUR = REPO / "missions" / "office_tour.yaml"
PARTICLES = 2000
UPDATE_TARGET_MS = 5.0
RTF_KEPT_TARGET = 0.85


def _best_ms(fn, repeat: int) -> float:
    fn()
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best * 1e3


def plain_numpy(
    field: MapField,
    poses: np.ndarray,
    data: LaserData,
    z_hit: float,
    z_rand: float,
    sigma: float,
    max_beams: int,
) -> np.ndarray:
    """The likelihood_field model written the plain way (the floor)."""
    step = max(1, (len(data.ranges) - 1) // (max_beams - 1))
    r = data.ranges[::step]
    b = data.bearings[::step]
    ok = r < data.range_max
    r, b = r[ok], b[ok]
    ang = poses[:, 2:3] + b[None, :]
    lx = (
        poses[:, 0]
        + data.laser_xy[0] * np.cos(poses[:, 2])
        - data.laser_xy[1] * np.sin(poses[:, 2])
    )
    ly = (
        poses[:, 1]
        + data.laser_xy[0] * np.sin(poses[:, 2])
        + data.laser_xy[1] * np.cos(poses[:, 2])
    )
    hx = lx[:, None] + r * np.cos(ang)
    hy = ly[:, None] + r * np.sin(ang)
    res, o = field.resolution, field.origin
    ci = np.floor((hx - o.x) / res).astype(np.intp)
    cj = np.floor((hy - o.y) / res).astype(np.intp)
    inside = (ci >= 0) & (ci < field.width) & (cj >= 0) & (cj < field.height)
    z = np.full(ci.shape, field.max_occ_dist)
    z[inside] = field.occ_dist[cj[inside], ci[inside]]
    pz = z_hit * np.exp(-(z * z) / (2 * sigma * sigma)) + z_rand / data.range_max
    return 1.0 + (pz**3).sum(axis=1)


def bench_update(repeat: int) -> None:
    mission = Mission.load(TOUR, overrides={"mission.localization": "amcl"})
    nav = mission.navigator()
    rt = nav.runtime
    amcl: Amcl = rt.localizer
    p = amcl.params
    assert amcl.field is not None
    field = amcl.field
    rt.spin_for(0.1)
    scan = rt.latest_scan
    assert scan is not None
    laser = rt.frames.lookup(p.base_frame_id, scan.frame_id)
    data = LaserData.from_scan(
        scan, (laser.x, laser.y, laser.yaw), p.laser_min_range, p.laser_max_range
    )
    gt = rt.world.robot_pose
    rng = np.random.default_rng(0)
    poses = np.stack(
        [
            gt.x + 0.3 * rng.standard_normal(PARTICLES),
            gt.y + 0.3 * rng.standard_normal(PARTICLES),
            gt.yaw + 0.2 * rng.standard_normal(PARTICLES),
        ],
        axis=1,
    )
    model = amcl.laser_model
    beams = len(model.beam_indices(len(data.ranges)))

    def laser_only() -> None:
        model.sensor_function(field, poses, data)

    def whole() -> None:
        pf = amcl.pf
        pf.poses = poses.copy()
        pf.weights = np.full(PARTICLES, 1.0 / PARTICLES)
        pf.max_samples = PARTICLES
        pf.poses = amcl.motion_model.odometry_update(
            pf.poses, (0.3, 0.0, 0.05), (0.25, 0.0, 0.05), amcl.rng
        )
        pf.update_sensor(model.sensor_function(field, pf.poses, data))
        pf.resample(amcl.uniform_poses)

    def floor() -> None:
        plain_numpy(field, poses, data, p.z_hit, p.z_rand, p.sigma_hit, p.max_beams)

    ref = plain_numpy(field, poses, data, p.z_hit, p.z_rand, p.sigma_hit, p.max_beams)
    ours = model.sensor_function(field, poses, data)
    agree = float(np.max(np.abs(ours - ref) / ref))
    t_laser = _best_ms(laser_only, repeat)
    t_whole = _best_ms(whole, max(10, repeat // 4))
    t_floor = _best_ms(floor, repeat)
    print(
        f"AMCL update, {PARTICLES} particles x {beams} beams, likelihood_field (best of {repeat}):"
    )
    print(f"  laser model (btnav)          {t_laser:7.2f} ms")
    print(
        f"  plain numpy laser model      {t_floor:7.2f} ms   btnav / plain = "
        f"{t_laser / t_floor:.2f}  (max relative difference {agree:.1e})"
    )
    print(
        f"  whole update (motion, laser, weights, resample, clusters) {t_whole:7.2f} ms"
        f"   target {UPDATE_TARGET_MS:g} ms: {'ok' if t_whole <= UPDATE_TARGET_MS else 'MISSED'}"
    )


def bench_tour(runs: int) -> None:
    rtf: dict[str, float] = {}
    for name in ("ground_truth", "amcl"):
        best = 0.0
        for _ in range(runs):
            mission = Mission.load(TOUR, overrides={"mission.localization": name})
            report = run_mission(mission, None)
            best = max(best, report.sim_time / report.wall_time)
            err = report.localization_error
        rtf[name] = best
        print(
            f"office tour, {name:12s}: {report.status}, {report.sim_time:.1f} s sim, "
            f"RTF {best:.2f} (best of {runs}), {report.collisions} collisions, "
            f"localisation rms {err['rms_xy'] * 100:.1f} cm / "
            f"{np.degrees(err['rms_yaw']):.1f} deg"
        )
    kept = rtf["amcl"] / rtf["ground_truth"]
    print(
        f"  AMCL keeps {kept:.0%} of ground truth's RTF (target >= {RTF_KEPT_TARGET:.0%}: "
        f"{'ok' if kept >= RTF_KEPT_TARGET else 'MISSED'})"
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--repeat", type=int, default=200)
    ap.add_argument("--skip-tour", action="store_true")
    args = ap.parse_args()
    bench_update(args.repeat)
    if not args.skip_tour:
        bench_tour(args.runs)


if __name__ == "__main__":
    main()
