"""The sparse linear solve of each SPA step: H dx = -g over 3x3 pose blocks.

SPA (Karto's optimiser) solves its normal equations with a sparse Cholesky; scipy has
none, and scipy's SuperLU calls the vendor BLAS, whose kernels OpenBLAS picks by CPU, so
its last bits differ between machines. `BlockCholesky` is btnav's own, on 3x3 blocks:
a symbolic step once per graph (a fill-reducing order, the factor's pattern, the
elimination tree planned level by level as flat index arrays), then per step only
correctly rounded +, -, *, / and sqrt in a fixed order: the same bits on every CPU.
`solve_superlu` stays for comparison. Design and timings: docs/decisions/0056.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from numpy.typing import NDArray

from btnav.core import fmath

F64 = NDArray[np.float64]
I64 = NDArray[np.int64]

_K3 = np.arange(3)
_K9 = np.arange(9)


def _ragged_arange(counts: I64) -> I64:
    """0..c-1 for every c in counts, concatenated."""
    total = int(counts.sum())
    starts = np.cumsum(counts) - counts
    return np.arange(total, dtype=np.int64) - np.repeat(starts, counts)


def _group_starts(keys: I64) -> I64:
    """Where each run of equal keys starts in a sorted key array."""
    if keys.size == 0:
        return np.zeros(0, np.int64)
    return np.flatnonzero(np.concatenate([[True], keys[1:] != keys[:-1]]))


class BlockPattern:
    """The 3x3 blocks of H that can be non-zero: one per node on the diagonal and one
    per linked pair (a < b); fixed while the graph's edges are."""

    def __init__(self, n: int, i: I64, j: I64) -> None:
        self.n = n
        lo, hi = np.minimum(i, j), np.maximum(i, j)
        uniq, edge_pair = np.unique(lo * n + hi, return_inverse=True)
        self.pair_a, self.pair_b = uniq // n, uniq % n
        self.flip = i > j  # that edge's A^T L B is H[b, a]: stored transposed
        self.diag_index = (np.concatenate([i, j])[:, None] * 9 + _K9).ravel()
        self.off_index = (edge_pair[:, None] * 9 + _K9).ravel()
        self.grad_index = (np.concatenate([i, j])[:, None] * 3 + _K3).ravel()
        self.linked = np.zeros(n, bool)
        self.linked[i] = True
        self.linked[j] = True


@dataclass
class NormalEquations:
    """H as its diagonal and upper off-diagonal 3x3 blocks, and the gradient g."""

    pattern: BlockPattern
    diag: F64  # (N, 3, 3)
    off: F64  # (P, 3, 3): H[pair_a, pair_b]
    grad: F64  # (N, 3)

    def damped_diag(self, lam: float) -> F64:
        """Diagonal blocks of H + lam diag(H) (Marquardt's damping, free of units)."""
        d = self.diag.copy()
        d[:, _K3, _K3] *= 1.0 + lam
        return d

    def to_csc(self, diag: F64) -> sp.csc_matrix:
        """H with `diag` as its diagonal blocks, as a scipy matrix."""
        p = self.pattern
        rows = np.concatenate([np.arange(p.n), p.pair_a, p.pair_b])
        cols = np.concatenate([np.arange(p.n), p.pair_b, p.pair_a])
        blocks = np.concatenate([diag, self.off, self.off.transpose(0, 2, 1)])
        r3 = np.broadcast_to(rows[:, None, None] * 3 + _K3[:, None], blocks.shape)
        c3 = np.broadcast_to(cols[:, None, None] * 3 + _K3, blocks.shape)
        m = sp.coo_matrix((blocks.ravel(), (r3.ravel(), c3.ravel())), shape=(3 * p.n,) * 2)
        return m.tocsc()


def assemble(
    pattern: BlockPattern, a: F64, b: F64, info: F64, r: F64, fixed: int
) -> NormalEquations:
    """Sum every edge's blocks A^T L A, A^T L B, B^T L B and A^T L r, B^T L r into H and
    g with `np.bincount` (in edge order). The fixed node, and any node no edge touches,
    gets an identity row and column and a zero gradient: its step is exactly zero."""
    la = fmath.matmul_k(info, a)
    lb = fmath.matmul_k(info, b)
    at, bt = a.transpose(0, 2, 1), b.transpose(0, 2, 1)
    h_ij = fmath.matmul_k(at, lb)
    h_ij[pattern.flip] = h_ij[pattern.flip].transpose(0, 2, 1)
    lr = fmath.matmul_k(info, r[:, :, None])
    n, npair = pattern.n, pattern.pair_a.size
    diag_w = np.concatenate([fmath.matmul_k(at, la), fmath.matmul_k(bt, lb)]).ravel()
    diag = np.bincount(pattern.diag_index, diag_w, minlength=9 * n).reshape(n, 3, 3)
    off = np.bincount(pattern.off_index, h_ij.ravel(), minlength=9 * npair)
    off = off.reshape(npair, 3, 3)
    grad_w = np.concatenate([fmath.matmul_k(at, lr), fmath.matmul_k(bt, lr)]).ravel()
    grad = np.bincount(pattern.grad_index, grad_w, minlength=3 * n).reshape(n, 3)
    held = ~pattern.linked
    held[fixed] = True
    diag[held] = np.eye(3)
    grad[held] = 0.0
    off[held[pattern.pair_a] | held[pattern.pair_b]] = 0.0
    return NormalEquations(pattern, diag, off, grad)


# The factor's blocks are stored component-major, (3, 3, K): every elementwise pass then
# runs over K contiguous numbers (an (K, 3, 3) layout makes numpy loop over runs of 3).
# Sums of products go in a fixed order, (p0 + p1) + p2, as fmath.matmul_k adds them.


def cholesky_3x3(m: F64) -> F64:
    """Lower Cholesky factors of (3, 3, K) SPD blocks (NaN where one is not SPD)."""
    out = np.zeros(m.shape)
    l00 = np.sqrt(m[0, 0])
    l10 = m[1, 0] / l00
    l20 = m[2, 0] / l00
    l11 = np.sqrt(m[1, 1] - l10 * l10)
    l21 = (m[2, 1] - l20 * l10) / l11
    l22 = np.sqrt(m[2, 2] - l20 * l20 - l21 * l21)
    out[0, 0], out[1, 0], out[2, 0] = l00, l10, l20
    out[1, 1], out[2, 1], out[2, 2] = l11, l21, l22
    return out


def lower_inverse_3x3(low: F64) -> F64:
    """Inverses of (3, 3, K) lower-triangular blocks, written out."""
    out = np.zeros(low.shape)
    i00 = 1.0 / low[0, 0]
    i11 = 1.0 / low[1, 1]
    i22 = 1.0 / low[2, 2]
    i10 = -low[1, 0] * i00 * i11
    i21 = -low[2, 1] * i11 * i22
    i20 = -(low[2, 0] * i00 + low[2, 1] * i10) * i22
    out[0, 0], out[1, 1], out[2, 2] = i00, i11, i22
    out[1, 0], out[2, 1], out[2, 0] = i10, i21, i20
    return out


def _take(blocks: F64, idx: I64) -> F64:
    """blocks[:, :, idx], contiguous (plain indexing there gives a K-major layout)."""
    return np.take(blocks, idx, axis=2)


def _mv(m: F64, v: F64) -> F64:
    """m @ v for (3, 3, K) blocks and (3, K) vectors."""
    out = m[:, 0] * v[0]
    out += m[:, 1] * v[1]
    out += m[:, 2] * v[2]
    return out


def _mtv(m: F64, v: F64) -> F64:
    """m^T @ v for (3, 3, K) blocks and (3, K) vectors."""
    out = m[0] * v[0]
    out += m[1] * v[1]
    out += m[2] * v[2]
    return out


def _mmt(a: F64, b: F64) -> F64:
    """a @ b^T for (3, 3, K) blocks."""
    out = a[:, None, 0] * b[None, :, 0]
    out += a[:, None, 1] * b[None, :, 1]
    out += a[:, None, 2] * b[None, :, 2]
    return out


@dataclass(frozen=True, slots=True)
class _Level:
    """One height of the elimination tree: its columns and the index plans that
    factor them (updates, diagonal, off-diagonal blocks) and solve through them."""

    cols: I64  # columns (permuted numbering) at this height
    upd_a: I64  # L entries (i, j) ...
    upd_b: I64  # ... and (k, j) whose product updates ...
    upd_starts: I64  # ... each run (np.add.reduceat) of ...
    upd_target: I64  # ... L entry (i, k), k in cols
    upd_diag: I64  # where each col's (k, k) is in upd_target (every k above height 0 has a child)
    diag: I64  # L entry (k, k) of each col
    off: I64  # L entries (i, k), i > k, of the cols, column by column
    off_col: I64  # index into cols of each off entry
    off_row: I64  # row i of each off entry
    off_starts: I64  # where each col's off entries start (cols that have some)
    off_cols: I64  # index into cols of those
    fw: I64  # L entries (k, j), j < k, k in cols, grouped by k
    fw_src: I64  # their column j
    fw_starts: I64
    fw_rows: I64  # index into cols of each group's k


class BlockCholesky:
    """A deterministic sparse Cholesky of H's pattern (see the module docstring)."""

    def __init__(self, pattern: BlockPattern) -> None:
        n = pattern.n
        self.n = n
        self.rank, lower = self._order_and_pattern(pattern)
        self.order = np.argsort(self.rank)  # permuted index -> node
        colptr, rows = lower.indptr.astype(np.int64), lower.indices.astype(np.int64)
        cols = np.repeat(np.arange(n, dtype=np.int64), np.diff(colptr))
        self.nnz = rows.size
        # where H's blocks go in L (lower triangle, permuted numbering)
        keys = cols * n + rows
        pa, pb = self.rank[pattern.pair_a], self.rank[pattern.pair_b]
        want = np.minimum(pa, pb) * n + np.maximum(pa, pb)
        self.off_slot = np.searchsorted(keys, want)
        if not (
            np.array_equal(rows[colptr[:-1]], np.arange(n))
            and np.array_equal(keys[np.minimum(self.off_slot, self.nnz - 1)], want)
        ):
            raise RuntimeError("SuperLU's factor pattern does not hold H's")
        self.off_transposed = pa < pb  # block (hi, lo) of H is off^T when a maps below b
        self.diag_slot = colptr[self.rank]
        # elimination tree and heights
        first_off = colptr[:-1] + 1
        has_parent = first_off < colptr[1:]
        parent = np.full(n, -1, np.int64)
        parent[has_parent] = rows[first_off[has_parent]]
        height = np.zeros(n, np.int64)
        child = np.flatnonzero(has_parent)
        while True:
            new = height.copy()
            np.maximum.at(new, parent[child], height[child] + 1)
            if np.array_equal(new, height):
                break
            height = new
        self.levels = self._plan(colptr, rows, cols, keys, height)

    @staticmethod
    def _order_and_pattern(pattern: BlockPattern) -> tuple[I64, sp.csc_matrix]:
        """A fill-reducing order (chains peeled, then minimum degree) and the lower
        factor's block pattern in it (from SuperLU on an M-matrix: integers only)."""
        n = pattern.n
        first, rest, ra, rb = _peel_chains(n, pattern.pair_a, pattern.pair_b)
        if rest.size:
            local = np.zeros(n, np.int64)
            local[rest] = np.arange(rest.size)
            lu = _lu_of_pattern(rest.size, local[ra], local[rb], "MMD_AT_PLUS_A")
            rest = rest[np.argsort(lu.perm_c)]
        order = np.concatenate([first, rest])
        rank = np.empty(n, np.int64)
        rank[order] = np.arange(n)
        lu = _lu_of_pattern(n, rank[pattern.pair_a], rank[pattern.pair_b], "NATURAL")
        rank = np.asarray(lu.perm_c, np.int64)[rank]  # SuperLU may postorder its tree
        lower = sp.csc_matrix(lu.L)
        lower.data[lower.data != 0.0] = 1.0
        lower.eliminate_zeros()
        lower.sort_indices()
        return rank, lower

    def _plan(self, colptr: I64, rows: I64, cols: I64, keys: I64, height: I64) -> list[_Level]:
        """Index arrays for every level, cut from whole-factor arrays sorted by level."""
        n, nnz = self.n, keys.size
        steps = np.arange(int(height.max()) + 2 if n else 1)
        cnt = np.diff(colptr) - 1  # off-diagonal entries per column
        off_ids = np.flatnonzero(rows > cols)
        # updates: for every column j, every pair p <= q of its off entries gives
        # L[i, j] L[k, j]^T into L[i, k] (k = row p, i = row q), at k's level
        rep = cnt[cols[off_ids]] - _ragged_arange(cnt)  # pairs (p, q >= p) from each p
        upd_b = np.repeat(off_ids, rep)
        upd_a = upd_b + _ragged_arange(rep)
        want = rows[upd_b] * n + rows[upd_a]
        target = np.searchsorted(keys, want)
        if not np.array_equal(keys[np.minimum(target, nnz - 1)], want):
            raise RuntimeError("fill outside the symbolic pattern")
        t_level = height[rows[upd_b]]
        o = np.lexsort((target, t_level))
        upd_a, upd_b, target, t_level = upd_a[o], upd_b[o], target[o], t_level[o]
        ub = np.searchsorted(t_level, steps)
        tkey = t_level * nnz + target
        gs = _group_starts(tkey)  # one run per updated entry
        gb = np.searchsorted(gs, ub)
        # columns level by level, and where each column's diagonal is among the runs
        col_order = np.lexsort((np.arange(n), height))
        cb = np.searchsorted(height[col_order], steps)
        pos = np.empty(n, np.int64)  # index of a column within its level
        pos[col_order] = np.arange(n) - np.repeat(cb[:-1], np.diff(cb))
        dkey = height[col_order] * nnz + colptr[col_order]
        dpos = np.searchsorted(tkey[gs], dkey)
        up = height[col_order] > 0
        if gs.size and not np.array_equal(tkey[gs][np.minimum(dpos, gs.size - 1)][up], dkey[up]):
            raise RuntimeError("a column above the leaves without updates")
        # off-diagonal entries of the columns, level by level, column by column
        oc = cnt[col_order]
        off = np.repeat(colptr[col_order] + 1, oc) + _ragged_arange(oc)
        off_col = np.repeat(pos[col_order], oc)
        cum = np.concatenate([[0], np.cumsum(oc)])
        ob = cum[cb]
        col_runs = cum[:-1][oc > 0]
        cr = np.searchsorted(col_runs, ob)
        # forward solve: off entries (k, j) grouped by row k, level by level
        fw = off_ids[np.lexsort((cols[off_ids], rows[off_ids], height[rows[off_ids]]))]
        fb = np.searchsorted(height[rows[fw]], steps)
        fgs = _group_starts(rows[fw])
        fgb = np.searchsorted(fgs, fb)
        levels = []
        for h in range(steps.size - 1):
            t0, t1, g0, g1 = ub[h], ub[h + 1], gb[h], gb[h + 1]
            o0, o1, f0, f1 = ob[h], ob[h + 1], fb[h], fb[h + 1]
            lc = col_order[cb[h] : cb[h + 1]]
            ost = col_runs[cr[h] : cr[h + 1]] - o0
            fst = fgs[fgb[h] : fgb[h + 1]] - f0
            levels.append(
                _Level(
                    cols=lc,
                    upd_a=upd_a[t0:t1],
                    upd_b=upd_b[t0:t1],
                    upd_starts=gs[g0:g1] - t0,
                    upd_target=target[gs[g0:g1]],
                    upd_diag=dpos[cb[h] : cb[h + 1]] - g0,
                    diag=colptr[lc],
                    off=off[o0:o1],
                    off_col=off_col[o0:o1],
                    off_row=rows[off[o0:o1]],
                    off_starts=ost,
                    off_cols=off_col[o0:o1][ost],
                    fw=fw[f0:f1],
                    fw_src=cols[fw[f0:f1]],
                    fw_starts=fst,
                    fw_rows=pos[rows[fw[f0:f1][fst]]],
                )
            )
        return levels

    def factor(self, system: NormalEquations, diag: F64) -> tuple[F64, F64] | None:
        """L's blocks and the inverses of its diagonal blocks, (3, 3, K) each, for H
        with `diag` on its diagonal; None when H is not positive definite."""
        lv = np.zeros((3, 3, self.nnz))
        lv[:, :, self.diag_slot] = diag.transpose(1, 2, 0)
        off = system.off.transpose(1, 2, 0)
        t = self.off_transposed
        lv[:, :, self.off_slot] = np.where(t, off.transpose(1, 0, 2), off)
        linv = np.zeros((3, 3, self.n))
        with np.errstate(invalid="ignore", divide="ignore"):
            for lev in self.levels:
                if lev.upd_a.size:
                    prod = _mmt(_take(lv, lev.upd_a), _take(lv, lev.upd_b))
                    target = _take(lv, lev.upd_target)
                    target -= np.add.reduceat(prod, lev.upd_starts, axis=2)
                    diag_blocks = _take(target, lev.upd_diag)
                    lv[:, :, lev.upd_target] = target
                else:
                    diag_blocks = _take(lv, lev.diag)
                ld = cholesky_3x3(diag_blocks)
                inv = lower_inverse_3x3(ld)
                lv[:, :, lev.diag] = ld
                linv[:, :, lev.cols] = inv
                if lev.off.size:
                    lv[:, :, lev.off] = _mmt(_take(lv, lev.off), _take(inv, lev.off_col))
        if not np.isfinite(linv).all():
            return None
        return lv, linv

    def solve(self, factors: tuple[F64, F64], rhs: F64) -> F64:
        """x with L L^T x = rhs, rhs and x as (N, 3) in node order."""
        lv, linv = factors
        y = np.ascontiguousarray(rhs[self.order].T)  # (3, N), permuted
        for lev in self.levels:  # L y = b, leaves to root
            b = np.take(y, lev.cols, axis=1)
            if lev.fw.size:
                terms = _mv(_take(lv, lev.fw), np.take(y, lev.fw_src, axis=1))
                b[:, lev.fw_rows] -= np.add.reduceat(terms, lev.fw_starts, axis=1)
            y[:, lev.cols] = _mv(_take(linv, lev.cols), b)
        for lev in reversed(self.levels):  # L^T x = y, root to leaves
            b = np.take(y, lev.cols, axis=1)
            if lev.off.size:
                terms = _mtv(_take(lv, lev.off), np.take(y, lev.off_row, axis=1))
                b[:, lev.off_cols] -= np.add.reduceat(terms, lev.off_starts, axis=1)
            y[:, lev.cols] = _mtv(_take(linv, lev.cols), b)
        return np.ascontiguousarray(y[:, self.rank].T)


def _peel_chains(n: int, a: I64, b: I64) -> tuple[I64, I64, I64, I64]:
    """Eliminate nodes of degree <= 2 in rounds, an independent set at a time (those
    whose pseudo-random priority beats their candidate neighbours'), as cyclic
    reduction does: a chain of m poses then gives an elimination tree of height
    ~log m, where minimum degree alone peels it from its ends (height m / 2) and the
    factorisation would take one pass per level. Returns the order so far, the nodes
    left and their edges (each node left has degree >= 3)."""
    prio = np.arange(n, dtype=np.int64) * 2654435761 % (1 << 32)  # a bijection
    alive = np.ones(n, bool)
    u, v = np.minimum(a, b), np.maximum(a, b)
    rounds = []
    while alive.any():
        ends, other = np.concatenate([u, v]), np.concatenate([v, u])
        cand = alive & (np.bincount(ends, minlength=n) <= 2)
        if not cand.any():
            break
        both = cand[ends] & cand[other]
        rival = np.full(n, 1 << 40, np.int64)
        np.minimum.at(rival, ends[both], prio[other[both]])
        sel = cand & (prio < rival)
        rounds.append(np.flatnonzero(sel))
        # each eliminated node of degree 2 links its two neighbours (the fill)
        s = np.flatnonzero(sel[ends])
        s = s[np.argsort(ends[s], kind="stable")]
        pair = np.flatnonzero(ends[s][1:] == ends[s][:-1])
        n1, n2 = other[s][pair], other[s][pair + 1]
        keep = ~(sel[u] | sel[v])
        key = np.unique(
            np.concatenate([u[keep] * n + v[keep], np.minimum(n1, n2) * n + np.maximum(n1, n2)])
        )
        u, v = key // n, key % n
        alive &= ~sel
    first = np.concatenate(rounds) if rounds else np.zeros(0, np.int64)
    return first, np.flatnonzero(alive), u, v


def _lu_of_pattern(n: int, a: I64, b: I64, spec: str) -> spla.SuperLU:
    """SuperLU of an M-matrix with the pattern of H's blocks: it has no cancellation, so
    its L's non-zeros are exactly the symbolic Cholesky factor's."""
    deg = np.bincount(np.concatenate([a, b]), minlength=n)
    rows = np.concatenate([np.arange(n), a, b])
    cols = np.concatenate([np.arange(n), b, a])
    vals = np.concatenate([deg + 1e-6, -np.ones(2 * a.size)])
    m = sp.csc_matrix((vals, (rows, cols)), shape=(n, n))
    lu = spla.splu(m, permc_spec=spec, diag_pivot_thresh=0.0, options={"SymmetricMode": True})
    if not np.array_equal(lu.perm_r, lu.perm_c):  # cannot happen for an M-matrix
        raise RuntimeError("SuperLU pivoted off the diagonal of an M-matrix")
    return lu


def solve_superlu(system: NormalEquations, diag: F64) -> F64:
    """H dx = -g by scipy's sparse LU: not bit-reproducible across CPUs (module doc)."""
    lu = spla.splu(
        system.to_csc(diag),
        permc_spec="MMD_AT_PLUS_A",
        diag_pivot_thresh=0.0,
        options={"SymmetricMode": True},
    )
    return lu.solve(-system.grad.ravel()).reshape(-1, 3)
