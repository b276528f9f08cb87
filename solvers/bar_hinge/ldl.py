"""Sparse LDL^T factorisation with the symbolic analysis done once per sparsity pattern.

The bar-and-hinge tangent K (free DOFs) keeps its sparsity pattern for a whole load path, and its
Newton iterations factorise it tens of thousands of times (42,858 factorisations in the full-level
design case). SuperLU (``scipy.sparse.linalg.splu``) repeats the fill-reducing ordering and its
symbolic work at every call: 36 ms for the 2536-DOF gridshell tangent, 19 ms of it without the
ordering. Here the ordering (SuperLU's MMD on A^T + A with its elimination-tree postorder, taken
once from a first ``splu``), the permuted upper triangle, the elimination tree and the column counts
of L are computed once; each factorisation is the numeric up-looking LDL^T of QDLDL (Stellato,
Banjac, Goulart et al., the OSQP solver's LDL^T, Apache 2.0), compiled with numba.

No pivoting: K = L D L^T in the fixed order, the same factors (up to round-off) as SuperLU with
``diag_pivot_thresh = 0`` and a symmetric ordering, whose U diagonal is D. By Sylvester's law of
inertia the signs of D are those of K's eigenvalues. An exactly zero pivot stops the factorisation
(the caller falls back to SuperLU, which can pivot off the diagonal).
"""

from __future__ import annotations

import numba
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as sla


@numba.njit(cache=True)
def _etree(n, ap, ai):
    """Elimination tree and column counts of L for the upper triangle (ap, ai) (QDLDL_etree)."""
    work = np.zeros(n, np.int64)
    lnz = np.zeros(n, np.int64)
    parent = np.full(n, -1, np.int64)
    for j in range(n):
        work[j] = j
        for p in range(ap[j], ap[j + 1]):
            i = ai[p]
            while work[i] != j:
                if parent[i] == -1:
                    parent[i] = j
                lnz[i] += 1
                work[i] = j
                i = parent[i]
    return parent, lnz


@numba.njit(cache=True)
def _factor(n, ap, ai, ax, lp, li, lx, d, dinv, parent):
    """Numeric LDL^T of the upper triangle (ap, ai, ax) into (lp, li, lx) and d (QDLDL_factor).

    Returns the number of columns factorised: n on success, k < n when pivot k is exactly zero.
    """
    marked = np.zeros(n, np.bool_)
    y_idx = np.empty(n, np.int64)
    elim = np.empty(n, np.int64)
    next_space = lp[:n].copy()
    y = np.zeros(n)
    for k in range(n):
        d[k] = 0.0
        nnz_y = 0
        for p in range(ap[k], ap[k + 1]):
            row = ai[p]
            if row == k:
                d[k] = ax[p]
                continue
            y[row] = ax[p]
            node = row
            if not marked[node]:
                marked[node] = True
                elim[0] = node
                nnz_e = 1
                node = parent[row]
                while node != -1 and node < k:
                    if marked[node]:
                        break
                    marked[node] = True
                    elim[nnz_e] = node
                    nnz_e += 1
                    node = parent[node]
                while nnz_e > 0:
                    nnz_e -= 1
                    y_idx[nnz_y] = elim[nnz_e]
                    nnz_y += 1
        for i in range(nnz_y - 1, -1, -1):
            c = y_idx[i]
            end = next_space[c]
            yc = y[c]
            for p in range(lp[c], end):
                y[li[p]] -= lx[p] * yc
            li[end] = k
            lx[end] = yc * dinv[c]
            d[k] -= yc * lx[end]
            next_space[c] = end + 1
            y[c] = 0.0
            marked[c] = False
        if d[k] == 0.0:
            return k
        dinv[k] = 1.0 / d[k]
    return n


@numba.njit(cache=True)
def _solve(n, lp, li, lx, dinv, x):
    """In place: x <- (L D L^T)^-1 x."""
    for i in range(n):
        xi = x[i]
        for p in range(lp[i], lp[i + 1]):
            x[li[p]] -= lx[p] * xi
    for i in range(n):
        x[i] *= dinv[i]
    for i in range(n - 1, -1, -1):
        s = x[i]
        for p in range(lp[i], lp[i + 1]):
            s -= lx[p] * x[li[p]]
        x[i] = s


def inserted_before(at: np.ndarray, size: int) -> np.ndarray:
    """For keys inserted into a sorted array of ``size`` keys before positions ``at``
    (``np.searchsorted(keys, new)``, no new key equal to a stored one): the number of new keys
    before each stored one, ``np.searchsorted(np.sort(new), keys)``, by counting instead of a
    search per stored key (0.5 against 2.9 ms for the 5 x 5 gridshell's 245,817 entries)."""
    return np.cumsum(np.bincount(at, minlength=size + 1)[:size])


class SymbolicLDL:
    """Ordering, permuted upper-triangle pattern and elimination tree of one CSC sparsity pattern.

    Args:
        indices, indptr: the CSC pattern (n x n, structurally symmetric) of the matrices to
            factorise; entries of its diagonal may be missing (they are taken as zero).
        perm: a fill-reducing ordering (original index i -> position perm[i]) to use instead of
            SuperLU's MMD of this pattern (e.g. that of a sub-pattern).
    """

    def __init__(
        self, indices: np.ndarray, indptr: np.ndarray, n: int, perm: np.ndarray | None = None
    ):
        self.n = n
        cols = np.repeat(np.arange(n), np.diff(indptr))
        rows = np.asarray(indices, dtype=np.int64)
        if perm is None:
            # Ordering: SuperLU's, from a diagonally dominant matrix of the pattern (MMD and the
            # etree postorder depend on the structure only).
            probe = sp.csc_matrix(
                (np.where(rows == cols, 2.0 * n, -1.0), indices, indptr), shape=(n, n)
            )
            probe = probe + sp.identity(n, format="csc") * (2.0 * n)
            perm = sla.splu(
                probe.tocsc(),
                permc_spec="MMD_AT_PLUS_A",
                diag_pivot_thresh=0.0,
                options={"SymmetricMode": True},
            ).perm_c
        self.perm = np.asarray(perm, dtype=np.int64)  # original index i -> position perm[i]
        # Upper triangle of the permuted matrix, diagonal always stored: entry p of the original
        # CSC data goes to slot source_of[...] of the permuted upper data.
        pr, pc = perm[rows], perm[cols]
        upper = pr <= pc
        diag_slots = np.arange(n)
        keys = np.concatenate([pc[upper] * n + pr[upper], diag_slots * n + diag_slots])
        unique, inverse = np.unique(keys, return_inverse=True)
        self.ap_keys = unique  # column * n + row of the permuted upper triangle, sorted
        self.ai = (unique % n).astype(np.int64)
        self.ap = np.concatenate([[0], np.cumsum(np.bincount(unique // n, minlength=n))]).astype(
            np.int64
        )
        self.nnz = unique.size
        self._from = np.flatnonzero(upper)  # original data positions kept
        self._to = inverse[: self._from.size]  # their slots
        self.diagonal_slots = inverse[
            self._from.size :
        ]  # slot of the diagonal of permuted column j
        self.parent, lnz = _etree(n, self.ap, self.ai)
        self.lp = np.concatenate([[0], np.cumsum(lnz)]).astype(np.int64)

    def with_entries(
        self, moved: np.ndarray, rows: np.ndarray, cols: np.ndarray, positions: np.ndarray
    ) -> "SymbolicLDL":
        """The symbolic LDL^T, in this ordering, of this pattern plus the entries (rows, cols)
        (none of them stored here; a structurally symmetric set), for the merged CSC data in which
        this pattern's entry p sits at ``moved[p]`` and the new entry q at ``positions[q]``. The
        new entries are merged into the permuted upper triangle (no new ordering, no sort of the
        whole pattern): a few milliseconds where a new SymbolicLDL is a sparse LU."""
        n, perm = self.n, self.perm
        pr, pc = perm[rows], perm[cols]
        upper = pr <= pc
        new_keys = pc[upper] * n + pr[upper]
        order = np.argsort(new_keys, kind="stable")
        new_keys = new_keys[order]
        old_keys = self.ap_keys
        out = object.__new__(SymbolicLDL)
        out.n, out.perm = n, perm
        at = np.searchsorted(old_keys, new_keys)
        keys = np.insert(old_keys, at, new_keys)
        shift = inserted_before(at, old_keys.size)
        out.ap_keys = keys
        out.ai = keys % n
        out.ap = np.concatenate([[0], np.cumsum(np.bincount(keys // n, minlength=n))]).astype(
            np.int64
        )
        out.nnz = keys.size
        new_from = np.asarray(positions)[upper][order]
        out._from = np.concatenate([np.asarray(moved)[self._from], new_from])
        out._to = np.concatenate([self._to + shift[self._to], np.searchsorted(keys, new_keys)])
        out.diagonal_slots = self.diagonal_slots + shift[self.diagonal_slots]
        out.parent, lnz = _etree(n, out.ap, out.ai)
        out.lp = np.concatenate([[0], np.cumsum(lnz)]).astype(np.int64)
        return out

    def factorize(self, data: np.ndarray, shift: float = 0.0) -> "NumericLDL | None":
        """LDL^T of the matrix with CSC values ``data`` (in the pattern's order) plus ``shift`` I;
        None when a pivot is exactly zero."""
        ax = np.zeros(self.nnz)
        ax[self._to] = data[self._from]
        if shift:
            ax[self.diagonal_slots] += shift
        lnz = int(self.lp[-1])
        li, lx = np.empty(lnz, np.int64), np.empty(lnz)
        d, dinv = np.empty(self.n), np.empty(self.n)
        if _factor(self.n, self.ap, self.ai, ax, self.lp, li, lx, d, dinv, self.parent) < self.n:
            return None
        return NumericLDL(self, li, lx, d, dinv)


class NumericLDL:
    """The factors of one matrix: :meth:`solve` and the pivots D (in the permuted order)."""

    def __init__(self, symbolic: SymbolicLDL, li, lx, d, dinv):
        self.symbolic, self._li, self._lx, self.pivots, self._dinv = symbolic, li, lx, d, dinv

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        """The solution of K x = rhs, rhs (n,) or (n, k) (one solve per column)."""
        s = self.symbolic
        rhs = np.asarray(rhs, dtype=float)
        columns = rhs.reshape(s.n, -1).T  # (k, n)
        x = np.empty(columns.shape)
        x[:, s.perm] = columns
        for column in x:  # rows of a C-ordered array: contiguous
            _solve(s.n, s.lp, self._li, self._lx, self._dinv, column)
        return x[:, s.perm].T.reshape(rhs.shape)
