"""Compiled (numba) element kernels of the bar-and-hinge assembly.

:func:`hinge_forces` is :func:`lcefem.models.bar_hinge.hinge_element` (gradient and Hessian of
L_h psi(theta), Liu & Paulino 2017, Eq. 12-15) with the dihedral angle's derivatives of
:func:`lcefem.models.bar_hinge.dihedral_angle` written element by element: the numpy version builds
some twenty (n, 3, 3) and (n, 12, 12) temporaries per call, and its Hessian was half of the
gridshell's assembly time. The models' functions stay the definition;
tests/solvers/test_bar_hinge_kernels.py checks the two agree to round-off.
"""

from __future__ import annotations

import numba
import numpy as np


@numba.njit(cache=True, inline="always")
def _skew(v, out):
    out[0, 0], out[0, 1], out[0, 2] = 0.0, -v[2], v[1]
    out[1, 0], out[1, 1], out[1, 2] = v[2], 0.0, -v[0]
    out[2, 0], out[2, 1], out[2, 2] = -v[1], v[0], 0.0


@numba.njit(cache=True, inline="always")
def _cross(a, b, out):
    out[0] = a[1] * b[2] - a[2] * b[1]
    out[1] = a[2] * b[0] - a[0] * b[2]
    out[2] = a[0] * b[1] - a[1] * b[0]


@numba.njit(cache=True, inline="always")
def _projector_times_skew(v, v2, scale, s, out):
    """out = scale (I - 2 v v^T/v2)/v2 @ s."""
    for r in range(3):
        for c in range(3):
            acc = 0.0
            for q in range(3):
                p = (1.0 if r == q else 0.0) - 2.0 * v[r] * v[q] / v2
                acc += p * s[q, c]
            out[r, c] = scale * acc / v2


@numba.njit(cache=True, inline="always")
def _dihedral_derivatives(xj, xk, xi, xl, h, w, s, g, hh, hessian=True):
    """g (12) = dtheta/dx and (``hessian``) hh (12, 12) = d2theta/dx2 (not yet symmetrised) of
    element h,
    nodes (j, k, i, l) (Liu & Paulino 2017, Eq. 12-15, and their exact Jacobian, as in
    :func:`lcefem.models.bar_hinge.dihedral_angle`). ``w`` (11, 3) and ``s`` (6, 3, 3) are scratch:
    rows of w are e, a, b, m, n, g_i, g_l, g_j, g_k, dA, dB; s holds [.]x, dg_i/da, dg_i/de,
    dg_l/de, dg_l/db and h_ee."""
    e, a, b, m, nn = w[0], w[1], w[2], w[3], w[4]
    gi, gl, gj, gk, dA, dB = w[5], w[6], w[7], w[8], w[9], w[10]
    sk, dgi_da, dgi_de, dgl_de, dgl_db, h_ee = s[0], s[1], s[2], s[3], s[4], s[5]
    for c in range(3):
        e[c] = xk[h, c] - xj[h, c]
        a[c] = xi[h, c] - xj[h, c]
        b[c] = xk[h, c] - xl[h, c]
    _cross(a, e, m)
    _cross(e, b, nn)
    e2 = e[0] * e[0] + e[1] * e[1] + e[2] * e[2]
    le = np.sqrt(e2)
    m2 = m[0] * m[0] + m[1] * m[1] + m[2] * m[2]
    n2 = nn[0] * nn[0] + nn[1] * nn[1] + nn[2] * nn[2]
    A = (a[0] * e[0] + a[1] * e[1] + a[2] * e[2]) / e2
    B = (b[0] * e[0] + b[1] * e[1] + b[2] * e[2]) / e2
    for c in range(3):
        gi[c] = le / m2 * m[c]
        gl[c] = -(le / n2) * nn[c]
    for c in range(3):
        gj[c] = (A - 1.0) * gi[c] - B * gl[c]
        gk[c] = (B - 1.0) * gl[c] - A * gi[c]
        g[c], g[3 + c], g[6 + c], g[9 + c] = gj[c], gk[c], gi[c], gl[c]
        dA[c] = (a[c] - 2.0 * A * e[c]) / e2
        dB[c] = (b[c] - 2.0 * B * e[c]) / e2
    if not hessian:
        return
    # g_i = |e| m/|m|^2, m = a x e: dm = -[e]x da + [a]x de; g_l = -|e| n/|n|^2, n = e x b.
    _skew(e, sk)
    _projector_times_skew(m, m2, -le, sk, dgi_da)
    _projector_times_skew(nn, n2, -le, sk, dgl_db)
    _skew(a, sk)
    _projector_times_skew(m, m2, le, sk, dgi_de)
    _skew(b, sk)
    _projector_times_skew(nn, n2, le, sk, dgl_de)
    for r in range(3):
        for c in range(3):
            dgi_de[r, c] += m[r] * e[c] / (m2 * le)
            dgl_de[r, c] += -nn[r] * e[c] / (n2 * le)
    for r in range(3):
        for c in range(3):
            h_ee[r, c] = gl[r] * dB[c] + B * dgl_de[r, c] - gi[r] * dA[c] - A * dgi_de[r, c]
    # h_aa = dgi_da, h_ae = dgi_de, h_bb = -dgl_db, h_be = -dgl_de, h_ea = h_ae^T, h_eb =
    # h_be^T; node rows (j, k, i, l) of d(a, e, b)/d(nodes) contracted as in dihedral_angle.
    for r in range(3):
        for c in range(3):
            haa, hae, hea = dgi_da[r, c], dgi_de[r, c], dgi_de[c, r]
            hbb, hbe, heb = -dgl_db[r, c], -dgl_de[r, c], -dgl_de[c, r]
            hee = h_ee[r, c]
            # row j: ra = -h_aa - h_ea, re = -h_ae - h_ee, rb = -h_eb
            ra, re, rb = -haa - hea, -hae - hee, -heb
            hh[r, c], hh[r, 3 + c], hh[r, 6 + c], hh[r, 9 + c] = -(ra + re), re + rb, ra, -rb
            # row k: ra = h_ea, re = h_ee + h_be, rb = h_eb + h_bb
            ra, re, rb = hea, hee + hbe, heb + hbb
            hh[3 + r, c], hh[3 + r, 3 + c], hh[3 + r, 6 + c], hh[3 + r, 9 + c] = (
                -(ra + re),
                re + rb,
                ra,
                -rb,
            )
            # row i: ra = h_aa, re = h_ae
            ra, re = haa, hae
            hh[6 + r, c], hh[6 + r, 3 + c], hh[6 + r, 6 + c], hh[6 + r, 9 + c] = (
                -(ra + re),
                re,
                ra,
                0.0,
            )
            # row l: re = -h_be, rb = -h_bb
            re, rb = -hbe, -hbb
            hh[9 + r, c], hh[9 + r, 3 + c], hh[9 + r, 6 + c], hh[9 + r, 9 + c] = (
                -re,
                re + rb,
                0.0,
                -rb,
            )


@numba.njit(cache=True)
def hinge_forces(xj, xk, xi, xl, force_coef, stiffness_coef, grad, hess, hessian=True):
    """Fill grad (n, 12) = c1 dtheta/dx and hess (n, 12, 12) = c2 dtheta dtheta^T + c1 d2theta/dx2,
    nodes ordered (j, k, i, l), with c1 = ``force_coef`` = L_h M(theta) [N mm/rad] and
    c2 = ``stiffness_coef`` = L_h dM/dtheta [N mm/rad^2] per hinge; ``hessian`` False: the
    gradient only (``hess`` untouched)."""
    n = xj.shape[0]
    w, s = np.empty((11, 3)), np.empty((6, 3, 3))
    g = np.empty(12)
    hh = np.empty((12, 12))
    for h in range(n):
        _dihedral_derivatives(xj, xk, xi, xl, h, w, s, g, hh, hessian)
        c1, c2 = force_coef[h], stiffness_coef[h]
        for r in range(12):
            grad[h, r] = c1 * g[r]
        if not hessian:
            continue
        for r in range(12):
            for c in range(r, 12):
                v = c2 * (g[r] * g[c]) + c1 * (0.5 * (hh[r, c] + hh[c, r]))
                hess[h, r, c] = v
                hess[h, c, r] = v


#: Spoke m of an N5B8 panel is the hinge (c, m; m - 1, m + 1): the slots of its (j, k, i, l) in
#: (c, 0, 1, 2, 3) (lcefem.models.bar_hinge.SPOKE_SLOTS, as an array for the compiled loop).
SPOKE_SLOT_TABLE = np.array([[0, 1 + m, 1 + (m - 1) % 4, 1 + (m + 1) % 4] for m in range(4)])


@numba.njit(cache=True)
def _hinge_angles(xs, slots, p, w, s, g, hh, ge, hessian):
    """Element p's hinges m (nodes ``xs[slots[m]]``, (j, k, i, l)): the gradient of each dihedral
    angle over the element's DOFs in ``ge[m]`` and, with ``hessian``, its (12, 12) Hessian over the
    hinge's own four nodes in ``hh[m]`` (:func:`_dihedral_derivatives`; ``w``, ``s``, ``g`` its
    work arrays)."""
    ge[:] = 0.0
    for m in range(slots.shape[0]):
        _dihedral_derivatives(
            xs[slots[m, 0]],
            xs[slots[m, 1]],
            xs[slots[m, 2]],
            xs[slots[m, 3]],
            p,
            w,
            s,
            g,
            hh[m],
            hessian,
        )
        for q in range(4):
            for c in range(3):
                ge[m, 3 * slots[m, q] + c] += g[3 * q + c]


@numba.njit(cache=True)
def _add_hinge_hessians(hess, p, slots, hh, weights):
    """hess[p] += sum_m weights[m] sym(hh[m]), each hinge's angle Hessian scattered from its four
    nodes to the element's slots (the moment term M_m d2theta_m/dx2 of a bending element)."""
    for m in range(slots.shape[0]):
        weight = weights[m]
        for a in range(4):
            for b in range(4):
                for r in range(3):
                    for c in range(3):
                        ra, cb = 3 * a + r, 3 * b + c
                        hess[p, 3 * slots[m, a] + r, 3 * slots[m, b] + c] += weight * (
                            0.5 * (hh[m, ra, cb] + hh[m, cb, ra])
                        )


@numba.njit(cache=True)
def panel_bending_forces(xs, lengths, coef, moment, slots, grad, hess, hessian=True):
    """Gradient (n, 15) and Hessian (n, 15, 15) of the panel bending element U = k_p S^2/(2 sum L)
    with S = sum_m L_m d_m (:func:`lcefem.models.bar_hinge.panel_bending_element`): with
    G = sum_m L_m dtheta_m/dx, grad = c S G and hess = c G G^T + sum_m c S L_m d2theta_m/dx2,
    ``coef`` c = k_p/sum L [N mm/rad^2 per mm], ``moment`` c S [N/rad]; ``xs`` (5, n, 3) the
    centre and corners, ``slots`` the spokes' node slots (SPOKE_SLOT_TABLE); ``hessian`` False: the
    gradient only (``hess`` untouched)."""
    n = xs.shape[1]
    w, s = np.empty((11, 3)), np.empty((6, 3, 3))
    g = np.empty(12)
    hh = np.empty((4, 12, 12))
    ge = np.empty((4, 15))
    gg = np.empty(15)
    weights = np.empty(4)
    for p in range(n):
        _hinge_angles(xs, slots, p, w, s, g, hh, ge, hessian)
        gg[:] = 0.0
        for m in range(4):
            for r in range(15):
                gg[r] += lengths[p, m] * ge[m, r]
        for r in range(15):
            grad[p, r] = moment[p] * gg[r]
        if not hessian:
            continue
        for r in range(15):
            for c in range(15):
                hess[p, r, c] = coef[p] * (gg[r] * gg[c])
        for m in range(4):
            weights[m] = moment[p] * lengths[p, m]
        _add_hinge_hessians(hess, p, slots, hh, weights)


#: The strip beam's two end hinges: slots of (j, k, i, l) in (a, a2, pa, b, b2, pb).
BEAM_SLOT_TABLE = np.array([[0, 1, 2, 3], [3, 4, 5, 0]])


@numba.njit(cache=True)
def strip_beam_forces(xs, stiffness, moment_a, moment_b, slots, grad, hess, hessian=True):
    """Gradient (n, 18) and Hessian (n, 18, 18) of the strip beam element
    U = c (d_a^2 + d_a d_b + d_b^2) (:func:`lcefem.models.bar_hinge.strip_beam_element`): with
    g_a, g_b the end angles' gradients, grad = M_a g_a + M_b g_b and hess = c (2 g_a g_a^T +
    g_a g_b^T + g_b g_a^T + 2 g_b g_b^T) + M_a H_a + M_b H_b, ``stiffness`` c = 2EI/L [N mm],
    ``moment_a/b`` M_a = c (2 d_a + d_b), M_b = c (d_a + 2 d_b) [N mm]; ``xs`` (6, n, 3);
    ``hessian`` False: the gradient only (``hess`` untouched)."""
    n = xs.shape[1]
    w, s = np.empty((11, 3)), np.empty((6, 3, 3))
    g = np.empty(12)
    hh = np.empty((2, 12, 12))
    ge = np.empty((2, 18))
    weights = np.empty(2)
    for p in range(n):
        _hinge_angles(xs, slots, p, w, s, g, hh, ge, hessian)
        c0 = stiffness[p]
        for r in range(18):
            grad[p, r] = moment_a[p] * ge[0, r] + moment_b[p] * ge[1, r]
        if not hessian:
            continue
        for r in range(18):
            ga, gb = ge[0, r], ge[1, r]
            for c in range(18):
                hess[p, r, c] = c0 * (
                    2.0 * ga * ge[0, c] + ga * ge[1, c] + gb * ge[0, c] + 2.0 * gb * ge[1, c]
                )
        weights[0], weights[1] = moment_a[p], moment_b[p]
        _add_hinge_hessians(hess, p, slots, hh, weights)


@numba.njit(cache=True)
def scatter_merged(
    values,
    before_source,
    before_target,
    extra_source,
    extra_target,
    after_source,
    after_target,
    moved,
    size,
):
    """The reduced Hessian's data (length ``size``, from zero) in ascending COO order: the base
    entries before the contact block (out[moved[before_target[k]]] += values[before_source[k]]),
    the closed contacts' (out[extra_target[k]] += ...), then the base entries after it: per entry
    the summation order of np.bincount over all COO entries, an open contact's zeros left out."""
    out = np.zeros(size)
    for k in range(before_source.size):
        out[moved[before_target[k]]] += values[before_source[k]]
    for k in range(extra_source.size):
        out[extra_target[k]] += values[extra_source[k]]
    for k in range(after_source.size):
        out[moved[after_target[k]]] += values[after_source[k]]
    return out
