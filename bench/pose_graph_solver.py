"""The pose-graph optimiser (btnav.slam.graph.pose_graph) against gtsam, and its linear solvers.

    python bench/pose_graph_solver.py [--repeat 3] [--skip-coretypes] [--skip-pcg]

Graphs (both built here, seeded):
- Manhattan (M3500-like): a random walk of 3500 poses on a 1 m grid (a turn left or
  right at 70% of the steps), odometry edges with noise (0.05 m, 0.05 m, 0.01 rad),
  a loop-closure edge whenever the walk comes back to a cell (to the previous visit),
  poses initialised by chaining the noisy odometry.
- Circle: 1000 poses on a 50 m circle, odometry edges and one loop closure, same noise.

Printed, for each graph: the time of `optimize_poses` with btnav's deterministic block
Cholesky and with scipy's SuperLU, and of gtsam's LevenbergMarquardtOptimizer on the
same graph (prior on node 0, COLAMD, multifrontal Cholesky, relative tolerance 1e-6);
their ratios; the final errors of each solution measured both ways (btnav's error is
the sum of squared residuals, gtsam's half a sum with its Log-map residual); iterations
and the position RMSE to the truth. Then one LM step's linear system solved by block-
Jacobi PCG (scipy's CSR matvec: a lower bound of a numpy-only PCG's cost): iterations
and time to 1e-6 relative accuracy. Then each solver's result bits under different
OpenBLAS kernels (OPENBLAS_CORETYPE, in child processes): the Cholesky's must not move.
gtsam is not a btnav dependency: `pip install gtsam`; without it those columns say so.

numpy runs single-threaded: one core. Times are the best of `--repeat` runs.
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMEXPR_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from collections.abc import Callable  # noqa: E402

import numpy as np  # noqa: E402
import scipy.sparse.linalg as spla  # noqa: E402

from btnav.core import fmath  # noqa: E402
from btnav.core.geometry import normalize_angle  # noqa: E402
from btnav.slam.graph.pose_graph import graph_error, jacobians, optimize_poses  # noqa: E402
from btnav.slam.graph.solver import BlockPattern, assemble  # noqa: E402

SIGMA = np.array([0.05, 0.05, 0.01])
Graph = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]


def chain(z: np.ndarray) -> np.ndarray:
    """Poses from the origin by composing relative poses z (K, 3) one after another."""
    yaw = np.concatenate([[0.0], np.cumsum(z[:, 2])])
    s, c = fmath.sincos(yaw[:-1])
    out = np.zeros((z.shape[0] + 1, 3))
    out[1:, 0] = np.cumsum(c * z[:, 0] - s * z[:, 1])
    out[1:, 1] = np.cumsum(s * z[:, 0] + c * z[:, 1])
    out[:, 2] = normalize_angle(yaw)
    return out


def relative(p: np.ndarray, i: np.ndarray, j: np.ndarray) -> np.ndarray:
    s, c = fmath.sincos(p[i, 2])
    dx, dy = p[j, 0] - p[i, 0], p[j, 1] - p[i, 1]
    return np.column_stack([c * dx + s * dy, c * dy - s * dx, normalize_angle(p[j, 2] - p[i, 2])])


def _noisy(truth: np.ndarray, i: np.ndarray, j: np.ndarray, rng: np.random.Generator) -> Graph:
    z = relative(truth, i, j) + rng.standard_normal((i.size, 3)) * SIGMA
    info = np.broadcast_to(np.diag(1.0 / SIGMA**2), (i.size, 3, 3)).copy()
    n = truth.shape[0]
    return truth, chain(z[: n - 1]), i, j, z, info


def manhattan_graph(n: int = 3500, seed: int = 1, turn: float = 0.7) -> Graph:
    """(truth, initial poses, i, j, measurements, information); edges 0..n-2 odometry."""
    rng = np.random.default_rng(seed)
    u = rng.random(n - 1)
    turns = np.where(u < turn / 2, 1, np.where(u < turn, -1, 0))
    heading = np.concatenate([[0], np.cumsum(turns)]) % 4
    steps = np.array([[1, 0], [0, 1], [-1, 0], [0, -1]])[heading[1:]]
    cells = np.zeros((n, 2), np.int64)
    cells[1:] = np.cumsum(steps, axis=0)
    truth = np.column_stack([cells, normalize_angle(heading * (np.pi / 2))]).astype(float)
    key = (cells[:, 0] + n) * (4 * n) + cells[:, 1] + n
    order = np.lexsort((np.arange(n), key))
    again = key[order][1:] == key[order][:-1]
    i = np.concatenate([np.arange(n - 1), order[:-1][again]])
    j = np.concatenate([np.arange(1, n), order[1:][again]])
    return _noisy(truth, i, j, rng)


def circle_graph(n: int = 1000, seed: int = 0, radius: float = 50.0) -> Graph:
    """A loop driven counter-clockwise from the origin; odometry and one loop closure."""
    rng = np.random.default_rng(seed)
    a = np.arange(n) * (2 * np.pi / n)
    s, c = fmath.sincos(a)
    truth = np.column_stack([radius * s, radius * (1.0 - c), normalize_angle(a)])
    i = np.append(np.arange(n - 1), n - 1)
    j = np.append(np.arange(1, n), 0)
    return _noisy(truth, i, j, rng)


def best_time(fn: Callable[[], object], repeat: int) -> tuple[float, object]:
    best, out = float("inf"), None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def gtsam_solve(g: Graph):
    """gtsam's LM on the same graph; None when gtsam is not installed."""
    try:
        import gtsam
    except ImportError:
        return None
    _, init, i, j, z, info = g
    graph = gtsam.NonlinearFactorGraph()
    graph.add(
        gtsam.PriorFactorPose2(0, gtsam.Pose2(*init[0]), gtsam.noiseModel.Isotropic.Sigma(3, 1e-6))
    )
    for k in range(i.size):
        noise = gtsam.noiseModel.Gaussian.Information(info[k])
        graph.add(gtsam.BetweenFactorPose2(int(i[k]), int(j[k]), gtsam.Pose2(*z[k]), noise))
    values = gtsam.Values()
    for k in range(init.shape[0]):
        values.insert(k, gtsam.Pose2(*init[k]))
    params = gtsam.LevenbergMarquardtParams()
    params.setRelativeErrorTol(1e-6)
    params.setAbsoluteErrorTol(1e-9)
    params.setMaxIterations(100)

    def run():
        opt = gtsam.LevenbergMarquardtOptimizer(graph, values, params)
        return opt.optimize(), opt.iterations()

    def poses_of(result) -> np.ndarray:
        return np.array(
            [[p.x(), p.y(), p.theta()] for p in (result.atPose2(k) for k in range(init.shape[0]))]
        )

    def error_of(poses: np.ndarray) -> float:
        v = gtsam.Values()
        for k in range(poses.shape[0]):
            v.insert(k, gtsam.Pose2(*poses[k]))
        return 2.0 * graph.error(v)  # gtsam's error is half the sum of squares

    return run, poses_of, error_of


def rmse(poses: np.ndarray, truth: np.ndarray) -> float:
    return float(np.sqrt(((poses[:, :2] - truth[:, :2]) ** 2).sum(axis=1).mean()))


def compare(name: str, g: Graph, repeat: int) -> None:
    truth, init, i, j, z, info = g
    print(
        f"\n{name}: {init.shape[0]} poses, {i.size} edges, initial error {graph_error(init, i, j, z, info):.4g}"
    )
    rows = []
    for solver in ("cholesky", "superlu"):
        t, (poses, rep) = best_time(
            lambda s=solver: optimize_poses(
                init, i, j, z, info, linear_solver=s, max_iterations=50
            ),
            repeat,
        )
        rows.append((f"btnav {solver}", t, poses, rep.iterations, rep.converged))
    gt = gtsam_solve(g)
    if gt is None:
        print("  gtsam: not installed (pip install gtsam): no comparison")
    else:
        run, poses_of, _ = gt
        t, (result, iters) = best_time(run, repeat)
        rows.append(("gtsam LM", t, poses_of(result), iters, True))
    print(f"  {'solver':<16}{'time ms':>9}{'x chol':>8}{'iters':>7}{'conv':>6}"
          f"{'btnav err':>12}{'gtsam err':>12}{'RMSE m':>9}")  # fmt: skip
    t_chol = rows[0][1]
    for label, t, poses, iters, conv in rows:
        e_b = graph_error(poses, i, j, z, info)
        e_g = f"{gt[2](poses):12.6g}" if gt is not None else f"{'-':>12}"
        print(f"  {label:<16}{t * 1e3:9.1f}{t / t_chol:8.2f}{iters:7d}{conv!s:>6}"
              f"{e_b:12.6g}{e_g}{rmse(poses, truth):9.4f}")  # fmt: skip
    if gt is not None:
        print(f"  btnav cholesky / gtsam time: {t_chol / rows[-1][1]:.2f}; "
              f"final btnav error / gtsam's (btnav's measure): "
              f"{graph_error(rows[0][2], i, j, z, info) / graph_error(rows[-1][2], i, j, z, info):.6f}")  # fmt: skip


def pcg_block_jacobi(g: Graph, max_iter: int = 20000) -> None:
    """The first LM step's system solved by block-Jacobi PCG: the deterministic option
    the Cholesky replaced, measured (scipy's CSR matvec; numpy-only would be slower)."""
    _, init, i, j, z, info = g
    pattern = BlockPattern(init.shape[0], i, j)
    r, a, b = jacobians(init, i, j, z)
    system = assemble(pattern, a, b, info, r, 0)
    diag = system.damped_diag(1e-4)
    h = system.to_csc(diag).tocsr()
    rhs = -system.grad.ravel()
    t0 = time.perf_counter()
    exact = spla.splu(h.tocsc()).solve(rhs)
    t_lu = time.perf_counter() - t0
    m_inv = np.linalg.inv(diag)  # the bench only: determinism does not matter here
    x = np.zeros_like(rhs)
    res = rhs.copy()
    zv = fmath.matmul_k(m_inv, res.reshape(-1, 3, 1)).ravel()
    p = zv.copy()
    rz = float((res * zv).sum())
    t0 = time.perf_counter()
    k, err = 0, 1.0
    scale = float(np.sqrt((exact * exact).sum()))
    while k < max_iter and err > 1e-6:
        hp = h @ p
        alpha = rz / float((p * hp).sum())
        x += alpha * p
        res -= alpha * hp
        zv = fmath.matmul_k(m_inv, res.reshape(-1, 3, 1)).ravel()
        rz, rz_old = float((res * zv).sum()), rz
        p = zv + (rz / rz_old) * p
        k += 1
        d = x - exact
        err = float(np.sqrt((d * d).sum())) / scale
    t = time.perf_counter() - t0
    print(f"  block-Jacobi PCG, one LM step: {k} iterations to |dx - dx*| / |dx*| = {err:.1e} "
          f"in {t * 1e3:.0f} ms; SuperLU factor + solve {t_lu * 1e3:.1f} ms")  # fmt: skip


CHILD = """
import hashlib, sys
sys.path.insert(0, {here!r})
from pose_graph_solver import manhattan_graph
from btnav.slam.graph.pose_graph import optimize_poses
_, init, i, j, z, info = manhattan_graph(n=1500)
for s in ("cholesky", "superlu"):
    x, _ = optimize_poses(init, i, j, z, info, linear_solver=s, max_iterations=50)
    print(s, hashlib.sha256(x.tobytes()).hexdigest()[:16])
"""


def coretypes() -> None:
    """Each solver's result bits with OpenBLAS forced to other CPUs' kernels."""
    print("\nresult bits (sha256, 1500-pose Manhattan) by OpenBLAS kernel:")
    here = os.path.dirname(os.path.abspath(__file__))
    for core in ("Haswell", "Sandybridge", "Nehalem", "Prescott"):
        env = dict(os.environ, OPENBLAS_CORETYPE=core)
        out = subprocess.run(
            [sys.executable, "-c", CHILD.format(here=here)], env=env, capture_output=True, text=True
        )
        got = (
            " ".join(out.stdout.split()) if out.returncode == 0 else f"failed: {out.stderr[-200:]}"
        )
        print(f"  {core:<12} {got}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--skip-coretypes", action="store_true")
    ap.add_argument("--skip-pcg", action="store_true")
    args = ap.parse_args()
    for name, g in (("Manhattan (M3500-like)", manhattan_graph()), ("Circle", circle_graph())):
        compare(name, g, args.repeat)
        if not args.skip_pcg:
            pcg_block_jacobi(g)
    if not args.skip_coretypes:
        coretypes()


if __name__ == "__main__":
    main()
