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


@numba.njit(cache=True)
def hinge_forces(xj, xk, xi, xl, force_coef, stiffness_coef, grad, hess):
    """Fill grad (n, 12) = c1 dtheta/dx and hess (n, 12, 12) = c2 dtheta dtheta^T + c1 d2theta/dx2,
    nodes ordered (j, k, i, l), with c1 = ``force_coef`` = L_h M(theta) [N mm/rad] and
    c2 = ``stiffness_coef`` = L_h dM/dtheta [N mm/rad^2] per hinge."""
    n = xj.shape[0]
    e, a, b = np.empty(3), np.empty(3), np.empty(3)
    m, nn = np.empty(3), np.empty(3)
    gi, gl, gj, gk = np.empty(3), np.empty(3), np.empty(3), np.empty(3)
    dA, dB = np.empty(3), np.empty(3)
    s = np.empty((3, 3))
    dgi_da, dgi_de = np.empty((3, 3)), np.empty((3, 3))
    dgl_de, dgl_db = np.empty((3, 3)), np.empty((3, 3))
    h_ee = np.empty((3, 3))
    g = np.empty(12)
    hh = np.empty((12, 12))
    for h in range(n):
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
        # g_i = |e| m/|m|^2, m = a x e: dm = -[e]x da + [a]x de; g_l = -|e| n/|n|^2, n = e x b.
        _skew(e, s)
        _projector_times_skew(m, m2, -le, s, dgi_da)
        _projector_times_skew(nn, n2, -le, s, dgl_db)
        _skew(a, s)
        _projector_times_skew(m, m2, le, s, dgi_de)
        _skew(b, s)
        _projector_times_skew(nn, n2, le, s, dgl_de)
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
        c1, c2 = force_coef[h], stiffness_coef[h]
        for r in range(12):
            grad[h, r] = c1 * g[r]
            for c in range(r, 12):
                v = c2 * (g[r] * g[c]) + c1 * (0.5 * (hh[r, c] + hh[c, r]))
                hess[h, r, c] = v
                hess[h, c, r] = v


@numba.njit(cache=True)
def scatter_add(values, source, target, size):
    """out[target[k]] += values[source[k]] for k in order (out of length ``size``, from zero): the
    summation order of np.bincount, so the same floating-point sums."""
    out = np.zeros(size)
    for k in range(source.size):
        out[target[k]] += values[source[k]]
    return out
