"""The pose graph and its SPA-style optimiser (btnav.slam.graph: pose_graph, solver)."""

from __future__ import annotations

import hashlib
import os
import subprocess
import sys

import numpy as np
import pytest

from btnav.core import fmath
from btnav.core.errors import MapError
from btnav.core.geometry import angle_diff, normalize_angle
from btnav.slam.graph.pose_graph import PoseGraph, graph_error

SIGMA = np.array([0.05, 0.05, 0.01])


def chain(z: np.ndarray) -> np.ndarray:
    """Poses from the origin by composing relative poses one after another."""
    yaw = np.concatenate([[0.0], np.cumsum(z[:, 2])])
    s, c = fmath.sincos(yaw[:-1])
    out = np.zeros((z.shape[0] + 1, 3))
    out[1:, 0] = np.cumsum(c * z[:, 0] - s * z[:, 1])
    out[1:, 1] = np.cumsum(s * z[:, 0] + c * z[:, 1])
    out[:, 2] = normalize_angle(yaw)
    return out


def relative(p: np.ndarray, i: np.ndarray, j: np.ndarray) -> np.ndarray:
    """Pose of j in i's frame."""
    s, c = fmath.sincos(p[i, 2])
    dx, dy = p[j, 0] - p[i, 0], p[j, 1] - p[i, 1]
    return np.column_stack([c * dx + s * dy, c * dy - s * dx, normalize_angle(p[j, 2] - p[i, 2])])


def build(poses: np.ndarray, i, j, z: np.ndarray, cov: np.ndarray) -> PoseGraph:
    g = PoseGraph()
    for p in poses:
        g.add_node(p)
    covs = np.broadcast_to(cov, (len(i), 3, 3))
    for a, b, m, c in zip(i, j, z, covs, strict=True):
        g.add_edge(int(a), int(b), m, c)
    return g


def square_loop(n: int = 40, side: float = 2.5):
    """Truth of a square driven counter-clockwise from the origin, n poses."""
    per_side = n // 4
    step = side / per_side
    z = np.tile([step, 0.0, 0.0], (n - 1, 1))
    z[per_side - 1 :: per_side, 2] = np.pi / 2  # turn at each corner
    return chain(z), z


def manhattan(n: int, seed: int = 1):
    """M3500-like: a 1 m grid walk, noisy odometry, a closure at every revisited cell
    (as bench/pose_graph_solver.py); the initial poses chain the noisy odometry."""
    rng = np.random.default_rng(seed)
    u = rng.random(n - 1)
    heading = np.concatenate([[0], np.cumsum(np.where(u < 0.35, 1, np.where(u < 0.7, -1, 0)))]) % 4
    cells = np.zeros((n, 2), np.int64)
    cells[1:] = np.cumsum(np.array([[1, 0], [0, 1], [-1, 0], [0, -1]])[heading[1:]], axis=0)
    truth = np.column_stack([cells, normalize_angle(heading * (np.pi / 2))]).astype(float)
    key = (cells[:, 0] + n) * (4 * n) + cells[:, 1] + n
    order = np.lexsort((np.arange(n), key))
    again = key[order][1:] == key[order][:-1]
    i = np.concatenate([np.arange(n - 1), order[:-1][again]])
    j = np.concatenate([np.arange(1, n), order[1:][again]])
    z = relative(truth, i, j) + rng.standard_normal((i.size, 3)) * SIGMA
    return truth, chain(z[: n - 1]), i, j, z


def test_square_loop_closure_pulls_the_last_pose_back():
    truth, z_true = square_loop()
    n = truth.shape[0]
    odom = z_true * [1.03, 1.0, 1.0] + [0.0, 0.0, 0.012]  # 3% scale and a yaw bias
    i = np.append(np.arange(n - 1), 0)
    j = np.append(np.arange(1, n), n - 1)
    z = np.vstack([odom, relative(truth, np.array([0]), np.array([n - 1]))])
    cov = np.tile(np.diag(SIGMA**2), (n, 1, 1))
    cov[-1] = np.diag([1e-6, 1e-6, 1e-6])  # a confident loop closure
    g = build(chain(odom), i, j, z, cov)
    drift = np.hypot(*(g.poses[-1, :2] - truth[-1, :2]))
    assert drift > 0.3  # the odometry alone ends far from the truth
    report = g.optimize()
    assert report.converged
    assert report.final_error < report.initial_error / 100
    assert np.hypot(*(g.poses[-1, :2] - truth[-1, :2])) < 0.01
    assert abs(angle_diff(g.poses[-1, 2], truth[-1, 2])) < 0.01
    assert report.final_error == pytest.approx(g.error())


def test_exact_measurements_give_zero_error_and_leave_poses_alone():
    truth, _ = square_loop()
    n = truth.shape[0]
    i, j = np.arange(n - 1), np.arange(1, n)
    g = build(truth, i, j, relative(truth, i, j), np.diag(SIGMA**2))
    g.add_edge(0, n - 1, relative(truth, np.array([0]), np.array([n - 1]))[0], np.eye(3) * 1e-4)
    before = g.poses.copy()
    report = g.optimize()
    assert report.converged and report.iterations == 0
    assert report.initial_error < 1e-20 and report.final_error < 1e-20
    assert np.array_equal(g.poses, before)


def test_the_fixed_node_does_not_move():
    _, init, i, j, z = manhattan(200)
    g = build(init, i, j, z, np.diag(SIGMA**2))
    before = g.poses.copy()
    report = g.optimize(fixed=37)
    assert report.converged and report.final_error < report.initial_error
    assert np.array_equal(g.poses[37], before[37])
    assert np.abs(g.poses - before).max() > 0.1  # the others did


def test_angles_wrap_round_plus_minus_pi():
    # 12 poses round a circle facing along it: their yaws go through +-pi; the loop
    # closures link opposite poses (relative yaw pi, written as -pi in one of them)
    n = 12
    a = np.arange(n) * (2 * np.pi / n)
    s, c = fmath.sincos(a)
    truth = np.column_stack([3 * s, 3 * (1 - c), normalize_angle(a)])
    i = np.concatenate([np.arange(n), np.arange(n // 2)])
    j = np.concatenate([(np.arange(n) + 1) % n, np.arange(n // 2) + n // 2])
    z = relative(truth, i, j)
    z[n:, 2] = np.where(np.arange(n // 2) % 2, np.pi, -np.pi)
    rng = np.random.default_rng(3)
    init = truth + rng.normal(0, [0.1, 0.1, 0.15], truth.shape)
    init[0] = truth[0]
    init[:, 2] = normalize_angle(init[:, 2])
    near_pi = np.abs(np.abs(truth[:, 2]) - np.pi) < 0.6
    assert (np.sign(init[near_pi, 2]) != np.sign(truth[near_pi, 2])).any()  # some wrapped
    g = build(init, i, j, z, np.diag(SIGMA**2))
    report = g.optimize()
    assert report.converged and report.final_error < 1e-12
    assert np.abs(g.poses[:, :2] - truth[:, :2]).max() < 1e-6
    assert np.abs(angle_diff(g.poses[:, 2], truth[:, 2])).max() < 1e-6
    assert (g.poses[:, 2] > -np.pi).all() and (g.poses[:, 2] <= np.pi).all()


def test_to_arrays_and_back_is_exact():
    _, init, i, j, z = manhattan(150)
    g = build(init, i, j, z, np.diag(SIGMA**2))
    g.optimize(max_iterations=3)
    arrays = g.to_arrays()
    h = PoseGraph.from_arrays(arrays)
    again = h.to_arrays()
    assert arrays.keys() == again.keys()
    for key, value in arrays.items():
        assert value.dtype == again[key].dtype and np.array_equal(value, again[key]), key
    assert all(g.neighbours(k) == h.neighbours(k) for k in range(g.num_nodes))
    g.optimize()
    h.optimize()
    assert np.array_equal(g.poses, h.poses)
    h.add_edge(0, 5, [1.0, 0.0, 0.0], np.eye(3))  # a loaded graph grows as any other
    assert 5 in h.neighbours(0)


def test_a_damaged_graph_file_names_the_array():
    arrays = build(*square_loop_graph()).to_arrays()
    with pytest.raises(MapError, match=r"unknown pose-graph array 'measurement'.*'measurements'"):
        PoseGraph.from_arrays({**arrays, "measurement": arrays["measurements"]})
    with pytest.raises(MapError, match="no 'poses' array"):
        PoseGraph.from_arrays({k: v for k, v in arrays.items() if k != "poses"})
    with pytest.raises(MapError, match="information"):
        PoseGraph.from_arrays({**arrays, "information": arrays["information"][:, :2]})
    with pytest.raises(MapError, match="does not exist"):
        PoseGraph.from_arrays({**arrays, "edge_j": arrays["edge_j"] + 100})


def square_loop_graph():
    truth, _ = square_loop(8, 2.0)
    i, j = np.arange(7), np.arange(1, 8)
    return truth, i, j, relative(truth, i, j), np.diag(SIGMA**2)


def test_bad_edges_are_refused():
    g = PoseGraph()
    g.add_node([0, 0, 0])
    g.add_node([1, 0, 0])
    with pytest.raises(IndexError, match="j=2"):
        g.add_edge(0, 2, [1, 0, 0], np.eye(3))
    with pytest.raises(ValueError, match="two different nodes"):
        g.add_edge(1, 1, [0, 0, 0], np.eye(3))
    with pytest.raises(ValueError, match="positive definite"):
        g.add_edge(0, 1, [1, 0, 0], np.diag([1.0, -1.0, 1.0]))
    with pytest.raises(ValueError, match="symmetric"):
        g.add_edge(0, 1, [1, 0, 0], [[1, 0.5, 0], [0, 1, 0], [0, 0, 1]])
    assert g.add_edge(0, 1, [1, 0, 0], np.eye(3) * 0.01) == 0
    assert np.allclose(g.edges.information[0], np.eye(3) * 100)
    assert g.neighbours(0) == [1] and g.neighbours(1) == [0]
    with pytest.raises(ValueError):
        g.poses[0, 0] = 5.0  # a read-only view: set_poses replaces them


def _digest(n: int) -> str:
    _, init, i, j, z = manhattan(n)
    g = build(init, i, j, z, np.diag(SIGMA**2))
    g.optimize()
    return hashlib.sha256(g.poses.tobytes()).hexdigest()


def test_same_inputs_same_bits_whatever_the_blas_kernels():
    here = _digest(400)
    assert _digest(400) == here
    # OpenBLAS picks its kernels by CPU; forcing another CPU's must not move a bit
    # (scipy's SuperLU, which calls BLAS, does change under this switch)
    code = (
        f"import sys; sys.path.insert(0, {os.path.dirname(__file__)!r}); "
        "from test_pose_graph import _digest; print(_digest(400))"
    )
    env = dict(os.environ, OPENBLAS_CORETYPE="Nehalem")
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == here


def test_cholesky_and_superlu_agree():
    _, init, i, j, z = manhattan(300)
    g = build(init, i, j, z, np.diag(SIGMA**2))
    h = PoseGraph.from_arrays(g.to_arrays())
    g.optimize()
    h.optimize(linear_solver="superlu")
    assert np.abs(g.poses - h.poses).max() < 1e-9


def test_a_3500_pose_manhattan_graph_converges():
    truth, init, i, j, z = manhattan(3500)
    g = build(init, i, j, z, np.diag(SIGMA**2))
    report = g.optimize(max_iterations=50)
    assert report.converged
    # At the optimum the normalised residuals are chi-square with 3E - 3(N - 1) degrees
    # of freedom (linear-Gaussian approximation): mean dof, spread sqrt(2 dof).
    dof = 3 * i.size - 3 * (init.shape[0] - 1)
    assert report.final_error < dof + 5 * np.sqrt(2 * dof)
    assert np.sqrt(((g.poses[:, :2] - truth[:, :2]) ** 2).sum(1).mean()) < 1.0
    try:
        import gtsam
    except ImportError:
        return
    graph = gtsam.NonlinearFactorGraph()
    graph.add(
        gtsam.PriorFactorPose2(0, gtsam.Pose2(*init[0]), gtsam.noiseModel.Isotropic.Sigma(3, 1e-6))
    )
    noise = gtsam.noiseModel.Diagonal.Sigmas(SIGMA)
    for a, b, m in zip(i.tolist(), j.tolist(), z, strict=True):
        graph.add(gtsam.BetweenFactorPose2(a, b, gtsam.Pose2(*m), noise))
    values = gtsam.Values()
    for k, p in enumerate(init):
        values.insert(k, gtsam.Pose2(*p))
    params = gtsam.LevenbergMarquardtParams()
    params.setRelativeErrorTol(1e-6)
    result = gtsam.LevenbergMarquardtOptimizer(graph, values, params).optimize()
    theirs = np.array(
        [[p.x(), p.y(), p.theta()] for p in map(result.atPose2, range(init.shape[0]))]
    )
    info = np.broadcast_to(np.diag(1 / SIGMA**2), (i.size, 3, 3))
    assert report.final_error <= 1.05 * graph_error(theirs, i, j, z, info)


def test_pop_edge_and_restore_poses_undo_a_closure_exactly():
    """What `Mapper._close` relies on to take a loop closure back: the graph after
    add_edge + optimize + pop_edge + restore_poses is the graph before, bit for bit."""
    g = PoseGraph()
    for k in range(5):
        g.add_node((0.5 * k, 0.01 * k, 0.02 * k))
    for k in range(4):
        g.add_edge(k, k + 1, (0.5, 0.0, 0.0), np.diag([1e-3, 1e-3, 1e-4]))
    before = g.to_arrays()
    neighbours = [g.neighbours(k) for k in range(5)]
    g.add_edge(0, 4, (1.5, 0.3, 0.1), np.diag([1e-3, 1e-3, 1e-4]))
    g.optimize()
    assert not np.array_equal(g.poses, before["poses"])
    g.pop_edge()
    g.restore_poses(before["poses"])
    after = g.to_arrays()
    for key in before:
        assert np.array_equal(after[key], before[key]), key
    assert [g.neighbours(k) for k in range(5)] == neighbours
    with pytest.raises(IndexError):
        PoseGraph().pop_edge()
