"""Compiled (numba) contact of the DER ribbon: the sample points between sections
(``models.rod.StencilPoints``), the smooth unilateral contact and friction potential against the
ground plane and boxes (:func:`contact`, :func:`box_gap`, :func:`normal_force`), and the smallest
corner gap per edge (:func:`edge_min_gaps`). The numpy reference is in :mod:`lcefem.models.rod` and
:mod:`lcefem.solvers.der.assembly` (``tests/solvers/test_der_kernels.py`` compares them).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from lcefem.solvers.der.kernel_ops import cross3, dot3, scatter, source_change_into
from lcefem.solvers.der.kernels import element_scratch, stencil_point_element


# ----------------------------------------------------------------------------------------------
# All sample points of the contact sampling, and the whole contact + friction potential
# ----------------------------------------------------------------------------------------------
@njit(cache=True, error_model="numpy")
def sample_points(
    x, a1, t, theta, twist, m1, m2, side, sigma, offsets, end_ids, end_sigma, end_offsets
):
    """Positions and frame offsets r = a m1 + b m2 [mm] of every contact sample point.

    Stencil points (``models.rod.stencil_points``; frame angle interpolated with the node's twist):
    (N-2, p_s, 3) each, empty when ``side`` is empty. End-edge points
    (``models.rod.section_points``, the edge's own frame): (len(end_ids), p_e, 3) each; end_sigma is
    (len(end_ids), p_e).
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
            # the section points of one sample section (e.g. its four corners) share the frame
            # angle: its cos, sin and a2 once per section (the same values; 4x fewer sin/cos, issue
            # 17)
            if edge != last_edge or sigma[j] != last_sigma:
                last_edge, last_sigma = edge, sigma[j]
                th = theta[edge] + (sigma[j] - 0.5) * twist[k]
                c = math.cos(th)
                s_ = math.sin(th)
                cross3(t[edge], a1[edge], a2)
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


@njit(cache=True, error_model="numpy")
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


@njit(cache=True, error_model="numpy")
def normal_force(gap, clearance, delta, K1, stiffness):
    """``models.contact.normal_force`` of an array of gaps (any shape) [N]."""
    out = np.empty(gap.size)
    flat = gap.ravel()
    for i in range(gap.size):
        out[i] = -stiffness * _contact_energy(flat[i], clearance, delta, K1)[1]
    return out.reshape(gap.shape)


@njit(cache=True, error_model="numpy")
def _friction(u, normal, fn, h, mu, K2, grad, hess, with_hessian, w):
    """``models.contact.friction_potential`` of one point: energy; dD/du into grad (3,), d2D/du2
    into hess (3, 3); w (3,) scratch."""
    un = dot3(u, normal)
    for i in range(3):
        w[i] = u[i] - un * normal[i]
    v = math.sqrt(dot3(w, w)) / h
    a = 0.5 * K2
    z = a * v
    if z < 1e-3:
        logcosh = 0.5 * z * z - z**4 / 12.0
        phi = a * (1.0 - z * z / 3.0)
        psi = -2.0 * a**3 / 3.0 + 8.0 * a**5 * v * v / 15.0
    else:
        logcosh = z + math.log1p(math.exp(-2.0 * z)) - math.log(2.0)
        th = math.tanh(z)
        phi = th / v
        psi = (a * (1.0 - th * th) * v - th) / v**3
    coef = mu * fn
    for i in range(3):
        grad[i] = coef * phi / h * w[i]
    if with_hessian:
        for i in range(3):
            for j in range(3):
                proj = (1.0 if i == j else 0.0) - normal[i] * normal[j]
                hess[i, j] = coef / h * (phi * proj + psi / (h * h) * w[i] * w[j])
    return coef * h * logcosh / a


@njit(cache=True, error_model="numpy")
def _section_point_element(t, length, r, sig, g, jac, h7, tr):
    """``models.rod.section_point_derivatives`` of one point (edge's own frame): jac (3, 7) and the
    Hessian h7 (7, 7) of g . point, dofs (x0, theta, x1); tr (3,) scratch."""
    cross3(t, r, tr)
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
    gt = dot3(g, t)
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
    h7[3, 3] = -dot3(g, r)


@njit(cache=True, error_model="numpy")
def contact(
    pos_s,
    r_s,
    pos_e,
    r_e,
    x,
    t,
    length,
    side,
    sigma,
    end_ids,
    end_sigma,
    normal,
    height,
    clearance,
    delta,
    K1,
    stiffness,
    with_friction,
    lag_ns,
    lag_ps,
    lag_ne,
    lag_pe,
    mu,
    K2,
    h,
    db,
    ddb,
    with_source,
    order,
    grad,
    band,
    box,
    is_box,
):
    """Contact potential k E(gap) of all sample points with the plane {n.p = height} (or, with
    ``is_box``, with the rounded box ``box`` = (lo, hi, radius, friction) of ``model.Box``: gap,
    normal and the gap's Hessian per point, :func:`box_gap`) plus (with friction) the friction
    potential of the points with a lagged normal force (on a box, tangential to the box's normal at
    the lagged point); ``order`` 0 energy, 1 with gradient, 2 with Hessian (added into grad and
    band). Returns the energy [mJ].

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
    ws = element_scratch()
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
                    gap = dot3(p, normal) - height
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
                    stencil_point_element(
                        e,
                        f,
                        rr[row, j],
                        t[edge],
                        side[j],
                        sigma[j],
                        g_pt,
                        jac,
                        h11,
                        hv,
                        jv,
                        tmp8,
                        with_hessian,
                        ws,
                    )
                    _chain_point(jac, h11, g_pt, cc, nrm, hD, g11, with_hessian)
                    _accumulate(g11, h11, acc_g, acc_h, with_hessian)
                else:
                    edge = end_ids[row]
                    _section_point_element(
                        t[edge], length[edge], rr[row, j], end_sigma[row, j], g_pt, jac7, h7, w3
                    )
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
                    source_change_into(
                        acc_g,
                        acc_h,
                        slot_a,
                        slot_t,
                        slot_b,
                        dbs,
                        ddbs,
                        W,
                        tmp11,
                        out11,
                        with_hessian,
                    )
                scatter(4 * k, acc_g, acc_h, grad, band, with_hessian)
            else:
                edge = end_ids[row]
                if with_source:
                    db1[0] = db[edge]
                    ddb1[0] = ddb[edge]
                    source_change_into(
                        acc_g, acc_h, e_a, e_t, e_b, db1, ddb1, W7, tmp7, out7, with_hessian
                    )
                scatter(4 * edge, acc_g, acc_h, grad, band, with_hessian)
    return energy


@njit(cache=True, error_model="numpy")
def box_gap(p, box, n, hg):
    """Gap [mm] of the point p to the rounded box ``box`` = (lo (3), hi (3), radius) of
    ``model.Box``; the outward unit normal (the gap's gradient) into n (3,) and the gap's Hessian
    into hg (3, 3). Beyond the inner box [lo + r, hi - r]: gap = D - r with D the distance to it,
    Hessian (P - n n^T)/D, P the axes along which p lies beyond it. Inside the inner box (a
    penetration deeper than the edge radius): minus the depth below the nearest face, minus r, with
    that face's normal and no curvature."""
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


@njit(cache=True, error_model="numpy")
def _accumulate(g_loc, h_loc, acc_g, acc_h, with_hessian):
    for i in range(g_loc.shape[0]):
        acc_g[i] += g_loc[i]
    if with_hessian:
        for i in range(g_loc.shape[0]):
            for j in range(g_loc.shape[0]):
                acc_h[i, j] += h_loc[i, j]


@njit(cache=True, error_model="numpy")
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
                s += jac[a, i] * (
                    hD[a, 0] * jac[0, j] + hD[a, 1] * jac[1, j] + hD[a, 2] * jac[2, j]
                )
            hloc[i, j] += s


@njit(cache=True, error_model="numpy")
def edge_min_gaps(
    pos_s, pos_e, side, slot_s, end_ids, slot_e, n_edges, k, normal, height, interpolated
):
    """``assembly.edge_corner_gaps``: the smallest gap [mm] (position . normal - height) of each of
    the k section point kinds over the sample points of each edge, (n_edges, k), +inf where an edge
    has none. pos_s (N-2, p_s, 3) the stencil points (point j on edge s + side[j], kind slot_s[j];
    used when ``interpolated``), pos_e (n_end, p_e, 3) those of the edges end_ids (kind
    slot_e[j])."""
    out = np.full((n_edges, k), np.inf)
    for r in range(len(end_ids)):
        edge = end_ids[r]
        for j in range(pos_e.shape[1]):
            g = (
                pos_e[r, j, 0] * normal[0]
                + pos_e[r, j, 1] * normal[1]
                + pos_e[r, j, 2] * normal[2]
                - height
            )
            if g < out[edge, slot_e[j]]:
                out[edge, slot_e[j]] = g
    if interpolated:
        for s in range(pos_s.shape[0]):
            for j in range(pos_s.shape[1]):
                g = (
                    pos_s[s, j, 0] * normal[0]
                    + pos_s[s, j, 1] * normal[1]
                    + pos_s[s, j, 2] * normal[2]
                    - height
                )
                edge = s + side[j]
                if g < out[edge, slot_s[j]]:
                    out[edge, slot_s[j]] = g
    return out
