"""Compiled (numba) element loops of the DER assembly: the same formulas as the vectorised numpy
functions of :mod:`lcefem.models.rod` (``stretching``, ``bend_twist``, ``twist_hessian_ef``,
``apply_source_change``, ``stencil_point_derivatives``), fused with the scatter into the gradient
and the lower banded Hessian (LAPACK storage ab[i - j, j] = H[i, j], half-bandwidth 10).

Why: at the ribbon's sizes (30-200 nodes) the numpy versions spend most of their time in the
Python/numpy overhead of ~100 calls on small arrays per evaluation (issue 17: ~5 ms of fixed cost
per step). The numpy versions stay the reference: ``tests/solvers/test_der_kernels.py`` checks that
both give the same energies, gradients and Hessians to round-off.

The other compiled loops live beside it: the dense helpers in :mod:`lcefem.solvers.der.kernel_ops`,
contact and friction in :mod:`lcefem.solvers.der.contact_kernels`, frame transport in
:mod:`lcefem.solvers.der.frame_kernels`, the banded Cholesky in :mod:`lcefem.solvers.der.banded` and
the section heat step in :mod:`lcefem.solvers.der.heat_kernels`.

Element layouts are those of :mod:`lcefem.solvers.der.assembly`: an edge k touches the 7 dofs
q[4k : 4k + 7] = (x_k, theta_k, x_(k+1)); the stencil of interior node k + 1 touches the 11 dofs
q[4k : 4k + 11] = (x_k, theta_k, x_(k+1), theta_(k+1), x_(k+2)).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from lcefem.solvers.der.kernel_ops import (
    MAP_IDX,
    MAP_SGN,
    cross3,
    dot3,
    matmul,
    rows_to_stencil,
    scatter,
    skew_into,
    source_change_into,
    to_stencil,
)


# ----------------------------------------------------------------------------------------------
# Holonomy derivatives of the transport source (models.rod.source_change)
# ----------------------------------------------------------------------------------------------
@njit(cache=True, error_model="numpy")
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
        c = 1.0 + dot3(s, tk)
        cross3(tk, s, g)
        for i in range(3):
            g[i] /= c
        inv_l = 1.0 / length[k]
        for i in range(3):
            db[k, i] = g[i] * inv_l
        for i in range(3):
            for j in range(3):
                # sym(outer(-g c, t + s)) / (2 c^2)
                hb[i, j] = (-(g[i] * c) * (tk[j] + s[j]) - (g[j] * c) * (tk[i] + s[i])) / (
                    2.0 * c * c
                )
                P[i, j] = (1.0 if i == j else 0.0) - tk[i] * tk[j]
        matmul(P, hb, tmp)
        matmul(tmp, P, hb)
        inv_l2 = inv_l * inv_l
        for i in range(3):
            for j in range(3):
                ddb[k, i, j] = hb[i, j] * inv_l2 - (g[i] * tk[j] + tk[i] * g[j]) * inv_l2
    return db, ddb


# ----------------------------------------------------------------------------------------------
# Elastic energy: stretching of edges, bending and twisting of interior nodes
# ----------------------------------------------------------------------------------------------
@njit(cache=True, error_model="numpy")
def _twist_hessian_ef(te, tf, le, lf, kb, out, w33):
    """out (6, 6) = ``models.rod.twist_hessian_ef`` of one stencil; w33 (6, 3, 3) scratch."""
    chi = 1.0 + dot3(te, tf)
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
    skew_into(te, tt_off, 0, 0, -1.0 / chi)
    t1 = w33[4]
    t2 = w33[5]
    matmul(pe, tt_diag, t1)
    matmul(t1, pe, t2)
    for i in range(3):
        for j in range(3):
            out[i, j] = -(t2[i, j] + (kb[i] * te[j] + te[i] * kb[j]) / (2.0 * le * le))
    matmul(pf, tt_diag, t1)
    matmul(t1, pf, t2)
    for i in range(3):
        for j in range(3):
            out[3 + i, 3 + j] = -(t2[i, j] + (kb[i] * tf[j] + tf[i] * kb[j]) / (2.0 * lf * lf))
    matmul(pe, tt_off, t1)
    matmul(t1, pf, t2)
    for i in range(3):
        for j in range(3):
            out[i, 3 + j] = -t2[i, j]
            out[3 + j, i] = -t2[i, j]


@njit(cache=True, error_model="numpy")
def element_scratch():
    """Scratch arrays of the element functions (:func:`_bend_twist_element`,
    :func:`stencil_point_element`), allocated once per kernel call: (v3 (12, 3), v6 (5, 6), v8 (4,
    8), m36 (2, 3, 6), m66 (4, 6, 6), w33 (6, 3, 3))."""
    return (
        np.zeros((12, 3)),
        np.zeros((5, 6)),
        np.zeros((4, 8)),
        np.zeros((2, 3, 6)),
        np.zeros((4, 6, 6)),
        np.zeros((6, 3, 3)),
    )


@njit(cache=True, error_model="numpy")
def _bend_twist_element(
    e,
    f,
    m1e,
    m2e,
    m1f,
    m2f,
    twist,
    kbar1,
    kbar2,
    tbar,
    inv_l,
    EI1,
    EI2,
    GJ,
    grad,
    hess,
    with_hessian,
    ws,
):
    """``models.rod.bend_twist`` of one interior node: energy; gradient (8,) and Hessian (8, 8) in
    (e, f, theta_e, theta_f) written into grad, hess; ``ws`` the scratch of :func:`element_scratch`
    (no allocation per element: at ~100 nodes the allocations cost as much as the arithmetic)."""
    v3, v6, v8, m36, m66, w33 = ws
    te, tf, nv, kb, M1, M2, w, ue, uf, me, mf = (
        v3[0],
        v3[1],
        v3[2],
        v3[3],
        v3[4],
        v3[5],
        v3[6],
        v3[7],
        v3[8],
        v3[9],
        v3[10],
    )
    dD, dnw, jte, jtf = v6[0], v6[1], v6[2], v6[3]
    g1, g2, gt = v8[0], v8[1], v8[2]
    dn, jac = m36[0], m36[1]
    h6, ddD, blk, th = m66[0], m66[1], m66[2], m66[3]
    le = math.sqrt(dot3(e, e))
    lf = math.sqrt(dot3(f, f))
    for i in range(3):
        te[i] = e[i] / le
        tf[i] = f[i] / lf
    cross3(e, f, nv)
    D = le * lf + dot3(e, f)
    for i in range(3):
        kb[i] = 2.0 * nv[i] / D
    dn[:, :] = 0.0
    skew_into(f, dn, 0, 0, -1.0)
    skew_into(e, dn, 0, 3, 1.0)
    for i in range(3):
        dD[i] = lf * te[i] + f[i]
        dD[3 + i] = le * tf[i] + e[i]
    for c in range(3):
        for i in range(6):
            jac[c, i] = 2.0 * (dn[c, i] / D - nv[c] * dD[i] / (D * D))
    for i in range(3):
        M1[i] = m1e[i] + m1f[i]
        M2[i] = m2e[i] + m2f[i]
    k1 = 0.5 * dot3(kb, M2)
    k2 = -0.5 * dot3(kb, M1)
    for i in range(6):
        s1 = 0.0
        s2 = 0.0
        for c in range(3):
            s1 += M2[c] * jac[c, i]
            s2 += M1[c] * jac[c, i]
        g1[i] = 0.5 * s1
        g2[i] = -0.5 * s2
    g1[6] = -0.5 * dot3(kb, m1e)
    g1[7] = -0.5 * dot3(kb, m1f)
    g2[6] = -0.5 * dot3(kb, m2e)
    g2[7] = -0.5 * dot3(kb, m2f)
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
    wn = dot3(w, nv)
    dnw[:] = 0.0
    for i in range(6):
        for c in range(3):
            dnw[i] += w[c] * dn[c, i]
    h6[:, :] = 0.0
    skew_into(w, h6, 0, 3, -1.0)
    skew_into(w, h6, 3, 0, 1.0)
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
    hess[6, 6] += -dot3(kb, me)
    hess[7, 7] += -dot3(kb, mf)
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


@njit(cache=True, error_model="numpy")
def elastic(
    x,
    m1,
    m2,
    twist,
    rest_length,
    kappa_bar,
    twist_bar,
    voronoi,
    EA,
    EI1,
    EI2,
    GJ,
    db,
    ddb,
    with_source,
    with_hessian,
    grad,
    band,
):
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
    ws = element_scratch()
    for k in range(n_edges):
        for i in range(3):
            e[i] = x[k + 1, i] - x[k, i]
        length = math.sqrt(dot3(e, e))
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
        scatter(4 * k, g7, h7, grad, band, with_hessian)
    # Bending and twisting (stencil of interior node k + 1, dofs 4k .. 4k + 10).
    g8 = np.empty(8)
    h8 = np.empty((8, 8))
    g11 = np.empty(11)
    h11 = np.empty((11, 11))
    W = np.empty((2, 12))  # rows of D: values and columns (source_change_into)
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
        energy += _bend_twist_element(
            e,
            f,
            m1[k],
            m2[k],
            m1[k + 1],
            m2[k + 1],
            twist[k],
            kappa_bar[k, 0],
            kappa_bar[k, 1],
            twist_bar[k],
            1.0 / voronoi[k],
            EI1,
            EI2,
            GJ,
            g8,
            h8,
            with_hessian,
            ws,
        )
        g11[:] = 0.0
        for i in range(8):
            for p in range(2):
                g11[MAP_IDX[i, p]] += MAP_SGN[i, p] * g8[i]
        if with_hessian:
            to_stencil(h8, h11)
        if with_source:
            dbs[0] = db[k]
            dbs[1] = db[k + 1]
            ddbs[0] = ddb[k]
            ddbs[1] = ddb[k + 1]
            source_change_into(
                g11, h11, slot_a, slot_t, slot_b, dbs, ddbs, W, tmp11, out11, with_hessian
            )
        scatter(4 * k, g11, h11, grad, band, with_hessian)
    return energy


# ----------------------------------------------------------------------------------------------
# Contact and friction of the sample points between sections (models.rod.StencilPoints)
# ----------------------------------------------------------------------------------------------
@njit(cache=True, error_model="numpy")
def stencil_point_element(e, f, r, t, side, sigma, g, jac, h11, hv, jv, tmp, with_hessian, ws):
    """``models.rod.stencil_point_derivatives`` of one point: jac (3, 11) and (with_hessian) the
    Hessian h11 (11, 11) of g . point, frames transported from the current state; ``ws`` the
    scratch of :func:`element_scratch`."""
    v3, v6, v8, m36, m66, w33 = ws
    te, tf, kb, tr, pg = v3[0], v3[1], v3[2], v3[3], v3[4]
    dth, cross_v = v8[0], v8[1]
    th = m66[0]
    le = math.sqrt(dot3(e, e))
    lf = math.sqrt(dot3(f, f))
    for i in range(3):
        te[i] = e[i] / le
        tf[i] = f[i] / lf
    cross3(e, f, kb)
    D = le * lf + dot3(e, f)
    for i in range(3):
        kb[i] = 2.0 * kb[i] / D
    cm = sigma - 0.5
    for i in range(3):
        dth[i] = cm / (2.0 * le) * kb[i]
        dth[3 + i] = cm / (2.0 * lf) * kb[i]
    dth[6] = -cm if side else 1.0 - cm
    dth[7] = 1.0 + cm if side else cm
    length = lf if side else le
    cross3(t, r, tr)
    off = 3 if side else 0
    for i in range(3):
        for j in range(8):
            jv[i, j] = tr[i] * dth[j]
        for j in range(3):
            jv[i, off + j] += -t[i] * r[j] / length
    rows_to_stencil(jv, jac)
    w0 = 0.0 if side else 1.0 - sigma
    w1 = 1.0 - sigma if side else sigma
    w2 = sigma if side else 0.0
    for i in range(3):
        jac[i, i] += w0
        jac[i, 4 + i] += w1
        jac[i, 8 + i] += w2
    if not with_hessian:
        return
    gt = dot3(g, t)
    for i in range(3):
        pg[i] = g[i] - gt * t[i]
    inv_l2 = 1.0 / (length * length)
    hv[:, :] = 0.0
    for i in range(3):
        for j in range(3):
            hv[off + i, off + j] = (
                gt * (r[i] * t[j] + t[i] * r[j]) - 0.5 * (r[i] * pg[j] + pg[i] * r[j])
            ) * inv_l2
    cross_v[:] = 0.0
    for i in range(3):
        cross_v[off + i] = -(gt / length) * tr[i]
    gr = dot3(g, r)
    for i in range(8):
        for j in range(8):
            hv[i, j] += cross_v[i] * dth[j] + dth[i] * cross_v[j] - gr * dth[i] * dth[j]
    _twist_hessian_ef(te, tf, le, lf, kb, th, w33)
    c = dot3(g, tr) * cm
    for i in range(6):
        for j in range(6):
            hv[i, j] += c * th[i, j]
    to_stencil(hv, h11)
