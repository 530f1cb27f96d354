"""The SLAM pose graph and its optimiser (Karto's Mapper graph and SPA solver).

slam_toolbox keeps one node per processed scan, at the robot's pose in the map frame,
and links nodes by constraints: each scan to the previous ones (odometry corrected by
scan matching) and, when the robot comes back, loop closures. A constraint (i, j)
says "node j, seen from node i, is at z", with the scan matcher's covariance; its
information is that covariance's inverse. `PoseGraph.optimize` moves the nodes to
minimise the sum over edges of r^T L r, r the relative pose of j in i's frame minus z
(the angle wrapped), by Levenberg-Marquardt as SPA does (Konolige et al. 2010, Karto's
`SpaSolver`): analytic Jacobians of every edge at once, the normal equations summed
into 3x3 blocks, each step solved by a sparse Cholesky (`solver`) that gives the
same bits on every CPU, since the optimised map -> odom transform steers the robot.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Literal, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from btnav.core import fmath
from btnav.core.errors import MapError
from btnav.core.geometry import normalize_angle
from btnav.core.suggest import best_match

from .solver import (
    BlockCholesky,
    BlockPattern,
    NormalEquations,
    assemble,
    cholesky_3x3,
    lower_inverse_3x3,
    solve_superlu,
)

F64 = NDArray[np.float64]
I64 = NDArray[np.int64]
LinearSolver = Literal["cholesky", "superlu"]
_K3 = np.arange(3)

#: Error per edge below which a graph counts as solved: rounding noise in the relative
#: poses (1e-16 of a coordinate) stays far below it for any sane information.
NEGLIGIBLE_ERROR_PER_EDGE = 1e-18
#: LM's damping relative to H's diagonal (Marquardt): start, bounds, step factor.
LAMBDA_INITIAL, LAMBDA_MIN, LAMBDA_MAX, LAMBDA_FACTOR = 1e-4, 1e-12, 1e8, 10.0


@dataclass(frozen=True, slots=True)
class SolveReport:
    """What one `optimize` did; errors are sums of squared Mahalanobis residuals (twice
    gtsam's `error`)."""

    iterations: int  # linear solves, refused steps included
    initial_error: float
    final_error: float
    converged: bool


# -- the edge model -----------------------------------------------------------------


def relative_poses(poses: F64, i: I64, j: I64) -> tuple[F64, F64, F64]:
    """Pose of j in i's frame (yaw not wrapped) and i's cos and sin."""
    s, c = fmath.sincos(poses[i, 2])
    dx = poses[j, 0] - poses[i, 0]
    dy = poses[j, 1] - poses[i, 1]
    rel = np.empty((i.size, 3))
    rel[:, 0] = c * dx + s * dy
    rel[:, 1] = c * dy - s * dx
    rel[:, 2] = poses[j, 2] - poses[i, 2]
    return rel, c, s


def residuals(poses: F64, i: I64, j: I64, z: F64) -> F64:
    """Relative pose of j in i's frame minus the measurement, the angle wrapped."""
    r = relative_poses(poses, i, j)[0] - z
    r[:, 2] = normalize_angle(r[:, 2])
    return r


def edge_errors(poses: F64, i: I64, j: I64, z: F64, info: F64) -> F64:
    """r^T L r of every edge."""
    r = residuals(poses, i, j, z)
    return fmath.dot_rows(r, fmath.matmul_k(info, r[:, :, None])[:, :, 0])


def graph_error(poses: F64, i: I64, j: I64, z: F64, info: F64) -> float:
    """The sum of every edge's r^T L r."""
    return float(edge_errors(poses, i, j, z, info).sum()) if i.size else 0.0


def jacobians(poses: F64, i: I64, j: I64, z: F64) -> tuple[F64, F64, F64]:
    """Residuals and their Jacobians A = dr/dx_i, B = dr/dx_j, (E, 3, 3) each: with
    R_i^T = [[c, s], [-s, c]] and t = R_i^T (t_j - t_i), B = diag(R_i^T, 1) and
    A = [[-c, -s, t_y], [s, -c, -t_x], [0, 0, -1]]."""
    rel, c, s = relative_poses(poses, i, j)
    r = rel - z
    r[:, 2] = normalize_angle(r[:, 2])
    a = np.zeros((i.size, 3, 3))
    b = np.zeros((i.size, 3, 3))
    a[:, 0, 0], a[:, 0, 1], a[:, 0, 2] = -c, -s, rel[:, 1]
    a[:, 1, 0], a[:, 1, 1], a[:, 1, 2] = s, -c, -rel[:, 0]
    a[:, 2, 2] = -1.0
    b[:, 0, 0], b[:, 0, 1], b[:, 1, 0], b[:, 1, 1] = c, s, -s, c
    b[:, 2, 2] = 1.0
    return r, a, b


def information_from_covariance(cov: ArrayLike) -> F64:
    """The inverse of a symmetric positive definite 3x3 covariance, through its
    Cholesky factor (np.linalg.inv is LAPACK); exactly symmetric."""
    c = np.asarray(cov, dtype=np.float64)
    if c.shape != (3, 3) or not np.isfinite(c).all():
        raise ValueError(f"covariance must be a finite 3x3 matrix, got shape {c.shape}")
    if np.abs(c - c.T).max() > 1e-9 * np.abs(c).max():
        raise ValueError(f"covariance must be symmetric, got {c.tolist()}")
    with np.errstate(invalid="ignore", divide="ignore"):
        factor = cholesky_3x3((0.5 * (c + c.T))[:, :, None])
        inv = lower_inverse_3x3(factor)[:, :, 0]
    if not (np.isfinite(inv).all() and (factor[_K3, _K3, 0] > 0).all()):
        raise ValueError(f"covariance must be positive definite, got {c.tolist()}")
    return fmath.matmul_k(inv.T, inv)


# -- the optimiser ------------------------------------------------------------------


def optimize_poses(
    poses: F64,
    i: I64,
    j: I64,
    z: F64,
    info: F64,
    *,
    fixed: int = 0,
    max_iterations: int = 20,
    tolerance: float = 1e-6,
    linear_solver: LinearSolver = "cholesky",
    huber: tuple[I64, float] | None = None,
) -> tuple[F64, SolveReport]:
    """Levenberg-Marquardt from `poses`; the new poses and a report.

    Every iteration is one linear solve of (H + lam diag(H)) dx = -g. A step that does
    not lower the error is refused and lam raised tenfold; an accepted one lowers lam
    tenfold. Converged: an accepted step lowered the error by at most `tolerance` of
    it, or the error is rounding noise, or no damping finds a lower error.
    `linear_solver="superlu"` is scipy's LU: faster on large graphs, but its last bits
    depend on the CPU's BLAS kernels (see `solver`), so not for a closed loop.
    `huber=(edges, scale)`: Huber's loss on those edges (Cartographer's loop closures),
    as Ceres minimises it: the error is sum rho(r^T L r) over them, and every
    linearisation weighs each one's information by rho' at its residual (Ceres's
    Corrector: Huber's rho'' is never positive, so no curvature term).
    """
    if linear_solver not in ("cholesky", "superlu"):
        raise ValueError(f"linear_solver must be 'cholesky' or 'superlu', not {linear_solver!r}")
    x = np.array(poses, dtype=np.float64)
    robust, scale = huber if huber is not None else (np.zeros(0, np.int64), 0.0)

    def error(poses: F64) -> float:
        if not robust.size:
            return graph_error(poses, i, j, z, info)
        e = edge_errors(poses, i, j, z, info)
        e[robust] = huber_loss(e[robust], scale)[0]
        return float(e.sum())

    def linearise(poses: F64) -> NormalEquations:
        r, a, b = jacobians(poses, i, j, z)
        weighted = info
        if robust.size:
            rl = r[robust]
            s = fmath.dot_rows(rl, fmath.matmul_k(info[robust], rl[:, :, None])[:, :, 0])
            weighted = info.copy()
            weighted[robust] *= huber_loss(s, scale)[1][:, None, None]
        return assemble(pattern, a, b, weighted, r, fixed)

    err0 = error(x)
    negligible = NEGLIGIBLE_ERROR_PER_EDGE * max(i.size, 1)
    if err0 <= negligible:
        return x, SolveReport(0, err0, err0, True)
    pattern = BlockPattern(x.shape[0], i, j)
    chol = BlockCholesky(pattern) if linear_solver == "cholesky" else None
    lam, err, iters, converged = LAMBDA_INITIAL, err0, 0, False
    system = linearise(x)
    while iters < max_iterations:
        iters += 1
        diag = system.damped_diag(lam)
        if chol is None:
            dx = solve_superlu(system, diag)
        else:
            factors = chol.factor(system, diag)
            dx = None if factors is None else chol.solve(factors, -system.grad)
        err_new = np.inf
        if dx is not None and np.isfinite(dx).all():
            trial = x + dx
            trial[:, 2] = normalize_angle(trial[:, 2])
            trial[fixed] = x[fixed]
            err_new = error(trial)
        if err_new < err:
            decrease = err - err_new
            x, err = trial, err_new
            lam = max(lam / LAMBDA_FACTOR, LAMBDA_MIN)
            if decrease <= tolerance * (err + decrease) or err <= negligible:
                converged = True
                break
            system = linearise(x)
        elif lam >= LAMBDA_MAX:
            converged = True  # no step lowers the error: a minimum, to rounding
            break
        else:
            lam = min(lam * LAMBDA_FACTOR, LAMBDA_MAX)
    return x, SolveReport(iters, err0, err, converged)


def huber_loss(s: F64, scale: float) -> tuple[F64, F64]:
    """Ceres's HuberLoss at squared residual norms `s`: rho(s) (s up to scale^2, then
    2 scale sqrt(s) - scale^2) and its derivative rho'(s) (1, then scale / sqrt(s))."""
    norm = np.sqrt(np.maximum(s, 0.0))
    outer = norm > scale
    rho = np.where(outer, 2.0 * scale * norm - scale * scale, s)
    weight = np.where(outer, scale / np.maximum(norm, scale), 1.0)
    return rho, weight


# -- the graph ----------------------------------------------------------------------


class Edges(NamedTuple):
    """The constraints as arrays (read-only views): edge k links node i[k] to j[k]."""

    i: I64  # (E,)
    j: I64  # (E,)
    measurement: F64  # (E, 3): pose of j in i's frame
    information: F64  # (E, 3, 3): inverse covariance


#: The arrays `to_arrays` gives and `from_arrays` takes.
ARRAY_KEYS = ("poses", "edge_i", "edge_j", "measurements", "information")


def _read_only(a: NDArray) -> NDArray:
    v = a.view()
    v.flags.writeable = False
    return v


class PoseGraph:
    """Nodes (robot poses in the map frame, one per processed scan) and the
    constraints between them; `optimize` moves the nodes to fit the constraints."""

    def __init__(self) -> None:
        self._n = 0
        self._e = 0
        self._poses = np.zeros((16, 3))
        self._i = np.zeros(16, np.int64)
        self._j = np.zeros(16, np.int64)
        self._z = np.zeros((16, 3))
        self._info = np.zeros((16, 3, 3))
        self._adjacent: list[list[int]] = []

    # -- building ---------------------------------------------------------------------

    def add_node(self, pose: ArrayLike) -> int:
        """A node at `pose` (x, y, yaw) in the map frame; its id is 0, 1, 2, ..."""
        p = _pose(pose, "pose")
        if self._n == self._poses.shape[0]:
            self._poses = _grown(self._poses)
        self._poses[self._n] = p
        self._adjacent.append([])
        self._n += 1
        return self._n - 1

    def add_edge(
        self,
        i: int,
        j: int,
        measurement: ArrayLike,
        covariance: ArrayLike | None = None,
        *,
        information: ArrayLike | None = None,
    ) -> int:
        """A constraint: node j seen from node i at `measurement` (x, y, yaw in i's
        frame), with its 3x3 `covariance` (or its `information`, the inverse, when the
        scan matcher gives that); returns the edge's id."""
        for name, node in (("i", i), ("j", j)):
            if not isinstance(node, int | np.integer) or not 0 <= node < self._n:
                raise IndexError(f"edge end {name}={node!r} is not a node (0..{self._n - 1})")
        if i == j:
            raise ValueError(f"an edge must link two different nodes, got {i} twice")
        z = _pose(measurement, "measurement")
        if (covariance is None) == (information is None):
            raise ValueError("give exactly one of covariance and information")
        if covariance is not None:
            info = information_from_covariance(covariance)
        else:
            info = np.asarray(information, dtype=np.float64)
            if info.shape != (3, 3) or not np.isfinite(info).all():
                raise ValueError(f"information must be a finite 3x3 matrix, got {info.shape}")
        if self._e == self._i.shape[0]:
            self._i, self._j = _grown(self._i), _grown(self._j)
            self._z, self._info = _grown(self._z), _grown(self._info)
        k = self._e
        self._i[k], self._j[k], self._z[k], self._info[k] = i, j, z, info
        self._adjacent[int(i)].append(int(j))
        self._adjacent[int(j)].append(int(i))
        self._e += 1
        return k

    def pop_edge(self) -> None:
        """Remove the last edge added (a loop closure the mapper takes back)."""
        if self._e == 0:
            raise IndexError("the graph has no edge to remove")
        self._e -= 1
        k = self._e
        i, j = int(self._i[k]), int(self._j[k])
        self._adjacent[i].pop()
        self._adjacent[j].pop()
        self._i[k], self._j[k], self._z[k], self._info[k] = 0, 0, 0.0, 0.0

    def restore_poses(self, poses: ArrayLike) -> None:
        """Put back every node's pose exactly as `poses` (a copy of `poses` taken
        earlier: no yaw wrapping, the same bits)."""
        p = np.asarray(poses, dtype=np.float64)
        if p.shape != (self._n, 3):
            raise ValueError(f"poses must be of shape ({self._n}, 3), got {p.shape}")
        self._poses[: self._n] = p

    # -- reading ----------------------------------------------------------------------

    @property
    def num_nodes(self) -> int:
        return self._n

    @property
    def num_edges(self) -> int:
        return self._e

    @property
    def poses(self) -> F64:
        """(N, 3) x, y, yaw of every node, read-only (`set_poses` replaces them)."""
        return _read_only(self._poses[: self._n])

    def set_poses(self, poses: ArrayLike) -> None:
        """Replace every node's pose (yaws wrapped to (-pi, pi])."""
        p = np.asarray(poses, dtype=np.float64)
        if p.shape != (self._n, 3) or not np.isfinite(p).all():
            raise ValueError(f"poses must be finite and of shape ({self._n}, 3), got {p.shape}")
        self._poses[: self._n] = p
        self._poses[: self._n, 2] = normalize_angle(p[:, 2])

    @property
    def edges(self) -> Edges:
        e = self._e
        return Edges(
            _read_only(self._i[:e]),
            _read_only(self._j[:e]),
            _read_only(self._z[:e]),
            _read_only(self._info[:e]),
        )

    def neighbours(self, i: int) -> list[int]:
        """The nodes linked to node i by an edge either way, in increasing order."""
        if not 0 <= i < self._n:
            raise IndexError(f"node {i} does not exist (0..{self._n - 1})")
        return sorted(set(self._adjacent[i]))

    def error(self) -> float:
        """The sum over edges of r^T L r at the current poses."""
        i, j, z, info = self.edges
        return graph_error(self.poses, i, j, z, info)

    # -- optimising -------------------------------------------------------------------

    def optimize(
        self,
        *,
        fixed: int = 0,
        max_iterations: int = 20,
        tolerance: float = 1e-6,
        linear_solver: LinearSolver = "cholesky",
    ) -> SolveReport:
        """Move every node but `fixed` to minimise the error (see `optimize_poses`)."""
        if self._n == 0:
            return SolveReport(0, 0.0, 0.0, True)
        if not 0 <= fixed < self._n:
            raise IndexError(f"fixed node {fixed} does not exist (0..{self._n - 1})")
        poses, report = optimize_poses(
            self.poses, *self.edges, fixed=fixed, max_iterations=max_iterations,
            tolerance=tolerance, linear_solver=linear_solver,
        )  # fmt: skip
        self._poses[: self._n] = poses
        return report

    # -- serialising ------------------------------------------------------------------

    def to_arrays(self) -> dict[str, F64 | I64]:
        """Copies of the graph's arrays (`ARRAY_KEYS`), for a file; `from_arrays` reads
        them back bit for bit."""
        i, j, z, info = self.edges
        return {
            "poses": self.poses.copy(),
            "edge_i": i.copy(),
            "edge_j": j.copy(),
            "measurements": z.copy(),
            "information": info.copy(),
        }

    @classmethod
    def from_arrays(cls, arrays: Mapping[str, ArrayLike]) -> PoseGraph:
        """The graph `to_arrays` described; a missing, misspelt or malformed array is a
        `MapError` naming it (the caller adds the file with `.located(file=...)`)."""
        for key in arrays:
            if key not in ARRAY_KEYS:
                raise MapError(
                    f"unknown pose-graph array {key!r}",
                    key=key,
                    suggestion=best_match(key, ARRAY_KEYS),
                )
        for key in ARRAY_KEYS:
            if key not in arrays:
                raise MapError(f"the pose graph has no {key!r} array", key=key)
        poses = np.asarray(arrays["poses"])
        n = poses.shape[0] if poses.ndim == 2 else -1
        i, j = np.asarray(arrays["edge_i"]), np.asarray(arrays["edge_j"])
        z, info = np.asarray(arrays["measurements"]), np.asarray(arrays["information"])
        e = i.shape[0] if i.ndim == 1 else -1
        shapes = {
            "poses": (poses, (n, 3), "f"),
            "edge_i": (i, (e,), "iu"),
            "edge_j": (j, (e,), "iu"),
            "measurements": (z, (e, 3), "f"),
            "information": (info, (e, 3, 3), "f"),
        }
        for key, (a, shape, kinds) in shapes.items():
            if a.shape != shape or a.dtype.kind not in kinds or min(shape) < 0:
                raise MapError(
                    f"expected {'integers' if kinds == 'iu' else 'floats'} of shape "
                    f"{tuple(s if s >= 0 else 'N' for s in shape)}, got {a.dtype} {a.shape}",
                    key=key,
                )
        if not (np.isfinite(poses).all() and np.isfinite(z).all() and np.isfinite(info).all()):
            raise MapError("the pose graph holds NaN or infinite numbers", key="poses")
        if e and (min(i.min(), j.min()) < 0 or max(i.max(), j.max()) >= n or (i == j).any()):
            raise MapError(
                f"an edge links a node that does not exist (0..{n - 1}) or itself", key="edge_i"
            )
        g = cls()
        g._n, g._e = n, e
        g._poses = np.array(poses, dtype=np.float64).reshape(-1, 3) if n else g._poses
        g._i, g._j = np.array(i, dtype=np.int64), np.array(j, dtype=np.int64)
        g._z = np.array(z, dtype=np.float64).reshape(-1, 3)
        g._info = np.array(info, dtype=np.float64).reshape(-1, 3, 3)
        ends, others = np.concatenate([g._i, g._j]), np.concatenate([g._j, g._i])
        order = np.argsort(ends, kind="stable")
        split = np.cumsum(np.bincount(ends, minlength=n))[:-1]
        g._adjacent = [a.tolist() for a in np.split(others[order], split)] if n else []
        return g


def _pose(p: ArrayLike, name: str) -> F64:
    """A finite (3,) pose with its yaw wrapped to (-pi, pi]."""
    a = np.array(p, dtype=np.float64)
    if a.shape != (3,) or not np.isfinite(a).all():
        raise ValueError(f"{name} must be 3 finite numbers (x, y, yaw), got {p!r}")
    a[2] = normalize_angle(float(a[2]))
    return a


def _grown(a: NDArray) -> NDArray:
    """`a` with twice the rows (amortised appends)."""
    out = np.zeros((max(2 * a.shape[0], 16), *a.shape[1:]), a.dtype)
    out[: a.shape[0]] = a
    return out
