"""nav2_amcl's particle filter (pf.c): the particle set, its weights and its statistics.

- `init_gaussian(mean, cov)` / `init_model(sampler)`: pf_init and pf_init_model (every
  particle weighs 1/max_samples; w_slow = w_fast = 0).
- `update_sensor(p)`: pf_update_sensor; each weight times the laser model's factor,
  normalised, and the running averages w_slow, w_fast of the mean weight (alpha_slow,
  alpha_fast) that tell recovery how surprised the filter is.
- `resample(random_poses)`: pf_update_resample with low-variance (systematic)
  resampling, recovery injection (each draw is a random pose with probability
  max(0, 1 - w_fast / w_slow)) and KLD sampling. nav2_amcl draws one particle at a time
  and stops once the count passes the KLD limit of the bins seen so far. Here all
  max_samples draws are made at once (one comb over the cumulative weights), put in a
  random order, and the same stopping rule picks the prefix: a random subset of a
  stratified draw is still drawn in proportion to weight.
- `cluster_stats()`: pf_cluster_stats; each cluster's weight, mean (yaw by its mean
  unit vector) and covariance, and the whole set's mean and covariance, which is what
  nav2_amcl publishes beside the heaviest cluster's mean.

All draws come from the generator given (the mission's `amcl` stream); sums are numpy's
pairwise or `bincount`'s in-order sums, so a run is the same bits on every CPU.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ...core import fmath
from ...core.geometry import normalize_angle
from .bins import bin_keys, clusters, kld_count

F64 = NDArray[np.float64]

#: A source of `n` random poses ((n, 3) array) for global localisation and recovery.
PoseSampler = Callable[[int], F64]


@dataclass
class Cluster:
    """One hypothesis: a connected group of bins (nav2_amcl's pf_cluster_t)."""

    weight: float
    mean: tuple[float, float, float]
    cov: F64  # 3x3 over x, y, yaw


class ParticleFilter:
    """Particles as (N, 3) poses (yaw in (-pi, pi]) and (N,) weights summing to 1."""

    #: nav2_amcl's pf->dist_threshold: converged when every particle is this close to the mean.
    dist_threshold = 0.5

    def __init__(
        self,
        min_samples: int,
        max_samples: int,
        alpha_slow: float,
        alpha_fast: float,
        pf_err: float,
        pf_z: float,
        rng: np.random.Generator,
    ) -> None:
        self.min_samples = int(min_samples)
        self.max_samples = int(max_samples)
        self.alpha_slow = float(alpha_slow)
        self.alpha_fast = float(alpha_fast)
        self.pf_err = float(pf_err)
        self.pf_z = float(pf_z)
        self.rng = rng
        self._poses: F64 = np.zeros((self.max_samples, 3))
        self._sincos: tuple[F64, F64] | None = None
        self.weights: F64 = np.full(self.max_samples, 1.0 / self.max_samples)
        self.w_slow = 0.0
        self.w_fast = 0.0
        self.converged = False
        self.clusters: list[Cluster] = []
        self.mean: tuple[float, float, float] = (0.0, 0.0, 0.0)
        self.cov: F64 = np.zeros((3, 3))
        #: The injection probability of the last resampling (0 without recovery).
        self.w_diff = 0.0
        self.cluster_stats()

    @property
    def count(self) -> int:
        return int(self._poses.shape[0])

    @property
    def poses(self) -> F64:
        return self._poses

    @poses.setter
    def poses(self, poses: F64) -> None:
        self._poses = poses
        self._sincos = None

    @property
    def sincos(self) -> tuple[F64, F64]:
        """(sin, cos) of the particles' yaws, computed once per particle set."""
        if self._sincos is None:
            self._sincos = fmath.sincos(self._poses[:, 2])
        return self._sincos

    # -- initialisation -------------------------------------------------------------------

    def init_gaussian(self, mean: tuple[float, float, float], cov: F64) -> None:
        """max_samples particles from N(mean, cov) (pf_init; cov 3x3, x-y block and yaw)."""
        n = self.max_samples
        z = self.rng.standard_normal((3, n))
        cov = np.asarray(cov, float)
        a, b, c = max(cov[0, 0], 0.0), cov[0, 1], max(cov[1, 1], 0.0)
        l11 = math.sqrt(a)  # the 2x2 Cholesky factor in closed form (no LAPACK)
        l21 = b / l11 if l11 > 0.0 else 0.0
        l22 = math.sqrt(max(c - l21 * l21, 0.0))
        poses = np.empty((n, 3))
        poses[:, 0] = mean[0] + l11 * z[0]
        poses[:, 1] = mean[1] + (l21 * z[0] + l22 * z[1])
        poses[:, 2] = normalize_angle(mean[2] + math.sqrt(max(cov[2, 2], 0.0)) * z[2])
        self._reset(poses)

    def init_model(self, sampler: PoseSampler) -> None:
        """max_samples particles from `sampler` (pf_init_model: global localisation)."""
        self._reset(np.asarray(sampler(self.max_samples), float))

    def _reset(self, poses: F64) -> None:
        self.poses = poses
        self.weights = np.full(len(poses), 1.0 / len(poses))
        self.w_slow = self.w_fast = 0.0
        self.cluster_stats()
        self.converged = False

    # -- the two steps ------------------------------------------------------------------

    def update_sensor(self, factors: F64) -> float:
        """Multiply the weights by the sensor model's `factors` and normalise; returns the
        total before normalising (pf_update_sensor)."""
        w = self.weights * factors
        total = float(w.sum())
        if total > 0.0:
            w_avg = total / len(w)
            self.weights = w / total
            self.w_slow = (
                w_avg
                if self.w_slow == 0.0
                else (self.w_slow + self.alpha_slow * (w_avg - self.w_slow))
            )
            self.w_fast = (
                w_avg
                if self.w_fast == 0.0
                else (self.w_fast + self.alpha_fast * (w_avg - self.w_fast))
            )
        else:
            self.weights = np.full(len(w), 1.0 / len(w))
        return total

    def resample(self, random_poses: PoseSampler | None) -> None:
        """Low-variance resampling with recovery injection and KLD sampling (see the module)."""
        m = self.max_samples
        rng = self.rng
        w_diff = 0.0
        if self.w_slow > 0.0:
            w_diff = max(0.0, 1.0 - self.w_fast / self.w_slow)
        self.w_diff = w_diff
        cum = np.cumsum(self.weights)
        comb = (rng.random() + np.arange(m)) * (cum[-1] / m)
        idx = np.minimum(np.searchsorted(cum, comb, side="right"), len(cum) - 1)
        idx = idx[rng.permutation(m)]
        poses = self.poses[idx]
        s, c = (v[idx] for v in self.sincos)
        if w_diff > 0.0 and random_poses is not None:
            inject = rng.random(m) < w_diff
            k = int(inject.sum())
            if k:
                poses[inject] = random_poses(k)
                s[inject], c[inject] = fmath.sincos(poses[inject, 2])
        n = kld_count(bin_keys(poses), self.pf_err, self.pf_z, self.min_samples, m)
        self.poses = poses[:n]
        self._sincos = (s[:n], c[:n])
        self.weights = np.full(n, 1.0 / n)
        if w_diff > 0.0:
            self.w_slow = self.w_fast = 0.0
        self.cluster_stats()
        self.update_converged()

    def update_converged(self) -> bool:
        """pf_update_converged: every particle within 0.5 m (x and y) of the plain mean."""
        xy = self.poses[:, :2]
        mean = xy.sum(axis=0) / len(xy)
        self.converged = bool((np.abs(xy - mean) <= self.dist_threshold).all())
        return self.converged

    # -- statistics -----------------------------------------------------------------------

    def cluster_stats(self) -> None:
        """Each cluster's weight, mean and covariance, and the whole set's mean and cov."""
        poses, w = self.poses, self.weights
        label, count = clusters(bin_keys(poses))
        s, c = self.sincos
        x, y = poses[:, 0], poses[:, 1]
        columns = (w, w * x, w * y, w * c, w * s, w * x * x, w * x * y, w * y * y)
        sums = np.stack([np.bincount(label, weights=v, minlength=count) for v in columns])
        totals = np.array([v.sum() for v in columns])
        self.clusters = [_cluster(sums[:, i]) for i in range(count) if sums[0, i] > 0.0]
        whole = _cluster(totals)
        self.mean, self.cov = whole.mean, whole.cov

    def best_cluster(self) -> Cluster | None:
        """The heaviest cluster (nav2_amcl's getMaxWeightHyp), None if no weight at all."""
        best = None
        for cluster in self.clusters:
            if cluster.weight > 0.0 and (best is None or cluster.weight > best.weight):
                best = cluster
        return best


def _cluster(m: F64) -> Cluster:
    """A cluster's statistics from its weighted sums (w, wx, wy, wcos, wsin, wxx, wxy, wyy)."""
    w, mx, my, mc, ms, mxx, mxy, myy = (float(v) for v in m)
    if w <= 0.0:
        return Cluster(0.0, (0.0, 0.0, 0.0), np.zeros((3, 3)))
    x, y = mx / w, my / w
    yaw = fmath.arctan2(ms, mc)
    cov = np.zeros((3, 3))
    cov[0, 0] = mxx / w - x * x
    cov[0, 1] = cov[1, 0] = mxy / w - x * y
    cov[1, 1] = myy / w - y * y
    r = math.sqrt(mc * mc + ms * ms) / w
    cov[2, 2] = max(0.0, -2.0 * fmath.log(r)) if r > 0.0 else math.inf
    return Cluster(w, (x, y, yaw), cov)
