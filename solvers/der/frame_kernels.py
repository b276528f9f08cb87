"""Compiled (numba) time-parallel transport of the DER reference frames and the moved geometry
(:mod:`lcefem.solvers.der.frames` is the numpy reference).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from lcefem.solvers.der.kernel_ops import cross3, dot3


# ----------------------------------------------------------------------------------------------
# Time-parallel transport of the reference frames (solvers.der.frames)
# ----------------------------------------------------------------------------------------------
@njit(cache=True, error_model="numpy")
def _parallel_transport(u, t_from, t_to, out, w3):
    """``models.rod.parallel_transport`` of one vector; w3 (3, 3) scratch."""
    v, vu, vvu = w3[0], w3[1], w3[2]
    cross3(t_from, t_to, v)
    c = dot3(t_from, t_to)
    cross3(v, u, vu)
    cross3(v, vu, vvu)
    for i in range(3):
        out[i] = u[i] + vu[i] + vvu[i] / (1.0 + c)


@njit(cache=True, error_model="numpy")
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
        pt = dot3(p, t_new[k])
        for i in range(3):
            p[i] -= pt * t_new[k, i]
        norm = math.sqrt(dot3(p, p))
        for i in range(3):
            out[k, i] = p[i] / norm
    ref = np.empty(n - 1)
    cr = np.empty(3)
    for k in range(n - 1):
        _parallel_transport(out[k], t_new[k], t_new[k + 1], p, w3)
        cross3(p, out[k + 1], cr)
        angle = math.atan2(dot3(cr, t_new[k + 1]), dot3(p, out[k + 1]))
        d = angle - ref_prev[k]
        ref[k] = ref_prev[k] + math.atan2(math.sin(d), math.cos(d))
    return out, ref


@njit(cache=True, error_model="numpy")
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


@njit(cache=True, error_model="numpy")
def material_frames_twist(t, a1, theta, ref):
    """Material frames m1 = cos(theta) a1 + sin(theta) t x a1, m2 = -sin(theta) a1 + cos(theta)
    t x a1 (``frames.material_frames``) and the integrated twists theta_(k+1) - theta_k + ref_k
    [rad]."""
    n = len(theta)
    m1 = np.empty((n, 3))
    m2 = np.empty((n, 3))
    a2 = np.empty(3)
    for k in range(n):
        cross3(t[k], a1[k], a2)
        c = math.cos(theta[k])
        s_ = math.sin(theta[k])
        for i in range(3):
            m1[k, i] = c * a1[k, i] + s_ * a2[i]
            m2[k, i] = -s_ * a1[k, i] + c * a2[i]
    twist = np.empty(n - 1)
    for k in range(n - 1):
        twist[k] = theta[k + 1] - theta[k] + ref[k]
    return m1, m2, twist


@njit(cache=True, error_model="numpy")
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
