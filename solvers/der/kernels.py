"""Compiled (numba) element loops of the DER assembly: the same formulas as the vectorised numpy
functions of :mod:`lcefem.models.rod` (``stretching``, ``bend_twist``, ``twist_hessian_ef``,
``apply_source_change``, ``stencil_point_derivatives``), fused with the scatter into the gradient and
the lower banded Hessian (LAPACK storage ab[i - j, j] = H[i, j], half-bandwidth 10).

Why: at the ribbon's sizes (30-200 nodes) the numpy versions spend most of their time in the
Python/numpy overhead of ~100 calls on small arrays per evaluation (issue 17: ~5 ms of fixed cost per
step). The numpy versions stay the reference: ``tests/solvers/test_der_kernels.py`` checks that both
give the same energies, gradients and Hessians to round-off.

Also the banded Cholesky factorisation and solve of the Newton loop
(:mod:`lcefem.solvers.der.compiled_newton`), the section heat step (:func:`heat_step`: exchange
coefficients, solve, fluxes) and the corner gaps per edge (:func:`edge_min_gaps`).

Element layouts are those of :mod:`lcefem.solvers.der.assembly`: an edge k touches the 7 dofs
q[4k : 4k + 7] = (x_k, theta_k, x_(k+1)); the stencil of interior node k + 1 touches the 11 dofs
q[4k : 4k + 11] = (x_k, theta_k, x_(k+1), theta_(k+1), x_(k+2)).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from lcefem.models.rod import STENCIL_MAP
from lcefem.models.units import STEFAN_BOLTZMANN, ZERO_CELSIUS_K

# ``models.rod.STENCIL_MAP`` as index lists: local variable i -> stencil dofs _MAP_IDX[i] with signs _MAP_SGN[i]
# (two entries for the edge vectors e = x_k - x_(k-1), f = x_(k+1) - x_k; one, padded with sign 0, for
# the angles), so that S H S^T costs 256 multiply-adds instead of 1672.
_MAP_IDX = np.zeros((8, 2), np.int64)
_MAP_SGN = np.zeros((8, 2))
for _i in range(8):
    _rows = np.nonzero(STENCIL_MAP[:, _i])[0]
    _MAP_IDX[_i, :len(_rows)] = _rows
    _MAP_SGN[_i, :len(_rows)] = STENCIL_MAP[_rows, _i]


# ----------------------------------------------------------------------------------------------
# Small dense helpers (fixed sizes, no allocation in the hot loops beyond the per-call workspaces)
# ----------------------------------------------------------------------------------------------
@njit(cache=True)
def _dot3(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@njit(cache=True)
def _cross3(a, b, out):
    out[0] = a[1] * b[2] - a[2] * b[1]
    out[1] = a[2] * b[0] - a[0] * b[2]
    out[2] = a[0] * b[1] - a[1] * b[0]


@njit(cache=True)
def _skew_into(v, out, r0, c0, sign):
    """out[r0:r0+3, c0:c0+3] += sign [v]_x."""
    out[r0 + 0, c0 + 1] += -sign * v[2]
    out[r0 + 0, c0 + 2] += sign * v[1]
    out[r0 + 1, c0 + 0] += sign * v[2]
    out[r0 + 1, c0 + 2] += -sign * v[0]
    out[r0 + 2, c0 + 0] += -sign * v[1]
    out[r0 + 2, c0 + 1] += sign * v[0]


@njit(cache=True)
def _matmul(a, b, out):
    n, m = a.shape
    p = b.shape[1]
    for i in range(n):
        for j in range(p):
            s = 0.0
            for k in range(m):
                s += a[i, k] * b[k, j]
            out[i, j] = s


@njit(cache=True)
def _to_stencil(h8, h11):
    """h11 (11, 11) = S h8 S^T with S = ``models.rod.STENCIL_MAP``."""
    h11[:, :] = 0.0
    for i in range(8):
        for p in range(2):
            a = _MAP_IDX[i, p]
            sa = _MAP_SGN[i, p]
            if sa == 0.0:
                continue
            for j in range(8):
                v = sa * h8[i, j]
                for q in range(2):
                    sb = _MAP_SGN[j, q]
                    if sb != 0.0:
                        h11[a, _MAP_IDX[j, q]] += v * sb


@njit(cache=True)
def _rows_to_stencil(j8, j11):
    """j11 (r, 11) = j8 S^T for a (r, 8) Jacobian."""
    j11[:, :] = 0.0
    for r in range(j8.shape[0]):
        for i in range(8):
            for p in range(2):
                sa = _MAP_SGN[i, p]
                if sa != 0.0:
                    j11[r, _MAP_IDX[i, p]] += sa * j8[r, i]


@njit(cache=True)
def _scatter(base, g_loc, H_loc, grad, band, with_hessian):
    m = g_loc.shape[0]
    for a in range(m):
        grad[base + a] += g_loc[a]
    if with_hessian:
        for a in range(m):
            for c in range(a + 1):
                band[a - c, base + c] += H_loc[a, c]


@njit(cache=True)
def _source_change_into(g_loc, H_loc, slot_a, slot_t, slot_b, db, ddb, W, tmp, out, with_hessian):
    """Chain rule of ``models.rod.apply_source_change`` for one element, in place on g_loc and on the
    lower triangle of H_loc (the only part :func:`_scatter` reads); slots (node a start, theta index,
    node b start), db (n_slots, 3), ddb (n_slots, 3, 3).

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


# ----------------------------------------------------------------------------------------------
# Holonomy derivatives of the transport source (models.rod.source_change)
# ----------------------------------------------------------------------------------------------
@njit(cache=True)
def source_change(source, t, length):
    """dbeta/de (n, 3) and d2beta/de2 (n, 3, 3) per edge (``models.rod.source_change``)."""
    n = len(t)
    db = np.empty((n, 3))
    ddb = np.empty((n, 3, 3))
    g = np.empty(3)
    hb = np.empty((3, 3))
    P = np.empty((3, 3))
    tmp = np.empty((3, 3))
    for k in range(n):
        s = source[k]
        tk = t[k]
        c = 1.0 + _dot3(s, tk)
        _cross3(tk, s, g)
        for i in range(3):
            g[i] /= c
        inv_l = 1.0 / length[k]
        for i in range(3):
            db[k, i] = g[i] * inv_l
        for i in range(3):
            for j in range(3):
                # sym(outer(-g c, t + s)) / (2 c^2)
                hb[i, j] = (-(g[i] * c) * (tk[j] + s[j]) - (g[j] * c) * (tk[i] + s[i])) / (2.0 * c * c)
                P[i, j] = (1.0 if i == j else 0.0) - tk[i] * tk[j]
        _matmul(P, hb, tmp)
        _matmul(tmp, P, hb)
        inv_l2 = inv_l * inv_l
        for i in range(3):
            for j in range(3):
                ddb[k, i, j] = hb[i, j] * inv_l2 - (g[i] * tk[j] + tk[i] * g[j]) * inv_l2
    return db, ddb


# ----------------------------------------------------------------------------------------------
# Elastic energy: stretching of edges, bending and twisting of interior nodes
# ----------------------------------------------------------------------------------------------
@njit(cache=True)
def _twist_hessian_ef(te, tf, le, lf, kb, out, w33):
    """out (6, 6) = ``models.rod.twist_hessian_ef`` of one stencil; w33 (6, 3, 3) scratch."""
    chi = 1.0 + _dot3(te, tf)
    tt_diag = w33[0]
    tt_off = w33[1]
    pe = w33[2]
    pf = w33[3]
    tt_off[:, :] = 0.0
    for i in range(3):
        for j in range(3):
            tt_diag[i, j] = (kb[i] * (te[j] + tf[j]) + (te[i] + tf[i]) * kb[j]) / (4.0 * chi)
            tt_off[i, j] = kb[i] * te[j] / (2.0 * chi)
            d = 1.0 if i == j else 0.0
            pe[i, j] = (d - te[i] * te[j]) / le
            pf[i, j] = (d - tf[i] * tf[j]) / lf
    _skew_into(te, tt_off, 0, 0, -1.0 / chi)
    t1 = w33[4]
    t2 = w33[5]
    _matmul(pe, tt_diag, t1)
    _matmul(t1, pe, t2)
    for i in range(3):
        for j in range(3):
            out[i, j] = -(t2[i, j] + (kb[i] * te[j] + te[i] * kb[j]) / (2.0 * le * le))
    _matmul(pf, tt_diag, t1)
    _matmul(t1, pf, t2)
    for i in range(3):
        for j in range(3):
            out[3 + i, 3 + j] = -(t2[i, j] + (kb[i] * tf[j] + tf[i] * kb[j]) / (2.0 * lf * lf))
    _matmul(pe, tt_off, t1)
    _matmul(t1, pf, t2)
    for i in range(3):
        for j in range(3):
            out[i, 3 + j] = -t2[i, j]
            out[3 + j, i] = -t2[i, j]


@njit(cache=True)
def _element_scratch():
    """Scratch arrays of the element functions (:func:`_bend_twist_element`, :func:`_stencil_point_element`),
    allocated once per kernel call: (v3 (12, 3), v6 (5, 6), v8 (4, 8), m36 (2, 3, 6), m66 (4, 6, 6),
    w33 (6, 3, 3))."""
    return (np.zeros((12, 3)), np.zeros((5, 6)), np.zeros((4, 8)), np.zeros((2, 3, 6)), np.zeros((4, 6, 6)),
            np.zeros((6, 3, 3)))


@njit(cache=True)
def _bend_twist_element(e, f, m1e, m2e, m1f, m2f, twist, kbar1, kbar2, tbar, inv_l, EI1, EI2, GJ,
                        grad, hess, with_hessian, ws):
    """``models.rod.bend_twist`` of one interior node: energy; gradient (8,) and Hessian (8, 8) in
    (e, f, theta_e, theta_f) written into grad, hess; ``ws`` the scratch of :func:`_element_scratch`
    (no allocation per element: at ~100 nodes the allocations cost as much as the arithmetic)."""
    v3, v6, v8, m36, m66, w33 = ws
    te, tf, nv, kb, M1, M2, w, ue, uf, me, mf = v3[0], v3[1], v3[2], v3[3], v3[4], v3[5], v3[6], v3[7], v3[8], \
        v3[9], v3[10]
    dD, dnw, jte, jtf = v6[0], v6[1], v6[2], v6[3]
    g1, g2, gt = v8[0], v8[1], v8[2]
    dn, jac = m36[0], m36[1]
    h6, ddD, blk, th = m66[0], m66[1], m66[2], m66[3]
    le = math.sqrt(_dot3(e, e))
    lf = math.sqrt(_dot3(f, f))
    for i in range(3):
        te[i] = e[i] / le
        tf[i] = f[i] / lf
    _cross3(e, f, nv)
    D = le * lf + _dot3(e, f)
    for i in range(3):
        kb[i] = 2.0 * nv[i] / D
    dn[:, :] = 0.0
    _skew_into(f, dn, 0, 0, -1.0)
    _skew_into(e, dn, 0, 3, 1.0)
    for i in range(3):
        dD[i] = lf * te[i] + f[i]
        dD[3 + i] = le * tf[i] + e[i]
    for c in range(3):
        for i in range(6):
            jac[c, i] = 2.0 * (dn[c, i] / D - nv[c] * dD[i] / (D * D))
    for i in range(3):
        M1[i] = m1e[i] + m1f[i]
        M2[i] = m2e[i] + m2f[i]
    k1 = 0.5 * _dot3(kb, M2)
    k2 = -0.5 * _dot3(kb, M1)
    for i in range(6):
        s1 = 0.0
        s2 = 0.0
        for c in range(3):
            s1 += M2[c] * jac[c, i]
            s2 += M1[c] * jac[c, i]
        g1[i] = 0.5 * s1
        g2[i] = -0.5 * s2
    g1[6] = -0.5 * _dot3(kb, m1e)
    g1[7] = -0.5 * _dot3(kb, m1f)
    g2[6] = -0.5 * _dot3(kb, m2e)
    g2[7] = -0.5 * _dot3(kb, m2f)
    for i in range(3):
        gt[i] = kb[i] / (2.0 * le)
        gt[3 + i] = kb[i] / (2.0 * lf)
    gt[6] = -1.0
    gt[7] = 1.0
    d1 = k1 - kbar1
    d2 = k2 - kbar2
    dt = twist - tbar
    energy = 0.5 * inv_l * (EI1 * d1 * d1 + EI2 * d2 * d2 + GJ * dt * dt)
    c1 = EI1 * d1 * inv_l
    c2 = EI2 * d2 * inv_l
    ct = GJ * dt * inv_l
    for i in range(8):
        grad[i] = c1 * g1[i] + c2 * g2[i] + ct * gt[i]
    if not with_hessian:
        return energy
    hess[:, :] = 0.0
    # kb_hess(w), w = 1/2 (c1 M2 - c2 M1)
    for i in range(3):
        w[i] = 0.5 * (c1 * M2[i] - c2 * M1[i])
    wn = _dot3(w, nv)
    dnw[:] = 0.0
    for i in range(6):
        for c in range(3):
            dnw[i] += w[c] * dn[c, i]
    h6[:, :] = 0.0
    _skew_into(w, h6, 0, 3, -1.0)
    _skew_into(w, h6, 3, 0, 1.0)
    for i in range(3):
        for j in range(3):
            d = 1.0 if i == j else 0.0
            ddD[i, j] = (lf / le) * (d - te[i] * te[j])
            ddD[3 + i, 3 + j] = (le / lf) * (d - tf[i] * tf[j])
            ddD[i, 3 + j] = te[i] * tf[j] + d
            ddD[3 + j, i] = te[i] * tf[j] + d
    for i in range(6):
        for j in range(6):
            v = h6[i, j] / D
            v -= (dnw[i] * dD[j] + dD[i] * dnw[j]) / (D * D)
            v += (2.0 * wn / (D * D * D)) * dD[i] * dD[j]
            v -= (wn / (D * D)) * ddD[i, j]
            hess[i, j] = 2.0 * v
    # cross terms kb x frame
    for i in range(3):
        ue[i] = 0.5 * (-c1 * m1e[i] - c2 * m2e[i])
        uf[i] = 0.5 * (-c1 * m1f[i] - c2 * m2f[i])
        me[i] = 0.5 * (c1 * m2e[i] - c2 * m1e[i])
        mf[i] = 0.5 * (c1 * m2f[i] - c2 * m1f[i])
    for i in range(6):
        x0 = 0.0
        x1 = 0.0
        y0 = 0.0
        y1 = 0.0
        for c in range(3):
            x0 += jac[c, i] * ue[c]
            x1 += jac[c, i] * uf[c]
            y0 += jac[c, i] * te[c]
            y1 += jac[c, i] * tf[c]
        hess[i, 6] += x0
        hess[i, 7] += x1
        hess[6, i] += x0
        hess[7, i] += x1
        jte[i] = y0
        jtf[i] = y1
    blk[:, :] = 0.0
    for i in range(6):
        for j in range(3):
            blk[i, j] -= jte[i] * me[j] / le
            blk[i, 3 + j] -= jtf[i] * mf[j] / lf
    for i in range(6):
        for j in range(6):
            hess[i, j] += blk[i, j] + blk[j, i]
    for i in range(3):
        for j in range(3):
            hess[i, j] += -0.5 * (me[i] * kb[j] + kb[i] * me[j]) / (le * le)
            hess[3 + i, 3 + j] += -0.5 * (mf[i] * kb[j] + kb[i] * mf[j]) / (lf * lf)
    hess[6, 6] += -_dot3(kb, me)
    hess[7, 7] += -_dot3(kb, mf)
    _twist_hessian_ef(te, tf, le, lf, kb, th, w33)
    for i in range(6):
        for j in range(6):
            hess[i, j] += ct * th[i, j]
    a1 = EI1 * inv_l
    a2 = EI2 * inv_l
    at = GJ * inv_l
    for i in range(8):
        for j in range(8):
            hess[i, j] += a1 * g1[i] * g1[j] + a2 * g2[i] * g2[j] + at * gt[i] * gt[j]
    return energy


@njit(cache=True)
def elastic(x, m1, m2, twist, rest_length, kappa_bar, twist_bar, voronoi, EA, EI1, EI2, GJ,
            db, ddb, with_source, with_hessian, grad, band):
    """Stretching + bending + twisting of the whole rod; adds the gradient into ``grad`` (4N-1,) and
    (with_hessian) the lower band into ``band`` (11, 4N-1); returns the energy [mJ].

    db, ddb: per-edge holonomy derivatives (:func:`source_change`), used when ``with_source``.
    """
    n_edges = len(rest_length)
    energy = 0.0
    # Stretching (edge k, dofs 4k .. 4k + 6); it does not depend on the frames.
    g7 = np.zeros(7)
    h7 = np.zeros((7, 7))
    tt = np.empty((3, 3))
    e = np.empty(3)
    f = np.empty(3)
    t = np.empty(3)
    ws = _element_scratch()
    for k in range(n_edges):
        for i in range(3):
            e[i] = x[k + 1, i] - x[k, i]
        length = math.sqrt(_dot3(e, e))
        for i in range(3):
            t[i] = e[i] / length
        strain = length / rest_length[k] - 1.0
        energy += 0.5 * EA * strain * strain * rest_length[k]
        gs = EA * strain
        for i in range(3):
            g7[i] = -gs * t[i]
            g7[4 + i] = gs * t[i]
        if with_hessian:
            a = EA / rest_length[k]
            b = EA * strain / length
            for i in range(3):
                for j in range(3):
                    tt[i, j] = t[i] * t[j]
                    hs = a * tt[i, j] + b * ((1.0 if i == j else 0.0) - tt[i, j])
                    h7[i, j] = hs
                    h7[4 + i, 4 + j] = hs
                    h7[i, 4 + j] = -hs
                    h7[4 + i, j] = -hs
        _scatter(4 * k, g7, h7, grad, band, with_hessian)
    # Bending and twisting (stencil of interior node k + 1, dofs 4k .. 4k + 10).
    g8 = np.empty(8)
    h8 = np.empty((8, 8))
    g11 = np.empty(11)
    h11 = np.empty((11, 11))
    tmp = np.empty((8, 11))
    W = np.empty((2, 12))  # rows of D: values and columns (_source_change_into)
    tmp11 = np.empty((11, 11))
    out11 = np.empty((11, 11))
    slot_a = np.array([0, 4])
    slot_t = np.array([3, 7])
    slot_b = np.array([4, 8])
    dbs = np.empty((2, 3))
    ddbs = np.empty((2, 3, 3))
    for k in range(n_edges - 1):
        for i in range(3):
            e[i] = x[k + 1, i] - x[k, i]
            f[i] = x[k + 2, i] - x[k + 1, i]
        energy += _bend_twist_element(e, f, m1[k], m2[k], m1[k + 1], m2[k + 1], twist[k], kappa_bar[k, 0],
                                      kappa_bar[k, 1], twist_bar[k], 1.0 / voronoi[k], EI1, EI2, GJ,
                                      g8, h8, with_hessian, ws)
        g11[:] = 0.0
        for i in range(8):
            for p in range(2):
                g11[_MAP_IDX[i, p]] += _MAP_SGN[i, p] * g8[i]
        if with_hessian:
            _to_stencil(h8, h11)
        if with_source:
            dbs[0] = db[k]
            dbs[1] = db[k + 1]
            ddbs[0] = ddb[k]
            ddbs[1] = ddb[k + 1]
            _source_change_into(g11, h11, slot_a, slot_t, slot_b, dbs, ddbs, W, tmp11, out11, with_hessian)
        _scatter(4 * k, g11, h11, grad, band, with_hessian)
    return energy


# ----------------------------------------------------------------------------------------------
# Contact and friction of the sample points between sections (models.rod.StencilPoints)
# ----------------------------------------------------------------------------------------------
@njit(cache=True)
def _stencil_point_element(e, f, r, t, side, sigma, g, jac, h11, hv, jv, tmp, with_hessian, ws):
    """``models.rod.stencil_point_derivatives`` of one point: jac (3, 11) and (with_hessian) the
    Hessian h11 (11, 11) of g . point, frames transported from the current state; ``ws`` the
    scratch of :func:`_element_scratch`."""
    v3, v6, v8, m36, m66, w33 = ws
    te, tf, kb, tr, pg = v3[0], v3[1], v3[2], v3[3], v3[4]
    dth, cross_v = v8[0], v8[1]
    th = m66[0]
    le = math.sqrt(_dot3(e, e))
    lf = math.sqrt(_dot3(f, f))
    for i in range(3):
        te[i] = e[i] / le
        tf[i] = f[i] / lf
    _cross3(e, f, kb)
    D = le * lf + _dot3(e, f)
    for i in range(3):
        kb[i] = 2.0 * kb[i] / D
    cm = sigma - 0.5
    for i in range(3):
        dth[i] = cm / (2.0 * le) * kb[i]
        dth[3 + i] = cm / (2.0 * lf) * kb[i]
    dth[6] = -cm if side else 1.0 - cm
    dth[7] = 1.0 + cm if side else cm
    length = lf if side else le
    _cross3(t, r, tr)
    off = 3 if side else 0
    for i in range(3):
        for j in range(8):
            jv[i, j] = tr[i] * dth[j]
        for j in range(3):
            jv[i, off + j] += -t[i] * r[j] / length
    _rows_to_stencil(jv, jac)
    w0 = 0.0 if side else 1.0 - sigma
    w1 = 1.0 - sigma if side else sigma
    w2 = sigma if side else 0.0
    for i in range(3):
        jac[i, i] += w0
        jac[i, 4 + i] += w1
        jac[i, 8 + i] += w2
    if not with_hessian:
        return
    gt = _dot3(g, t)
    for i in range(3):
        pg[i] = g[i] - gt * t[i]
    inv_l2 = 1.0 / (length * length)
    hv[:, :] = 0.0
    for i in range(3):
        for j in range(3):
            hv[off + i, off + j] = (gt * (r[i] * t[j] + t[i] * r[j]) - 0.5 * (r[i] * pg[j] + pg[i] * r[j])) * inv_l2
    cross_v[:] = 0.0
    for i in range(3):
        cross_v[off + i] = -(gt / length) * tr[i]
    gr = _dot3(g, r)
    for i in range(8):
        for j in range(8):
            hv[i, j] += cross_v[i] * dth[j] + dth[i] * cross_v[j] - gr * dth[i] * dth[j]
    _twist_hessian_ef(te, tf, le, lf, kb, th, w33)
    c = _dot3(g, tr) * cm
    for i in range(6):
        for j in range(6):
            hv[i, j] += c * th[i, j]
    _to_stencil(hv, h11)


# ----------------------------------------------------------------------------------------------
# All sample points of the contact sampling, and the whole contact + friction potential
# ----------------------------------------------------------------------------------------------
@njit(cache=True)
def sample_points(x, a1, t, theta, twist, m1, m2, side, sigma, offsets, end_ids, end_sigma, end_offsets):
    """Positions and frame offsets r = a m1 + b m2 [mm] of every contact sample point.

    Stencil points (``models.rod.stencil_points``; frame angle interpolated with the node's twist):
    (N-2, p_s, 3) each, empty when ``side`` is empty. End-edge points (``models.rod.section_points``,
    the edge's own frame): (len(end_ids), p_e, 3) each; end_sigma is (len(end_ids), p_e).
    """
    ns = len(twist) if len(side) else 0
    ps = len(side)
    pos_s = np.empty((ns, ps, 3))
    r_s = np.empty((ns, ps, 3))
    a2 = np.empty(3)
    for k in range(ns):
        last_edge, last_sigma = -1, np.nan
        c, s_ = 1.0, 0.0
        for j in range(ps):
            edge = k + (1 if side[j] else 0)
            # the section points of one sample section (e.g. its four corners) share the frame angle:
            # its cos, sin and a2 once per section (the same values; 4x fewer sin/cos, issue 17)
            if edge != last_edge or sigma[j] != last_sigma:
                last_edge, last_sigma = edge, sigma[j]
                th = theta[edge] + (sigma[j] - 0.5) * twist[k]
                c = math.cos(th)
                s_ = math.sin(th)
                _cross3(t[edge], a1[edge], a2)
            for i in range(3):
                mm1 = c * a1[edge, i] + s_ * a2[i]
                mm2 = -s_ * a1[edge, i] + c * a2[i]
                r = offsets[j, 0] * mm1 + offsets[j, 1] * mm2
                r_s[k, j, i] = r
                pos_s[k, j, i] = x[edge, i] + sigma[j] * (x[edge + 1, i] - x[edge, i]) + r
    ne = len(end_ids)
    pe = end_offsets.shape[0]
    pos_e = np.empty((ne, pe, 3))
    r_e = np.empty((ne, pe, 3))
    for row in range(ne):
        edge = end_ids[row]
        for j in range(pe):
            sg = end_sigma[row, j]
            for i in range(3):
                r = end_offsets[j, 0] * m1[edge, i] + end_offsets[j, 1] * m2[edge, i]
                r_e[row, j, i] = r
                pos_e[row, j, i] = x[edge, i] + sg * (x[edge + 1, i] - x[edge, i]) + r
    return pos_s, r_s, pos_e, r_e


@njit(cache=True)
def _contact_energy(gap, clearance, delta, K1):
    """``models.contact.contact_energy`` of one point: (E, dE/dgap, d2E/dgap2)."""
    d = clearance - gap
    if d >= delta:
        return d * d, -2.0 * d, 2.0
    if d <= -delta:
        return 0.0, 0.0, 0.0
    xk = K1 * d
    s = (max(xk, 0.0) + math.log1p(math.exp(-abs(xk)))) / K1
    sig = 0.5 * (1.0 + math.tanh(0.5 * xk))
    return s * s, -2.0 * s * sig, 2.0 * sig * sig + 2.0 * s * sig * (1.0 - sig) * K1


@njit(cache=True)
def normal_force(gap, clearance, delta, K1, stiffness):
    """``models.contact.normal_force`` of an array of gaps (any shape) [N]."""
    out = np.empty(gap.size)
    flat = gap.ravel()
    for i in range(gap.size):
        out[i] = -stiffness * _contact_energy(flat[i], clearance, delta, K1)[1]
    return out.reshape(gap.shape)


@njit(cache=True)
def _friction(u, normal, fn, h, mu, K2, grad, hess, with_hessian, w):
    """``models.contact.friction_potential`` of one point: energy; dD/du into grad (3,), d2D/du2
    into hess (3, 3); w (3,) scratch."""
    un = _dot3(u, normal)
    for i in range(3):
        w[i] = u[i] - un * normal[i]
    v = math.sqrt(_dot3(w, w)) / h
    a = 0.5 * K2
    z = a * v
    if z < 1e-3:
        logcosh = 0.5 * z * z - z ** 4 / 12.0
        phi = a * (1.0 - z * z / 3.0)
        psi = -2.0 * a ** 3 / 3.0 + 8.0 * a ** 5 * v * v / 15.0
    else:
        logcosh = z + math.log1p(math.exp(-2.0 * z)) - math.log(2.0)
        th = math.tanh(z)
        phi = th / v
        psi = (a * (1.0 - th * th) * v - th) / v ** 3
    coef = mu * fn
    for i in range(3):
        grad[i] = coef * phi / h * w[i]
    if with_hessian:
        for i in range(3):
            for j in range(3):
                proj = (1.0 if i == j else 0.0) - normal[i] * normal[j]
                hess[i, j] = coef / h * (phi * proj + psi / (h * h) * w[i] * w[j])
    return coef * h * logcosh / a


@njit(cache=True)
def _section_point_element(t, length, r, sig, g, jac, h7, tr):
    """``models.rod.section_point_derivatives`` of one point (edge's own frame): jac (3, 7) and the
    Hessian h7 (7, 7) of g . point, dofs (x0, theta, x1); tr (3,) scratch."""
    _cross3(t, r, tr)
    for i in range(3):
        for j in range(7):
            jac[i, j] = 0.0
        jac[i, i] = 1.0 - sig
        jac[i, 4 + i] = sig
        for j in range(3):
            dr = -t[i] * r[j] / length
            jac[i, j] -= dr
            jac[i, 4 + j] += dr
        jac[i, 3] = tr[i]
    gt = _dot3(g, t)
    inv_l2 = 1.0 / (length * length)
    for i in range(3):
        for j in range(3):
            pgi = g[i] - gt * t[i]
            pgj = g[j] - gt * t[j]
            hee = (gt * (r[i] * t[j] + t[i] * r[j]) - 0.5 * (r[i] * pgj + pgi * r[j])) * inv_l2
            h7[i, j] = hee
            h7[4 + i, 4 + j] = hee
            h7[i, 4 + j] = -hee
            h7[4 + i, j] = -hee
        het = -(gt / length) * tr[i]
        h7[i, 3] = -het
        h7[3, i] = -het
        h7[4 + i, 3] = het
        h7[3, 4 + i] = het
    h7[3, 3] = -_dot3(g, r)


@njit(cache=True)
def contact(pos_s, r_s, pos_e, r_e, x, t, length, side, sigma, end_ids, end_sigma, normal, height, clearance, delta, K1,
            stiffness, with_friction, lag_ns, lag_ps, lag_ne, lag_pe, mu, K2, h, db, ddb, with_source, order,
            grad, band, box, is_box):
    """Contact potential k E(gap) of all sample points with the plane {n.p = height} (or, with
    ``is_box``, with the rounded box ``box`` = (lo, hi, radius, friction) of ``model.Box``: gap, normal and the
    gap's Hessian per point, :func:`box_gap`) plus (with friction) the friction potential of the
    points with a lagged normal force (on a box, tangential to the box's normal at the lagged
    point); ``order`` 0 energy, 1 with gradient, 2 with Hessian (added into grad and band). Returns
    the energy [mJ].

    Mirrors ``Assembly.contact``: a point is differentiated when within reach of the plane or
    carrying a lagged friction force.
    """
    energy = 0.0
    with_hessian = order >= 2
    g_pt = np.empty(3)
    gD = np.zeros(3)
    hD = np.zeros((3, 3))
    u = np.empty(3)
    # stencil points
    jac = np.empty((3, 11))
    h11 = np.empty((11, 11))
    hv = np.empty((8, 8))
    jv = np.empty((3, 8))
    tmp8 = np.empty((8, 11))
    g11 = np.empty(11)
    W = np.empty((2, 12))
    tmp11 = np.empty((11, 11))
    out11 = np.empty((11, 11))
    slot_a = np.array([0, 4])
    slot_t = np.array([3, 7])
    slot_b = np.array([4, 8])
    dbs = np.empty((2, 3))
    ddbs = np.empty((2, 3, 3))
    # end-edge points
    jac7 = np.empty((3, 7))
    h7 = np.empty((7, 7))
    g7 = np.empty(7)
    W7 = np.empty((1, 12))
    tmp7 = np.empty((7, 7))
    out7 = np.empty((7, 7))
    e_a = np.array([0])
    e_t = np.array([3])
    e_b = np.array([4])
    db1 = np.empty((1, 3))
    ddb1 = np.empty((1, 3, 3))
    ws = _element_scratch()
    e = np.empty(3)
    f = np.empty(3)
    w3 = np.empty(3)
    acc_g11 = np.empty(11)
    acc_h11 = np.empty((11, 11))
    acc_g7 = np.empty(7)
    acc_h7 = np.empty((7, 7))
    nrm = normal.copy()  # the point's contact normal (the plane's, or the box's at the point)
    nfr = normal.copy()  # the friction's normal (the box's at the lagged point)
    hg = np.zeros((3, 3))  # Hessian of a box gap
    hg_lag = np.zeros((3, 3))
    if is_box and box[7] >= 0.0:  # the box's own friction coefficient
        mu = box[7]
    for kind in range(2):
        pos = pos_s if kind == 0 else pos_e
        rr = r_s if kind == 0 else r_e
        lag_n = lag_ns if kind == 0 else lag_ne
        lag_p = lag_ps if kind == 0 else lag_pe
        # The points of one element (a stencil, or an end edge) are summed first, then the source
        # change (linear in gradient and Hessian) and the scatter are done once per element.
        acc_g = acc_g11 if kind == 0 else acc_g7
        acc_h = acc_h11 if kind == 0 else acc_h7
        for row in range(pos.shape[0]):
            active = False
            for j in range(pos.shape[1]):
                p = pos[row, j]
                if is_box:
                    gap = box_gap(p, box, nrm, hg)
                else:
                    gap = _dot3(p, normal) - height
                fn = lag_n[row, j] if with_friction else 0.0
                if not (gap < clearance + delta or fn > 0.0):
                    continue
                E, d1, d2 = _contact_energy(gap, clearance, delta, K1)
                energy += stiffness * E
                if fn > 0.0:
                    for i in range(3):
                        u[i] = p[i] - lag_p[row, j, i]
                    if is_box:
                        box_gap(lag_p[row, j], box, nfr, hg_lag)
                    energy += _friction(u, nfr, fn, h, mu, K2, gD, hD, with_hessian, w3)
                else:
                    gD[:] = 0.0
                    hD[:, :] = 0.0
                if order == 0:
                    continue
                if is_box and with_hessian and d1 != 0.0:
                    for a in range(3):
                        for b in range(3):
                            hD[a, b] += stiffness * d1 * hg[a, b]
                if not active:
                    active = True
                    acc_g[:] = 0.0
                    if with_hessian:
                        acc_h[:, :] = 0.0
                for i in range(3):
                    g_pt[i] = stiffness * d1 * nrm[i] + gD[i]
                cc = stiffness * d2
                if kind == 0:
                    k = row
                    edge = k + (1 if side[j] else 0)
                    for i in range(3):
                        e[i] = x[k + 1, i] - x[k, i]
                        f[i] = x[k + 2, i] - x[k + 1, i]
                    _stencil_point_element(e, f, rr[row, j], t[edge], side[j], sigma[j], g_pt, jac, h11, hv, jv,
                                           tmp8, with_hessian, ws)
                    _chain_point(jac, h11, g_pt, cc, nrm, hD, g11, with_hessian)
                    _accumulate(g11, h11, acc_g, acc_h, with_hessian)
                else:
                    edge = end_ids[row]
                    _section_point_element(t[edge], length[edge], rr[row, j], end_sigma[row, j], g_pt, jac7, h7, w3)
                    _chain_point(jac7, h7, g_pt, cc, nrm, hD, g7, with_hessian)
                    _accumulate(g7, h7, acc_g, acc_h, with_hessian)
            if not active:
                continue
            if kind == 0:
                k = row
                if with_source:
                    dbs[0] = db[k]
                    dbs[1] = db[k + 1]
                    ddbs[0] = ddb[k]
                    ddbs[1] = ddb[k + 1]
                    _source_change_into(acc_g, acc_h, slot_a, slot_t, slot_b, dbs, ddbs, W, tmp11, out11,
                                        with_hessian)
                _scatter(4 * k, acc_g, acc_h, grad, band, with_hessian)
            else:
                edge = end_ids[row]
                if with_source:
                    db1[0] = db[edge]
                    ddb1[0] = ddb[edge]
                    _source_change_into(acc_g, acc_h, e_a, e_t, e_b, db1, ddb1, W7, tmp7, out7, with_hessian)
                _scatter(4 * edge, acc_g, acc_h, grad, band, with_hessian)
    return energy


@njit(cache=True)
def box_gap(p, box, n, hg):
    """Gap [mm] of the point p to the rounded box ``box`` = (lo (3), hi (3), radius) of ``model.Box``;
    the outward unit normal (the gap's gradient) into n (3,) and the gap's Hessian into hg (3, 3).
    Beyond the inner box [lo + r, hi - r]: gap = D - r with D the distance to it, Hessian (P - n n^T)/D,
    P the axes along which p lies beyond it. Inside the inner box (a penetration deeper than the edge
    radius): minus the depth below the nearest face, minus r, with that face's normal and no curvature."""
    r = box[6]
    d2 = 0.0
    for i in range(3):
        lo = box[i] + r
        hi = box[3 + i] - r
        if p[i] < lo:
            n[i] = p[i] - lo
        elif p[i] > hi:
            n[i] = p[i] - hi
        else:
            n[i] = 0.0
        d2 += n[i] * n[i]
    if d2 > 0.0:
        D = math.sqrt(d2)
        for i in range(3):
            n[i] /= D
        for i in range(3):
            for j in range(3):
                hg[i, j] = -n[i] * n[j] / D
            if n[i] != 0.0:
                hg[i, i] += 1.0 / D
        return D - r
    best = math.inf
    axis = 0
    sign = 1.0
    for i in range(3):
        a = p[i] - (box[i] + r)
        b = (box[3 + i] - r) - p[i]
        if a < best:
            best, axis, sign = a, i, -1.0
        if b < best:
            best, axis, sign = b, i, 1.0
    for i in range(3):
        n[i] = 0.0
        for j in range(3):
            hg[i, j] = 0.0
    n[axis] = sign
    return -best - r


@njit(cache=True)
def _accumulate(g_loc, h_loc, acc_g, acc_h, with_hessian):
    for i in range(g_loc.shape[0]):
        acc_g[i] += g_loc[i]
    if with_hessian:
        for i in range(g_loc.shape[0]):
            for j in range(g_loc.shape[0]):
                acc_h[i, j] += h_loc[i, j]


@njit(cache=True)
def _chain_point(jac, hloc, g_pt, cc, normal, hD, g_loc, with_hessian):
    """g_loc = J^T g_pt; hloc += cc (J^T n)(J^T n)^T + J^T hD J (hloc holds the g.point Hessian)."""
    m = jac.shape[1]
    for i in range(m):
        g_loc[i] = g_pt[0] * jac[0, i] + g_pt[1] * jac[1, i] + g_pt[2] * jac[2, i]
    if not with_hessian:
        return
    for i in range(m):
        jni = normal[0] * jac[0, i] + normal[1] * jac[1, i] + normal[2] * jac[2, i]
        for j in range(m):
            jnj = normal[0] * jac[0, j] + normal[1] * jac[1, j] + normal[2] * jac[2, j]
            s = cc * jni * jnj
            for a in range(3):
                s += jac[a, i] * (hD[a, 0] * jac[0, j] + hD[a, 1] * jac[1, j] + hD[a, 2] * jac[2, j])
            hloc[i, j] += s


# ----------------------------------------------------------------------------------------------
# Time-parallel transport of the reference frames (solvers.der.frames)
# ----------------------------------------------------------------------------------------------
@njit(cache=True)
def _parallel_transport(u, t_from, t_to, out, w3):
    """``models.rod.parallel_transport`` of one vector; w3 (3, 3) scratch."""
    v, vu, vvu = w3[0], w3[1], w3[2]
    _cross3(t_from, t_to, v)
    c = _dot3(t_from, t_to)
    _cross3(v, u, vu)
    _cross3(v, vu, vvu)
    for i in range(3):
        out[i] = u[i] + vu[i] + vvu[i] / (1.0 + c)


@njit(cache=True)
def transport_frames(a1, t_old, t_new, ref_prev):
    """Reference directors transported in time from t_old to t_new and re-orthonormalised
    (``frames.transport_directors``), and the reference twist of the interior nodes continued from
    ``ref_prev`` without 2 pi jumps (``frames.reference_twist``)."""
    n = len(t_new)
    out = np.empty((n, 3))
    p = np.empty(3)
    w3 = np.empty((3, 3))
    for k in range(n):
        _parallel_transport(a1[k], t_old[k], t_new[k], p, w3)
        pt = _dot3(p, t_new[k])
        for i in range(3):
            p[i] -= pt * t_new[k, i]
        norm = math.sqrt(_dot3(p, p))
        for i in range(3):
            out[k, i] = p[i] / norm
    ref = np.empty(n - 1)
    cr = np.empty(3)
    for k in range(n - 1):
        _parallel_transport(out[k], t_new[k], t_new[k + 1], p, w3)
        _cross3(p, out[k + 1], cr)
        angle = math.atan2(_dot3(cr, t_new[k + 1]), _dot3(p, out[k + 1]))
        d = angle - ref_prev[k]
        ref[k] = ref_prev[k] + math.atan2(math.sin(d), math.cos(d))
    return out, ref


@njit(cache=True)
def edge_tangents(x):
    """Edges e_k = x_(k+1) - x_k [mm], their lengths [mm] and unit tangents t_k = e_k / |e_k|."""
    n = len(x) - 1
    e = np.empty((n, 3))
    length = np.empty(n)
    t = np.empty((n, 3))
    for k in range(n):
        for i in range(3):
            e[k, i] = x[k + 1, i] - x[k, i]
        length[k] = math.sqrt(e[k, 0] * e[k, 0] + e[k, 1] * e[k, 1] + e[k, 2] * e[k, 2])
        for i in range(3):
            t[k, i] = e[k, i] / length[k]
    return e, length, t


@njit(cache=True)
def material_frames_twist(t, a1, theta, ref):
    """Material frames m1 = cos(theta) a1 + sin(theta) t x a1, m2 = -sin(theta) a1 + cos(theta)
    t x a1 (``frames.material_frames``) and the integrated twists theta_(k+1) - theta_k + ref_k [rad]."""
    n = len(theta)
    m1 = np.empty((n, 3))
    m2 = np.empty((n, 3))
    a2 = np.empty(3)
    for k in range(n):
        _cross3(t[k], a1[k], a2)
        c = math.cos(theta[k])
        s_ = math.sin(theta[k])
        for i in range(3):
            m1[k, i] = c * a1[k, i] + s_ * a2[i]
            m2[k, i] = -s_ * a1[k, i] + c * a2[i]
    twist = np.empty(n - 1)
    for k in range(n - 1):
        twist[k] = theta[k + 1] - theta[k] + ref[k]
    return m1, m2, twist


@njit(cache=True)
def moved_geometry(x, theta, a1_old, t_old, ref_prev):
    """Everything a displaced state needs, in one pass (``model.RodState.moved`` and ``geometry``):
    edges e, lengths, unit tangents t, reference directors a1 transported in time from t_old (and
    the reference twist continued from ref_prev, :func:`transport_frames`), material frames
    m1 = cos(theta) a1 + sin(theta) t x a1, m2 = t x m1 (``frames.material_frames``) and the
    integrated twists theta_(k+1) - theta_k + ref_twist_k."""
    e, length, t = edge_tangents(x)
    a1, ref = transport_frames(a1_old, t_old, t, ref_prev)
    m1, m2, twist = material_frames_twist(t, a1, theta, ref)
    return e, length, t, a1, ref, m1, m2, twist


# ----------------------------------------------------------------------------------------------
# Banded Cholesky (the Newton loop's and the heat step's symmetric banded systems)
# ----------------------------------------------------------------------------------------------
@njit(cache=True)
def band_cholesky(ab):
    """Lower banded Cholesky factor in place (LAPACK dpbtf2 storage ab[i - j, j] = H[i, j]); returns
    info (0: done; k > 0: the leading minor of order k is not positive definite).

    The arithmetic of dpbtf2 in its order (scale the column, rank-one update of the trailing block
    as dsyr does it), on a transposed copy so that each update runs along contiguous memory (1.5x
    faster at 399 x 11; the same factor bit for bit): :func:`band_cholesky_rows`."""
    kd = ab.shape[0] - 1
    n = ab.shape[1]
    L = np.empty((n, kd + 1))  # L[j, i] = ab[i, j]
    for j in range(n):
        for i in range(kd + 1):
            L[j, i] = ab[i, j]
    info = band_cholesky_rows(L)
    for j in range(n):
        for i in range(kd + 1):
            ab[i, j] = L[j, i]
    return info


@njit(cache=True)
def band_cholesky_rows(L):
    """:func:`band_cholesky` on the transposed storage L[j, i] = H[j + i, j] (row j: column j of the
    band), in place; returns info. A caller that assembles in this layout skips the two copies
    (the heat step, :func:`heat_solve`)."""
    n = L.shape[0]
    kd = L.shape[1] - 1
    info = 0
    for j in range(n):
        ajj = L[j, 0]
        if not ajj > 0.0:
            info = j + 1
            break
        ajj = math.sqrt(ajj)
        L[j, 0] = ajj
        kn = min(kd, n - 1 - j)
        if kn > 0:
            r = 1.0 / ajj
            for i in range(1, kn + 1):
                L[j, i] *= r
            for c in range(kn):  # symmetric rank-one update of the trailing block (dsyr, lower)
                xc = L[j, c + 1]
                if xc != 0.0:
                    temp = -xc
                    for p in range(c, kn):
                        L[j + 1 + c, p - c] += L[j, p + 1] * temp
    return info


@njit(cache=True)
def band_cholesky_solve_rows(L, x):
    """:func:`band_cholesky_solve` with the factor of :func:`band_cholesky_rows` (the same
    operations in the same order)."""
    n = L.shape[0]
    kd = L.shape[1] - 1
    for j in range(n):
        if x[j] != 0.0:
            x[j] /= L[j, 0]
            temp = x[j]
            for i in range(1, min(kd, n - 1 - j) + 1):
                x[j + i] -= temp * L[j, i]
    for j in range(n - 1, -1, -1):
        temp = x[j]
        for i in range(1, min(kd, n - 1 - j) + 1):
            temp -= L[j, i] * x[j + i]
        x[j] = temp / L[j, 0]


@njit(cache=True)
def band_cholesky_solve(factor, x):
    """Solves L L^T y = x in place with the factor of :func:`band_cholesky` (LAPACK dpbtrs, lower)."""
    kd = factor.shape[0] - 1
    n = factor.shape[1]
    for j in range(n):  # L z = x (dtbsv, lower, no transpose)
        if x[j] != 0.0:
            x[j] /= factor[0, j]
            temp = x[j]
            for i in range(1, min(kd, n - 1 - j) + 1):
                x[j + i] -= temp * factor[i, j]
    for j in range(n - 1, -1, -1):  # L^T y = z (dtbsv, lower, transpose)
        temp = x[j]
        for i in range(1, min(kd, n - 1 - j) + 1):
            temp -= factor[i, j] * x[j + i]
        x[j] = temp / factor[0, j]


@njit(cache=True)
def edge_min_gaps(pos_s, pos_e, side, slot_s, end_ids, slot_e, n_edges, k, normal, height, interpolated):
    """``assembly.edge_corner_gaps``: the smallest gap [mm] (position . normal - height) of each of
    the k section point kinds over the sample points of each edge, (n_edges, k), +inf where an edge
    has none. pos_s (N-2, p_s, 3) the stencil points (point j on edge s + side[j], kind slot_s[j];
    used when ``interpolated``), pos_e (n_end, p_e, 3) those of the edges end_ids (kind slot_e[j])."""
    out = np.full((n_edges, k), np.inf)
    for r in range(len(end_ids)):
        edge = end_ids[r]
        for j in range(pos_e.shape[1]):
            g = pos_e[r, j, 0] * normal[0] + pos_e[r, j, 1] * normal[1] + pos_e[r, j, 2] * normal[2] - height
            if g < out[edge, slot_e[j]]:
                out[edge, slot_e[j]] = g
    if interpolated:
        for s in range(pos_s.shape[0]):
            for j in range(pos_s.shape[1]):
                g = pos_s[s, j, 0] * normal[0] + pos_s[s, j, 1] * normal[1] + pos_s[s, j, 2] * normal[2] - height
                edge = s + side[j]
                if g < out[edge, slot_s[j]]:
                    out[edge, slot_s[j]] = g
    return out


# ----------------------------------------------------------------------------------------------
# Section heat step (solvers.der.heat.SectionHeat.step)
# ----------------------------------------------------------------------------------------------
@njit(cache=True)
def heat_solve(C, G_g, G_a, T, T_ground, T_air, length, pair_a, pair_b, pair_g, k_axial):
    """Cell temperatures (n, n_cells) [C] of one implicit-Euler heat step: the banded system
    (C + G_g + G_a + conduction) T_new = C T + G_g T_ground + G_a T_air assembled (cells of edge k at
    rows n_cells k ..., in-section pairs (pair_a, pair_b) with conductance per length pair_g
    [mW/(K mm)], the same cell of neighbouring edges k_axial / mean length) and solved by
    :func:`band_cholesky`. C (n, 1) [mW/K] = capacity / dt; the rest (n, n_cells).
    The sums are taken in the order of the numpy assembly it replaces (diagonal: capacity and
    exchange, then the pair sums, then the axial terms)."""
    n, nc = G_g.shape
    nd = n * nc
    L = np.zeros((nd, nc + 1))  # L[j, i] = H[j + i, j] (band_cholesky_rows: no transposed copies)
    rhs = np.empty(nd)
    sum_a = np.zeros(nc)
    sum_b = np.zeros(nc)
    for k in range(n):
        base = nc * k
        sum_a[:] = 0.0
        sum_b[:] = 0.0
        for p in range(len(pair_a)):
            gl = length[k] * pair_g[p]
            L[base + pair_a[p], pair_b[p] - pair_a[p]] -= gl
            sum_a[pair_a[p]] += gl
            sum_b[pair_b[p]] += gl
        for c in range(nc):
            L[base + c, 0] = (C[k, 0] + G_g[k, c] + G_a[k, c]) + (sum_a[c] + sum_b[c])
            rhs[base + c] = C[k, 0] * T[k, c] + G_g[k, c] * T_ground[k, c] + G_a[k, c] * T_air[k, c]
    for k in range(n - 1):
        ga = k_axial / (0.5 * (length[k] + length[k + 1]))
        for c in range(nc):
            L[nc * k + c, nc] -= ga
            L[nc * k + c, 0] += ga
    for k in range(n - 1):  # the downstream cells second, as numpy added them
        ga = k_axial / (0.5 * (length[k] + length[k + 1]))
        for c in range(nc):
            L[nc * (k + 1) + c, 0] += ga
    info = band_cholesky_rows(L)
    if info != 0:
        raise ValueError("heat step: the conductance matrix is not positive definite")
    band_cholesky_solve_rows(L, rhs)
    return rhs.reshape(n, nc)


@njit(cache=True)
def heat_exchange(T, centre, m1, m2, length, corner_gap, normal, plane_height, p_cell, p_area, p_axis, p_sign, p_off,
                  corner_cells, corner_off, T_uniform, gradient, air, ground, K1):
    """``SectionHeat.coefficients`` in one loop over edges and patches: the conductances [mW/K] of each
    cell with the ground G_g and the air G_a (n, n_cells) and the conductance-weighted ground and air
    temperatures [C] (n, n_cells). air = (film coefficient [mW/(mm^2 K)], ambient temperature [C],
    emissivity), ground = (air conductivity [mW/(mm K)], gap floor z0 [mm], plate emissivity,
    boundary layer d_bl [mm], contact conductance G_c [mW/(mm K)]) (``models.heat.SurfaceExchange``,
    ``models.ribbon.GroundHeatExchange``); the plate at T_uniform + gradient . x [C]. The formulas
    and their order of operations are those of the numpy reference, which stays:
    ``tests/solvers/test_der_ribbon.py`` compares both (the sums over a cell's patches are taken in
    patch order; numpy's matrix products add the same one or two nonzero terms)."""
    n, nc = T.shape
    film, ambient, emissivity = air
    k_air, gap_floor, plate_emissivity, boundary_layer, contact_conductance = ground
    sigma = STEFAN_BOLTZMANN  # [mW/(mm^2 K^4)]; numba freezes module globals at compilation
    kelvin = ZERO_CELSIUS_K
    tak_amb = ambient + kelvin
    G_g = np.zeros((n, nc))
    G_a = np.zeros((n, nc))
    Q_g = np.zeros((n, nc))
    Q_a = np.zeros((n, nc))
    for k in range(n):
        cz = (centre[k, 0] * normal[0] + centre[k, 1] * normal[1] + centre[k, 2] * normal[2]) - plane_height
        m1z = m1[k, 0] * normal[0] + m1[k, 1] * normal[1] + m1[k, 2] * normal[2]
        m2z = m2[k, 0] * normal[0] + m2[k, 1] * normal[1] + m2[k, 2] * normal[2]
        gc = centre[k, 0] * gradient[0] + centre[k, 1] * gradient[1] + centre[k, 2] * gradient[2]
        g1 = m1[k, 0] * gradient[0] + m1[k, 1] * gradient[1] + m1[k, 2] * gradient[2]
        g2 = m2[k, 0] * gradient[0] + m2[k, 1] * gradient[1] + m2[k, 2] * gradient[2]
        for p in range(len(p_cell)):
            c = p_cell[p]
            height = cz + p_off[p, 0] * m1z + p_off[p, 1] * m2z
            nrm_z = (m1z if p_axis[p] == 0 else m2z) * p_sign[p]
            facing = max(0.0, -nrm_z)
            area = p_area[p] * length[k]
            tg = T_uniform + (gc + p_off[p, 0] * g1 + p_off[p, 1] * g2)
            tk = T[k, c] + kelvin
            tgk = tg + kelvin
            above = max(height, 0.0)
            h_ground = facing * (k_air / (above + gap_floor)
                                 + plate_emissivity * sigma * (tk ** 2 + tgk ** 2) * (tk + tgk))
            h_amb = film + emissivity * sigma * (tk ** 2 + tak_amb ** 2) * (tk + tak_amb) * (1.0 - facing)
            t_air = ambient + (tg - ambient) * math.exp(-above / boundary_layer)
            G_g[k, c] += h_ground * area
            Q_g[k, c] += h_ground * area * tg
            G_a[k, c] += h_amb * area
            Q_a[k, c] += h_amb * area * t_air
        for j in range(len(corner_cells)):
            c = corner_cells[j]
            weight = 0.5 * (1.0 - math.tanh(0.5 * K1 * corner_gap[k, j]))
            g_contact = contact_conductance * length[k] * weight
            G_g[k, c] += g_contact
            Q_g[k, c] += g_contact * (T_uniform + gc + corner_off[j, 0] * g1 + corner_off[j, 1] * g2)
    for k in range(n):
        for c in range(nc):
            Q_a[k, c] /= max(G_a[k, c], 1e-300)
            Q_g[k, c] /= max(G_g[k, c], 1e-300)
    return G_g, G_a, Q_a, Q_g


@njit(cache=True)
def heat_step(T, dt, centre, m1, m2, length, corner_gap, T_uniform, gradient, model):
    """One implicit-Euler heat step in one call: :func:`heat_exchange`, :func:`heat_solve` and the
    fluxes. model = (capacity (n,) [mJ/K], plane normal (3,), plane height [mm], patch cells, areas
    per length [mm], frame axes, signs, offsets (n_patches, 2) [mm], corner cells, corner offsets
    (4, 2) [mm], air, ground, K1 [1/mm], pair_a, pair_b, pair_g [mW/(K mm)], k_axial [mW mm/K])
    (``SectionHeat._kernel_data``). Returns (T_new (n, n_cells) [C], power from the ground (n,)
    [mW], power to the air (n,) [mW])."""
    (capacity, normal, plane_height, p_cell, p_area, p_axis, p_sign, p_off, corner_cells, corner_off, air, ground,
     K1, pair_a, pair_b, pair_g, k_axial) = model
    G_g, G_a, T_air, T_ground = heat_exchange(T, centre, m1, m2, length, corner_gap, normal, plane_height, p_cell,
                                              p_area, p_axis, p_sign, p_off, corner_cells, corner_off, T_uniform,
                                              gradient, air, ground, K1)
    n, nc = T.shape
    C = np.empty((n, 1))
    for k in range(n):
        C[k, 0] = capacity[k] / dt
    T_new = heat_solve(C, G_g, G_a, T, T_ground, T_air, length, pair_a, pair_b, pair_g, k_axial)
    from_ground = np.zeros(n)
    to_air = np.zeros(n)
    for k in range(n):
        for c in range(nc):
            from_ground[k] += G_g[k, c] * (T_ground[k, c] - T_new[k, c])
            to_air[k] += G_a[k, c] * (T_new[k, c] - T_air[k, c])
    return T_new, from_ground, to_air
