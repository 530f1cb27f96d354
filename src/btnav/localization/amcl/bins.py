"""nav2_amcl's pf_kdtree as a histogram: KLD bins, the KLD sample limit, clusters.

nav2_amcl drops every particle into a kd-tree of bins 0.5 m x 0.5 m x 10 degrees. The
number of occupied bins k sets how many particles resampling keeps (KLD sampling, Fox
2003): n(k) = (k - 1) / (2 pf_err) (1 - 2/(9(k-1)) + sqrt(2/(9(k-1))) pf_z)^3, within
[min_particles, max_particles]. (nav2_amcl passes `pf_z` itself as the normal quantile;
so does btnav, so the counts match Nav2's.) Clusters are the connected groups of
occupied bins, neighbours in all 26 directions.

Here the bins are integer keys and the clusters come from `scipy.ndimage.label` on
the occupied cells of a dense (x, y, yaw) histogram. Unlike the kd-tree's, the yaw
axis wraps: particles are kept in (-pi, pi] and a cloud round yaw = pi is one cluster,
not two (36 bins of 10 degrees tile the circle exactly).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray
from scipy.ndimage import label

#: nav2_amcl's pf_kdtree bin size: x, y (m) and yaw (rad).
BIN_XY = 0.5
BIN_YAW = 10.0 * math.pi / 180.0
YAW_BINS = 36

_NEIGHBOURS = np.ones((3, 3, 3), dtype=bool)


def bin_keys(poses: NDArray[np.float64]) -> NDArray[np.int64]:
    """(N, 3) integer bins of (N, 3) poses (yaw wrapped onto 36 bins)."""
    keys = np.empty(poses.shape, np.int64)
    keys[:, 0] = np.floor(poses[:, 0] / BIN_XY)
    keys[:, 1] = np.floor(poses[:, 1] / BIN_XY)
    keys[:, 2] = np.floor(poses[:, 2] / BIN_YAW)
    keys[:, 2] %= YAW_BINS
    return keys


def flat_keys(keys: NDArray[np.int64]) -> NDArray[np.int64]:
    """One int per bin (for counting distinct bins)."""
    lo = keys.min(axis=0)
    span = keys.max(axis=0) - lo + 1
    k = keys - lo
    return (k[:, 0] * span[1] + k[:, 1]) * YAW_BINS + k[:, 2]


def kld_limit(
    k: NDArray[np.int64], pf_err: float, pf_z: float, lo: int, hi: int
) -> NDArray[np.int64]:
    """nav2_amcl's pf_resample_limit for each bin count in `k`."""
    k = np.asarray(k, np.float64)
    km1 = np.maximum(k - 1.0, 1.0)
    b = 2.0 / (9.0 * km1)
    x = 1.0 - b + np.sqrt(b) * pf_z
    n = np.ceil(km1 / (2.0 * pf_err) * x * x * x)
    n = np.clip(n, lo, hi)
    return np.where(k <= 1.0, hi, n).astype(np.int64)


def kld_count(keys: NDArray[np.int64], pf_err: float, pf_z: float, lo: int, hi: int) -> int:
    """How many of `keys` (the resampled particles' bins, in draw order) nav2_amcl keeps:
    it stops after the s-th draw once s exceeds the limit for the bins seen so far."""
    flat = flat_keys(keys)
    _, first = np.unique(flat, return_index=True)
    new = np.zeros(len(flat), np.int64)
    new[first] = 1
    seen = np.cumsum(new)
    limit = kld_limit(seen, pf_err, pf_z, lo, hi)
    s = np.arange(1, len(flat) + 1)
    over = np.flatnonzero(s > limit)
    return int(over[0] + 1) if over.size else len(flat)


def clusters(keys: NDArray[np.int64]) -> tuple[NDArray[np.intp], int]:
    """The cluster index of each particle (0..count-1) and the cluster count.

    Clusters are connected groups of occupied bins (26-neighbourhood, yaw wrapping);
    numbering follows scipy's labelling, so it is the same on every run.
    """
    lo = keys.min(axis=0)
    k = keys - lo
    nx, ny = int(k[:, 0].max()) + 1, int(k[:, 1].max()) + 1
    grid = np.zeros((nx, ny, YAW_BINS), dtype=bool)
    grid[k[:, 0], k[:, 1], k[:, 2]] = True
    labels, count = label(grid, structure=_NEIGHBOURS)
    if count > 1:
        labels, count = _wrap_yaw(labels, count)
    return labels[k[:, 0], k[:, 1], k[:, 2]] - 1, count


def _wrap_yaw(labels: NDArray[np.int32], count: int) -> tuple[NDArray[np.int32], int]:
    """Merge the labels that touch across yaw = pi (bins 35 and 0)."""
    first, last = labels[:, :, 0], labels[:, :, -1]
    if not (first.any() and last.any()):
        return labels, count
    nx, ny = first.shape
    pairs = []
    for dx in (-1, 0, 1):  # the nine x, y neighbours across the seam
        for dy in (-1, 0, 1):
            a = first[max(0, -dx) : nx - max(0, dx), max(0, -dy) : ny - max(0, dy)]
            b = last[max(0, dx) : nx + min(0, dx), max(0, dy) : ny + min(0, dy)]
            both = (a > 0) & (b > 0)
            pairs.append(np.stack([a[both], b[both]], axis=1))
    touching = np.unique(np.concatenate(pairs), axis=0)
    if not len(touching):
        return labels, count
    root = np.arange(count + 1)
    for a, b in touching.tolist():  # a handful of seam contacts between a few clusters
        ra, rb = a, b
        while root[ra] != ra:
            ra = root[ra]
        while root[rb] != rb:
            rb = root[rb]
        root[max(ra, rb)] = min(ra, rb)
    for i in range(count + 1):  # flatten, in label order (each root is below its members)
        root[i] = root[root[i]]
    _, dense = np.unique(root, return_inverse=True)  # 0 stays 0 (background)
    return dense.astype(labels.dtype)[labels], int(dense.max())
