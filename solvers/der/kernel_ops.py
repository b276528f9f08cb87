"""Small fixed-size dense helpers of the compiled DER element loops (numba): 3-vectors, the
scatter of local gradients and Hessians into the rod's gradient and lower banded Hessian (LAPACK
storage ab[i - j, j] = H[i, j], half-bandwidth 10), and ``models.rod.STENCIL_MAP`` as index lists.

Element layouts are those of :mod:`lcefem.solvers.der.assembly`: an edge k touches the 7 dofs
q[4k : 4k + 7] = (x_k, theta_k, x_(k+1)); the stencil of interior node k + 1 touches the 11 dofs
q[4k : 4k + 11] = (x_k, theta_k, x_(k+1), theta_(k+1), x_(k+2)).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from lcefem.models.rod import STENCIL_MAP

# ``models.rod.STENCIL_MAP`` as index lists: local variable i -> stencil dofs MAP_IDX[i] with signs
# MAP_SGN[i] (two entries for the edge vectors e = x_k - x_(k-1), f = x_(k+1) - x_k; one, padded
# with sign 0, for the angles), so that S H S^T costs 256 multiply-adds instead of 1672.
MAP_IDX = np.zeros((8, 2), np.int64)
MAP_SGN = np.zeros((8, 2))
for _i in range(8):
    _rows = np.nonzero(STENCIL_MAP[:, _i])[0]
    MAP_IDX[_i, : len(_rows)] = _rows
    MAP_SGN[_i, : len(_rows)] = STENCIL_MAP[_rows, _i]


# ----------------------------------------------------------------------------------------------
# Small dense helpers (fixed sizes, no allocation in the hot loops beyond the per-call workspaces)
# ----------------------------------------------------------------------------------------------
@njit(cache=True, error_model="numpy")
def dot3(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@njit(cache=True, error_model="numpy")
def cross3(a, b, out):
    out[0] = a[1] * b[2] - a[2] * b[1]
    out[1] = a[2] * b[0] - a[0] * b[2]
    out[2] = a[0] * b[1] - a[1] * b[0]


@njit(cache=True, error_model="numpy")
def skew_into(v, out, r0, c0, sign):
    """out[r0:r0+3, c0:c0+3] += sign [v]_x."""
    out[r0 + 0, c0 + 1] += -sign * v[2]
    out[r0 + 0, c0 + 2] += sign * v[1]
    out[r0 + 1, c0 + 0] += sign * v[2]
    out[r0 + 1, c0 + 2] += -sign * v[0]
    out[r0 + 2, c0 + 0] += -sign * v[1]
    out[r0 + 2, c0 + 1] += sign * v[0]


@njit(cache=True, error_model="numpy")
def matmul(a, b, out):
    n, m = a.shape
    p = b.shape[1]
    for i in range(n):
        for j in range(p):
            s = 0.0
            for k in range(m):
                s += a[i, k] * b[k, j]
            out[i, j] = s


@njit(cache=True, error_model="numpy")
def to_stencil(h8, h11):
    """h11 (11, 11) = S h8 S^T with S = ``models.rod.STENCIL_MAP``."""
    h11[:, :] = 0.0
    for i in range(8):
        for p in range(2):
            a = MAP_IDX[i, p]
            sa = MAP_SGN[i, p]
            if sa == 0.0:
                continue
            for j in range(8):
                v = sa * h8[i, j]
                for q in range(2):
                    sb = MAP_SGN[j, q]
                    if sb != 0.0:
                        h11[a, MAP_IDX[j, q]] += v * sb


@njit(cache=True, error_model="numpy")
def rows_to_stencil(j8, j11):
    """j11 (r, 11) = j8 S^T for a (r, 8) Jacobian."""
    j11[:, :] = 0.0
    for r in range(j8.shape[0]):
        for i in range(8):
            for p in range(2):
                sa = MAP_SGN[i, p]
                if sa != 0.0:
                    j11[r, MAP_IDX[i, p]] += sa * j8[r, i]


@njit(cache=True, error_model="numpy")
def scatter(base, g_loc, H_loc, grad, band, with_hessian):
    m = g_loc.shape[0]
    for a in range(m):
        grad[base + a] += g_loc[a]
    if with_hessian:
        for a in range(m):
            for c in range(a + 1):
                band[a - c, base + c] += H_loc[a, c]


@njit(cache=True, error_model="numpy")
def source_change_into(g_loc, H_loc, slot_a, slot_t, slot_b, db, ddb, W, tmp, out, with_hessian):
    """Chain rule of ``models.rod.apply_source_change`` for one element, in place on g_loc and on
    the lower triangle of H_loc (the only part :func:`scatter` reads); slots (node a start, theta
    index, node b start), db (n_slots, 3), ddb (n_slots, 3, 3).

    D (the change of the angle rows t_s) has six nonzero columns per slot, so H D and D^T H D run
    over those only, and over the lower triangle (issue 17: 2.6x fewer operations at 11 dofs; the
    same sums in the same order, so the same lower triangle bit for bit)."""
    m = g_loc.shape[0]
    ns = len(slot_a)
    # the angle gradients of the (at most two) slots, held as scalars (no allocation per element)
    g_t0 = g_loc[slot_t[0]]
    g_t1 = g_loc[slot_t[1]] if ns > 1 else 0.0
    if with_hessian:
        # W = I + D, D nonzero only in the angle rows t_s: W^T H W = H + H D + (H D)^T + D^T H D.
        # Row s of D: -db at the columns of node a, +db at those of node b (W[s, 0:6] the values,
        # W[s, 6:12] the columns).
        for s in range(ns):
            for c in range(3):
                W[s, c] = -db[s, c]
                W[s, 3 + c] = db[s, c]
                W[s, 6 + c] = slot_a[s] + c
                W[s, 9 + c] = slot_b[s] + c
        for i in range(m):
            for j in range(m):
                tmp[i, j] = 0.0
        for s in range(ns):  # tmp = H D
            t = slot_t[s]
            for i in range(m):
                hit = H_loc[i, t]
                for c in range(6):
                    tmp[i, int(W[s, 6 + c])] += hit * W[s, c]
        for i in range(m):
            for j in range(i + 1):
                out[i, j] = H_loc[i, j] + tmp[i, j] + tmp[j, i]
        for s in range(ns):
            for s2 in range(ns):
                hss = H_loc[slot_t[s], slot_t[s2]]
                for ci in range(6):
                    i = int(W[s, 6 + ci])
                    v = hss * W[s, ci]
                    if v != 0.0:
                        for cj in range(6):
                            j = int(W[s2, 6 + cj])
                            if j <= i:
                                out[i, j] += v * W[s2, cj]
        for s in range(ns):
            a, b = slot_a[s], slot_b[s]  # a + 3 <= b: the (a, b) block is upper, (b, a) lower
            g_ts = g_t0 if s == 0 else g_t1
            for i in range(3):
                for j in range(3):
                    blk = g_ts * ddb[s, i, j]
                    if j <= i:
                        out[a + i, a + j] += blk
                        out[b + i, b + j] += blk
                    out[b + i, a + j] -= blk
        for i in range(m):
            for j in range(i + 1):
                H_loc[i, j] = out[i, j]
    for s in range(ns):
        g_ts = g_t0 if s == 0 else g_t1
        for c in range(3):
            g_loc[slot_a[s] + c] -= g_ts * db[s, c]
            g_loc[slot_b[s] + c] += g_ts * db[s, c]
