"""Discrete Elastic Rods: cross-section properties and the elastic energies of one element.

Energies (seed 000, "DER - Energy Components"; Bergou et al. 2008, 2010; Jawed, Novelia & O'Reilly,
"A Primer on the Kinematics of Discrete Elastic Rods", 2018):

    stretching (edge k)   E_s = 1/2 EA (|e^k| / |e_bar^k| - 1)^2 |e_bar^k|
    bending (node k)      E_b = 1/(2 l_bar_k) sum_i EI_i (kappa_i - kappa_bar_i)^2,  i = 1, 2
    twisting (node k)     E_t = GJ/(2 l_bar_k) (m_k - m_bar_k)^2

with (kappa b)_k = 2 t^(k-1) x t^k / (1 + t^(k-1).t^k), kappa_1 = 1/2 (kappa b).(m2^(k-1) + m2^k),
kappa_2 = -1/2 (kappa b).(m1^(k-1) + m1^k) (integrated curvatures [-]), the integrated twist
m_k = theta^k - theta^(k-1) + (reference twist) [rad], and l_bar_k = (|e_bar^(k-1)| + |e_bar^k|)/2
the rest Voronoi length [mm]. kappa_1 is the curvature towards m1 (bending about m2, stiffness
EI_1), kappa_2 the curvature towards m2 (stiffness EI_2). The natural values kappa_bar, m_bar
(integrated, i.e. density times l_bar) and the rest lengths may change in time: that is how heat
actuates a rod.

Reference frames move by time-parallel transport. The element gradients and Hessians here are
exact derivatives of the energy with the reference frame transported from the *current*
configuration (Panetta, "Discrete elastic rods: the gradient and Hessian", 2019, makes the same
choice); :func:`apply_source_change` turns them into the exact derivatives for frames transported
from a fixed source (the start of a time step), which is what makes a step's incremental potential
one fixed function of the dofs. With the current source, for an edge of length l, unit tangent t
and material frame (m1, m2):

    d m1 = -t (m1.de)/l + m2 d(theta),   d m2 = -t (m2.de)/l - m1 d(theta),

and the second-order terms follow from the Taylor expansion of the parallel transport (see
:func:`frame_second_derivative`). The reference twist varies as the holonomy of the loop traced
by the two tangents on the unit sphere (see :func:`twist_hessian_ef`).

Everything is vectorised over elements: no Python loop over nodes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from lcefem.models.parameters import param


# ----------------------------------------------------------------------------------------------
# Cross-section
# ----------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class RodSection:
    """Stiffnesses and inertia of a rod cross-section (uniform along the rod)."""

    EA: float = param(1.0, "N", "axial stiffness E A", positive=True)
    EI1: float = param(
        1.0, "N mm^2", "bending stiffness for curvature towards m1 (about m2)", positive=True
    )
    EI2: float = param(
        1.0, "N mm^2", "bending stiffness for curvature towards m2 (about m1)", positive=True
    )
    GJ: float = param(1.0, "N mm^2", "torsional stiffness G J", positive=True)
    mass_per_length: float = param(1.0e-9, "t/mm", "rho A", minimum=0.0)
    inertia_per_length: float = param(
        1.0e-9, "t mm", "rho I_p: polar mass moment per length", minimum=0.0
    )
    width: float = param(0.0, "mm", "extent along m1 (0: a line, no corners)", minimum=0.0)
    thickness: float = param(0.0, "mm", "extent along m2 (0: a line, no corners)", minimum=0.0)


def torsion_constant_rectangle(width: float, thickness: float) -> float:
    """Saint-Venant torsion constant J [mm^4] of a solid w x t rectangle (w >= t after sorting).

    J = w t^3 [1/3 - 0.21 (t/w) (1 - (t/w)^4 / 12)] (Roark's Formulas for Stress and Strain, 7th
    ed., Table 10.7 case 4; within about 1 % of the exact series of Timoshenko & Goodier, Theory of
    Elasticity, 3rd ed., Sec. 109, for every aspect ratio). It tends to the thin-strip value w t^3/3
    for w >> t; the 0.21 t/w term is the stress-free edge correction, which matters for the LCE
    ribbons' aspect ratio (t/w ~ 0.2 lowers J by 13 %).
    """
    w, t = max(width, thickness), min(width, thickness)
    r = t / w
    return w * t**3 * (1.0 / 3.0 - 0.21 * r * (1.0 - r**4 / 12.0))


def rectangular_section(
    width: float, thickness: float, youngs_modulus: float, shear_modulus: float, density: float
) -> RodSection:
    """Section of a solid rectangular ribbon: width along m1, thickness along m2 [mm], E, G [MPa],
    density [t/mm^3].

    EA = E w t; EI_1 = E t w^3/12 (in-plane, curvature towards m1); EI_2 = E w t^3/12 (out of the
    ribbon's plane, the soft direction); GJ with :func:`torsion_constant_rectangle`; rho A and the
    polar mass moment rho I_p = rho w t (w^2 + t^2)/12.
    """
    area = width * thickness
    return RodSection(
        EA=youngs_modulus * area,
        EI1=youngs_modulus * thickness * width**3 / 12.0,
        EI2=youngs_modulus * width * thickness**3 / 12.0,
        GJ=shear_modulus * torsion_constant_rectangle(width, thickness),
        mass_per_length=density * area,
        inertia_per_length=density * area * (width**2 + thickness**2) / 12.0,
        width=width,
        thickness=thickness,
    )


def circular_section(
    radius: float, youngs_modulus: float, shear_modulus: float, density: float
) -> RodSection:
    """Section of a solid round rod: I = pi r^4/4, J = pi r^4/2 (seed 000, 'Energy Components')."""
    area = math.pi * radius**2
    inertia = math.pi * radius**4 / 4.0
    return RodSection(
        EA=youngs_modulus * area,
        EI1=youngs_modulus * inertia,
        EI2=youngs_modulus * inertia,
        GJ=shear_modulus * 2.0 * inertia,
        mass_per_length=density * area,
        inertia_per_length=density * 2.0 * inertia,
        width=0.0,
        thickness=0.0,
    )


# ----------------------------------------------------------------------------------------------
# Small vector helpers (vectorised over a leading axis)
# ----------------------------------------------------------------------------------------------
def skew(v: np.ndarray) -> np.ndarray:
    """[v]_x with [v]_x u = v x u, shape (..., 3, 3)."""
    out = np.zeros(v.shape[:-1] + (3, 3))
    out[..., 0, 1] = -v[..., 2]
    out[..., 0, 2] = v[..., 1]
    out[..., 1, 0] = v[..., 2]
    out[..., 1, 2] = -v[..., 0]
    out[..., 2, 0] = -v[..., 1]
    out[..., 2, 1] = v[..., 0]
    return out


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a x b over the last axis (a faster np.cross for small stacks of 3-vectors)."""
    out = np.empty(np.broadcast_shapes(a.shape, b.shape))
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    out[..., 0] = a1 * b2 - a2 * b1
    out[..., 1] = a2 * b0 - a0 * b2
    out[..., 2] = a0 * b1 - a1 * b0
    return out


def _dot(a, b):
    return np.einsum("...i,...i->...", a, b)


def _outer(a, b):
    return a[..., :, None] * b[..., None, :]


def _sym(a):
    return a + np.swapaxes(a, -1, -2)


_EYE = np.eye(3)


def parallel_transport(u: np.ndarray, t_from: np.ndarray, t_to: np.ndarray) -> np.ndarray:
    """Rotate u by the smallest rotation taking unit vector t_from to t_to (seed 000, 'Parallel
    Transport'): P(u) = u + v x u + v x (v x u)/(1 + c), v = t_from x t_to, c = t_from . t_to.

    Undefined for antipodal tangents (c = -1), which a time step never produces.
    """
    v = cross(t_from, t_to)
    c = _dot(t_from, t_to)
    vu = cross(v, u)
    return u + vu + cross(v, vu) / (1.0 + c)[..., None]


def signed_angle(u: np.ndarray, v: np.ndarray, axis: np.ndarray) -> np.ndarray:
    """Angle [rad] that rotates u onto v about ``axis`` (both perpendicular to it)."""
    return np.arctan2(_dot(cross(u, v), axis), _dot(u, v))


def curvature_binormal(e: np.ndarray, f: np.ndarray) -> np.ndarray:
    """(kappa b) = 2 t_e x t_f / (1 + t_e . t_f) = 2 e x f / (|e||f| + e.f) [-]."""
    le = np.linalg.norm(e, axis=-1)
    lf = np.linalg.norm(f, axis=-1)
    return 2.0 * cross(e, f) / (le * lf + _dot(e, f))[..., None]


# ----------------------------------------------------------------------------------------------
# Stretching
# ----------------------------------------------------------------------------------------------
def stretching(e: np.ndarray, rest_length: np.ndarray, EA: float):
    """Stretching energy of each edge and its derivatives with respect to the edge vector e.

    Args:
        e: edge vectors x_(k+1) - x_k [mm], shape (n, 3).
        rest_length: |e_bar| [mm], shape (n,).
        EA: axial stiffness [N].

    Returns:
        energy (n,) [mJ], gradient dE/de (n, 3) [N], Hessian d2E/de2 (n, 3, 3) [N/mm].
        With respect to (x_k, x_(k+1)) the gradient is (-g, g) and the Hessian [[H, -H], [-H, H]].
    """
    length = np.linalg.norm(e, axis=1)
    t = e / length[:, None]
    strain = length / rest_length - 1.0
    energy = 0.5 * EA * strain**2 * rest_length
    grad = (EA * strain)[:, None] * t
    tt = _outer(t, t)
    hess = (EA / rest_length)[:, None, None] * tt + (EA * strain / length)[:, None, None] * (
        _EYE - tt
    )
    return energy, grad, hess


# ----------------------------------------------------------------------------------------------
# Frame derivatives (at the transport source, i.e. the current configuration)
# ----------------------------------------------------------------------------------------------
def frame_second_derivative(t: np.ndarray, length: np.ndarray, m: np.ndarray, g: np.ndarray):
    """Second derivatives of g . m for a material-frame vector m (m1 or m2) of one edge.

    With the reference frame time-parallel transported from the current tangent t, the Taylor
    expansion of the transport gives, for the edge vector e and a fixed vector g,

        d2(g.m)/de2 = [(g.t)(m t^T + t m^T) - 1/2 (m p^T + p m^T)] / l^2,   p = (I - t t^T) g,

    and (for m = m1; m2 is analogous with m2 -> -m1) d2(g.m1)/(de dtheta) = -(g.t) m2 / l,
    d2(g.m1)/dtheta2 = -g.m1.

    Returns:
        d2(g.m)/de2 of shape (n, 3, 3).
    """
    gt = _dot(g, t)
    p = g - gt[:, None] * t
    inv_l2 = 1.0 / length**2
    return inv_l2[:, None, None] * (
        gt[:, None, None] * _sym(_outer(m, t)) - 0.5 * _sym(_outer(m, p))
    )


def source_change(source: np.ndarray, t: np.ndarray, length: np.ndarray):
    """Derivatives of the holonomy angle beta of each edge's time-parallel transport.

    Within a Newton solve the reference directors are transported from a fixed *source* tangent s
    (the step's start): a1(t) = P_(s->t) a1_s. Transporting instead through the current tangent t,
    P_(t->t') P_(s->t), differs from the direct transport P_(s->t') by a turn of the angle beta(t')
    about t', minus the solid angle of the geodesic triangle (s, t, t') (Van Oosterom & Strackee
    1983). So the energy with the fixed source is E(x, theta + beta(x)) in terms of the energy E
    whose source is the current state (the one :func:`bend_twist` differentiates), and

        d beta/de   = (t x s) / ((1 + s.t) l),
        d2 beta/de2 = P [(s x t)(t + s)^T + (t + s)(s x t)^T] P / (2 (1 + s.t)^2 l^2)
                      - (g t^T + t g^T)/l^2,     g = (t x s)/(1 + s.t),  P = I - t t^T,

    both zero when t = s.

    Returns:
        (dbeta/de (n, 3), d2beta/de2 (n, 3, 3)) for edges of length l and unit tangents t.
    """
    c = 1.0 + _dot(source, t)
    g = cross(t, source) / c[:, None]
    P = _EYE - _outer(t, t)
    hb = _sym(_outer(-g * c[:, None], t + source)) / (2.0 * c * c)[:, None, None]
    inv_l2 = (1.0 / length**2)[:, None, None]
    return g / length[:, None], P @ hb @ P * inv_l2 - _sym(_outer(g, t)) * inv_l2


def apply_source_change(grad: np.ndarray, hess: np.ndarray | None, slots, d_beta, dd_beta):
    """Chain rule from the current-source derivatives of elements to the fixed-source ones.

    Args:
        grad, hess: element gradients (n, m) and Hessians (n, m, m) in local dofs.
        slots: for each edge of the element, (start of node a, theta index, start of node b) with
            e = x_b - x_a (e.g. ((0, 3, 4),) for an edge element, ((0, 3, 4), (4, 7, 8)) for a node
            stencil).
        d_beta, dd_beta: per element and per slot, (n, 3) and (n, 3, 3) from :func:`source_change`.

    Returns:
        (W^T g, W^T H W + sum_j g_theta_j d2beta_j) with W the Jacobian of
        (x, theta) -> (x, theta + beta(x)).
    """
    n, m = grad.shape
    W = np.broadcast_to(np.eye(m), (n, m, m)).copy()
    g_new = grad.copy()
    for (a, it, b), db in zip(slots, d_beta):
        W[:, it, a : a + 3] = -db
        W[:, it, b : b + 3] = db
        g_new[:, a : a + 3] -= grad[:, it, None] * db
        g_new[:, b : b + 3] += grad[:, it, None] * db
    if hess is None:
        return g_new, None
    h_new = np.swapaxes(W, 1, 2) @ hess @ W
    for (a, it, b), ddb in zip(slots, dd_beta):
        blk = grad[:, it, None, None] * ddb
        h_new[:, a : a + 3, a : a + 3] += blk
        h_new[:, b : b + 3, b : b + 3] += blk
        h_new[:, a : a + 3, b : b + 3] -= blk
        h_new[:, b : b + 3, a : a + 3] -= blk
    return g_new, h_new


# ----------------------------------------------------------------------------------------------
# Bending and twisting of an interior node
# ----------------------------------------------------------------------------------------------
#: Local variables of a node stencil: (e, f, theta_e, theta_f), e = x_k - x_(k-1), f = x_(k+1) -
#: x_k. ``STENCIL_MAP`` (11 x 8) takes them to the stencil dofs (x_(k-1), theta_(k-1), x_k, theta_k,
#: x_(k+1)).
STENCIL_MAP = np.zeros((11, 8))
STENCIL_MAP[0:3, 0:3] = -_EYE
STENCIL_MAP[4:7, 0:3] = _EYE
STENCIL_MAP[4:7, 3:6] = -_EYE
STENCIL_MAP[8:11, 3:6] = _EYE
STENCIL_MAP[3, 6] = 1.0
STENCIL_MAP[7, 7] = 1.0


def _kappa_b_derivatives(e, f, le, lf, te, tf):
    """(kappa b), its Jacobian (n, 3, 6) in (e, f), and a function giving sum_c w_c d2(kappa
    b)_c."""
    n = cross(e, f)
    D = le * lf + _dot(e, f)
    kb = 2.0 * n / D[:, None]
    dn = np.concatenate([-skew(f), skew(e)], axis=2)  # (n, 3, 6): dn_c/d(e,f)
    dD = np.concatenate([lf[:, None] * te + f, le[:, None] * tf + e], axis=1)  # (n, 6)
    ddD = np.zeros((len(e), 6, 6))
    ddD[:, :3, :3] = (lf / le)[:, None, None] * (_EYE - _outer(te, te))
    ddD[:, 3:, 3:] = (le / lf)[:, None, None] * (_EYE - _outer(tf, tf))
    ddD[:, :3, 3:] = _outer(te, tf) + _EYE
    ddD[:, 3:, :3] = np.swapaxes(ddD[:, :3, 3:], 1, 2)
    jac = 2.0 * (dn / D[:, None, None] - n[:, :, None] * dD[:, None, :] / (D**2)[:, None, None])

    def contracted_hessian(w):
        """sum_c w_c d2(kappa b)_c / d(e,f)2, shape (n, 6, 6)."""
        wn = _dot(w, n)
        dnw = np.einsum("nc,nci->ni", w, dn)  # d(w.n)
        h = np.zeros((len(e), 6, 6))
        sw = skew(w)
        h[:, :3, 3:] = -sw
        h[:, 3:, :3] = sw
        h /= D[:, None, None]
        h -= _sym(_outer(dnw, dD)) / (D**2)[:, None, None]
        h += (2.0 * wn / D**3)[:, None, None] * _outer(dD, dD)
        h -= (wn / D**2)[:, None, None] * ddD
        return 2.0 * h

    return kb, jac, contracted_hessian


def twist_hessian_ef(te, tf, le, lf, kb):
    """Hessian (n, 6, 6) of the reference twist in (e, f) with frames transported from the current
    state.

    The reference twist changes by minus the solid angle of the loop (s_e, t_e, t_f, s_f) that the
    tangents trace on the unit sphere from their sources s (holonomy of parallel transport), split
    into two triangles, each Omega = 2 atan2(A.(B x C), 1 + A.B + B.C + C.A) (Van Oosterom &
    Strackee 1983). Its first derivative is the classic (kappa b)/(2|e|), (kappa b)/(2|f|)
    (Bergou et al. 2010); this function returns the exact second derivative at the source.
    """
    chi = 1.0 + _dot(te, tf)
    apc = te + tf
    # Hessian of Omega_1 + Omega_2 with respect to the unit tangents (B = t_e, C = t_f).
    tt_diag = _sym(_outer(kb, apc)) / (4.0 * chi)[:, None, None]
    tt_off = -skew(te) / chi[:, None, None] + _outer(kb, te) / (2.0 * chi)[:, None, None]
    pe = (_EYE - _outer(te, te)) / le[:, None, None]
    pf = (_EYE - _outer(tf, tf)) / lf[:, None, None]
    h = np.zeros((len(te), 6, 6))
    h[:, :3, :3] = pe @ tt_diag @ pe + _sym(_outer(kb, te)) / (2.0 * le**2)[:, None, None]
    h[:, 3:, 3:] = pf @ tt_diag @ pf + _sym(_outer(kb, tf)) / (2.0 * lf**2)[:, None, None]
    h[:, :3, 3:] = pe @ tt_off @ pf
    h[:, 3:, :3] = np.swapaxes(h[:, :3, 3:], 1, 2)
    return -h


def bend_twist(
    e,
    f,
    m1e,
    m2e,
    m1f,
    m2f,
    twist,
    kappa_bar,
    twist_bar,
    voronoi_length,
    EI1,
    EI2,
    GJ,
    want_hessian: bool = True,
):
    """Bending and twisting energy of each interior node with gradient and Hessian.

    Args:
        e, f: edges before and after the node [mm], (n, 3).
        m1e, m2e, m1f, m2f: material frames of the two edges [-], (n, 3).
        twist: integrated twist m = theta_f - theta_e + reference twist [rad], (n,).
        kappa_bar: natural integrated curvatures (kappa_bar_1, kappa_bar_2) [-], (n, 2).
        twist_bar: natural integrated twist [rad], (n,).
        voronoi_length: rest Voronoi length l_bar [mm], (n,).
        EI1, EI2, GJ: stiffnesses [N mm^2] (scalars or (n,)).

    Returns:
        energy (n,) [mJ], gradient (n, 8) and Hessian (n, 8, 8) in the local variables
        (e, f, theta_e, theta_f); map to stencil dofs with :data:`STENCIL_MAP`.
    """
    n = len(e)
    le = np.linalg.norm(e, axis=1)
    lf = np.linalg.norm(f, axis=1)
    te = e / le[:, None]
    tf = f / lf[:, None]
    kb, jac, kb_hess = _kappa_b_derivatives(e, f, le, lf, te, tf)
    M1 = m1e + m1f
    M2 = m2e + m2f
    k1 = 0.5 * _dot(kb, M2)
    k2 = -0.5 * _dot(kb, M1)

    # Gradients in (e, f, theta_e, theta_f); the frame terms in e, f vanish because kb is normal to
    # te, tf.
    g1 = np.zeros((n, 8))
    g2 = np.zeros((n, 8))
    g1[:, :6] = 0.5 * np.einsum("nc,nci->ni", M2, jac)
    g2[:, :6] = -0.5 * np.einsum("nc,nci->ni", M1, jac)
    g1[:, 6] = -0.5 * _dot(kb, m1e)
    g1[:, 7] = -0.5 * _dot(kb, m1f)
    g2[:, 6] = -0.5 * _dot(kb, m2e)
    g2[:, 7] = -0.5 * _dot(kb, m2f)
    gt = np.zeros((n, 8))
    gt[:, :3] = kb / (2.0 * le)[:, None]
    gt[:, 3:6] = kb / (2.0 * lf)[:, None]
    gt[:, 6] = -1.0
    gt[:, 7] = 1.0

    d1 = k1 - kappa_bar[:, 0]
    d2 = k2 - kappa_bar[:, 1]
    dt = twist - twist_bar
    inv_l = 1.0 / voronoi_length
    EI1 = np.broadcast_to(EI1, (n,))
    EI2 = np.broadcast_to(EI2, (n,))
    GJ = np.broadcast_to(GJ, (n,))
    energy = 0.5 * inv_l * (EI1 * d1**2 + EI2 * d2**2 + GJ * dt**2)
    c1 = EI1 * d1 * inv_l
    c2 = EI2 * d2 * inv_l
    ct = GJ * dt * inv_l
    grad = c1[:, None] * g1 + c2[:, None] * g2 + ct[:, None] * gt
    if not want_hessian:
        return energy, grad, None

    # Hessians of kappa_1, kappa_2 contracted with c1, c2 (one combined pass).
    hk = np.zeros((n, 8, 8))
    w = 0.5 * (c1[:, None] * M2 - c2[:, None] * M1)  # sum of c_i dkappa_i/dkb
    hk[:, :6, :6] = kb_hess(w)
    # Cross terms d(kb) x d(frame): frame derivatives in e, f and theta.
    # kappa_1: 1/2 [J^T dM2 + dM2^T J]; dM2/de = -te m2e^T/le, dM2/dtheta_e = -m1e (and f
    # analogous).
    je = jac[:, :, :]  # (n, 3, 6)
    cross = np.zeros((n, 6, 2))  # d2/(d(e,f) d(theta_e, theta_f)) from kb x frame
    cross[:, :, 0] = np.einsum("nci,nc->ni", je, 0.5 * (-c1[:, None] * m1e - c2[:, None] * m2e))
    cross[:, :, 1] = np.einsum("nci,nc->ni", je, 0.5 * (-c1[:, None] * m1f - c2[:, None] * m2f))
    # d(frame)/de terms: dM/de = -te m^T / le; contracted with J: J^T(-te m^T/le) -> -(J^T te) m^T /
    # le
    jte = np.einsum("nci,nc->ni", je, te)  # (n, 6)
    jtf = np.einsum("nci,nc->ni", je, tf)
    me = 0.5 * (c1[:, None] * m2e - c2[:, None] * m1e)
    mf = 0.5 * (c1[:, None] * m2f - c2[:, None] * m1f)
    blk = np.zeros((n, 6, 6))
    blk[:, :, 0:3] -= _outer(jte, me) / le[:, None, None]
    blk[:, :, 3:6] -= _outer(jtf, mf) / lf[:, None, None]
    hk[:, :6, :6] += _sym(blk)
    hk[:, :6, 6:] += cross
    hk[:, 6:, :6] += np.swapaxes(cross, 1, 2)
    # Second derivatives of the frames contracted with kb (kb . t = 0 simplifies them).
    # sum_i c_i d2(kappa_i): kappa_1 -> 1/2 kb.m2, kappa_2 -> -1/2 kb.m1.
    for sl, le_, m1, m2, it in ((slice(0, 3), le, m1e, m2e, 6), (slice(3, 6), lf, m1f, m2f, 7)):
        wm = 0.5 * (c1[:, None] * m2 - c2[:, None] * m1)  # the combination of frame vectors
        hk[:, sl, sl] += -0.5 * _sym(_outer(wm, kb)) / (le_**2)[:, None, None]
        hk[:, it, it] += -_dot(kb, wm)
    # Twist.
    ht = np.zeros((n, 8, 8))
    ht[:, :6, :6] = ct[:, None, None] * twist_hessian_ef(te, tf, le, lf, kb)
    hess = (
        hk
        + ht
        + (EI1 * inv_l)[:, None, None] * _outer(g1, g1)
        + (EI2 * inv_l)[:, None, None] * _outer(g2, g2)
        + (GJ * inv_l)[:, None, None] * _outer(gt, gt)
    )
    return energy, grad, hess


def material_curvatures(e, f, m1e, m2e, m1f, m2f):
    """Integrated curvatures (kappa_1, kappa_2) [-] at interior nodes, shape (n, 2)."""
    kb = curvature_binormal(e, f)
    return np.stack([0.5 * _dot(kb, m2e + m2f), -0.5 * _dot(kb, m1e + m1f)], axis=1)


# ----------------------------------------------------------------------------------------------
# Points of the cross-section (ribbon corners) and their derivatives
# ----------------------------------------------------------------------------------------------
#: Corner signs (s1, s2) of a w x t rectangle: corner = centre + s1 w/2 m1 + s2 t/2 m2.
CORNER_SIGNS = np.array([[1.0, 1.0], [-1.0, 1.0], [-1.0, -1.0], [1.0, -1.0]])


def section_points(x0, x1, m1, m2, offsets, sigma=None):
    """Points x0 + sigma e + a m1 + b m2 of each edge's cross-section at the fraction sigma along it
    (default 1/2, the midpoint), with the edge's own frame.

    Args:
        x0, x1: edge end nodes [mm], (n, 3); m1, m2: material frame [-], (n, 3).
        offsets: (p, 2) offsets (a, b) [mm] in the frame (e.g. corners +-w/2, +-t/2).
        sigma: fractions along the edge, (p,) or (n, p) (default 0.5).

    Returns:
        points (n, p, 3) [mm].
    """
    n, p = len(x0), len(offsets)
    sig = np.broadcast_to(0.5 if sigma is None else np.asarray(sigma, float), (n, p))
    base = x0[:, None, :] + sig[..., None] * (x1 - x0)[:, None, :]
    return (
        base
        + offsets[None, :, 0, None] * m1[:, None, :]
        + offsets[None, :, 1, None] * m2[:, None, :]
    )


def section_point_derivatives(x0, x1, m1, m2, offsets, g, sigma=None):
    """Jacobian of section points (edge's own frame) and the Hessian of g . point, dofs (x0, theta,
    x1).

    The offset r = a m1 + b m2 moves with the frame: d r = -t (r.de)/l + (t x r) d(theta).

    Args:
        offsets: (p, 2) or (n, p, 2) offsets (a, b) [mm].
        g: vectors contracted with the point's second derivative, shape (n, p, 3).
        sigma: fractions along the edge, (p,) or (n, p) (default 0.5).

    Returns:
        jac (n, p, 3, 7) and hess (n, p, 7, 7), dof order (x0, theta, x1).
    """
    n = len(x0)
    off = np.broadcast_to(offsets, (n,) + np.shape(offsets)[-2:])
    p = off.shape[1]
    sig = np.broadcast_to(0.5 if sigma is None else np.asarray(sigma, float), (n, p))
    e = x1 - x0
    length = np.linalg.norm(e, axis=1)
    t = e / length[:, None]
    r = off[..., 0, None] * m1[:, None, :] + off[..., 1, None] * m2[:, None, :]
    tb = np.broadcast_to(t[:, None, :], r.shape)
    lb = np.broadcast_to(length[:, None], (n, p))
    dr_de = -tb[..., :, None] * r[..., None, :] / lb[..., None, None]  # (n, p, 3, 3)
    jac = np.zeros((n, p, 3, 7))
    jac[..., 0:3] = (1.0 - sig)[..., None, None] * _EYE - dr_de
    jac[..., 4:7] = sig[..., None, None] * _EYE + dr_de
    jac[..., 3] = cross(tb, r)
    # Hessian of g.p: r-part only (the base point is linear in the nodes).
    gt = _dot(g, tb)
    pg = g - gt[..., None] * tb
    h_ee = (gt[..., None, None] * _sym(_outer(r, tb)) - 0.5 * _sym(_outer(r, pg))) / (lb**2)[
        ..., None, None
    ]
    h_et = -(gt / lb)[..., None] * cross(tb, r)  # d2(g.r)/(de dtheta)
    h_tt = -_dot(g, r)
    hess = np.zeros((n, p, 7, 7))
    hess[..., 0:3, 0:3] = h_ee
    hess[..., 4:7, 4:7] = h_ee
    hess[..., 0:3, 4:7] = -h_ee
    hess[..., 4:7, 0:3] = -h_ee
    hess[..., 0:3, 3] = -h_et
    hess[..., 3, 0:3] = -h_et
    hess[..., 4:7, 3] = h_et
    hess[..., 3, 4:7] = h_et
    hess[..., 3, 3] = h_tt
    return jac, hess


# ----------------------------------------------------------------------------------------------
# Section points between the sections: the frame angle interpolated with the node's twist
# ----------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class StencilPoints:
    """Points on the two half-edges next to an interior node, with the frame angle interpolated.

    A point of edge E (E = e before the node, f after it) at the fraction sigma along E sits on the
    section turned to theta_eff = theta_E + (sigma - 1/2) m, m = theta_f - theta_e + (reference
    twist) the node's integrated twist: the angle varies linearly from one section to the next, so
    the ribbon between sections is a helicoid and its edges are continuous lines (a flat ribbon
    rolling about its axis then meets the ground smoothly instead of section by section).

    Attributes:
        side: (p,) 0 for edge e (sigma > 1/2), 1 for edge f (sigma < 1/2).
        sigma: (p,) fractions along the point's edge.
        offsets: (p, 2) offsets (a, b) [mm] from the centreline along m1, m2.
    """

    side: np.ndarray
    sigma: np.ndarray
    offsets: np.ndarray

    @classmethod
    def sampling(cls, offsets: np.ndarray, per_edge: int) -> "StencilPoints":
        """``per_edge`` (even) fractions (j + 1/2)/per_edge per edge, half on each side of a
        node."""
        half = per_edge // 2
        sig = (np.arange(per_edge) + 0.5) / per_edge
        sig_e, sig_f = sig[half:], sig[:half]
        k = len(offsets)
        side = np.concatenate([np.zeros(half * k, int), np.ones(half * k, int)])
        sigma = np.concatenate([np.repeat(sig_e, k), np.repeat(sig_f, k)])
        offs = np.concatenate([np.tile(offsets, (half, 1)), np.tile(offsets, (half, 1))])
        return cls(side, sigma, offs)


def stencil_point_heights(x, a1, t, theta, twist, pts: StencilPoints, normal):
    """Heights n.p [mm] of all :class:`StencilPoints` of all interior nodes, shape (N-2, p).

    Only the normal component is formed (the energy-only evaluations and the active-set search need
    no more). x (N, 3) nodes, a1 and t (N-1, 3) reference directors and tangents, theta (N-1,) edge
    angles, twist (N-2,) integrated twists, normal (3,) unit normal of the plane.
    """
    xn = x @ normal
    a1n = a1 @ normal
    a2n = cross(t, a1) @ normal
    side = pts.side.astype(bool)
    edge = np.arange(len(twist))[:, None] + side[None, :].astype(int)  # (n, p): e = s, f = s + 1
    th = theta[edge] + (pts.sigma - 0.5)[None, :] * twist[:, None]
    c, s_ = np.cos(th), np.sin(th)
    m1n = c * a1n[edge] + s_ * a2n[edge]
    m2n = -s_ * a1n[edge] + c * a2n[edge]
    base = xn[edge] + pts.sigma[None, :] * (xn[edge + 1] - xn[edge])
    return base + pts.offsets[None, :, 0] * m1n + pts.offsets[None, :, 1] * m2n


def stencil_points(x, a1, t, theta, twist, pts: StencilPoints, rows: np.ndarray, cols: np.ndarray):
    """Positions (k, 3) [mm] of the selected points (stencil ``rows``, point ``cols``) of
    :class:`StencilPoints`, their offsets r = a m1 + b m2 in the interpolated frames (k, 3) and
    their edges' tangents (k, 3). Stencil s is the interior node s + 1, between edges s and s +
    1."""
    side = pts.side[cols].astype(bool)
    sigma = pts.sigma[cols]
    edge = rows + side.astype(int)
    th = theta[edge] + (sigma - 0.5) * twist[rows]
    a1p = a1[edge]
    tp = t[edge]
    a2p = cross(tp, a1p)
    c, s_ = np.cos(th)[:, None], np.sin(th)[:, None]
    m1 = c * a1p + s_ * a2p
    m2 = -s_ * a1p + c * a2p
    base = x[edge] + sigma[:, None] * (x[edge + 1] - x[edge])
    r = pts.offsets[cols, 0, None] * m1 + pts.offsets[cols, 1, None] * m2
    return base + r, r, tp


def stencil_point_derivatives(e, f, r, t, side, sigma, g, hessian: bool = True):
    """Jacobian of single stencil points and the Hessian of g . point, in the 11 stencil dofs
    (x_(k-1), theta_(k-1), x_k, theta_k, x_(k+1)), for frames transported from the current state.

    Args (one row per point, k rows):
        e, f: the point's stencil edges (k, 3); r: offset a m1 + b m2 in the interpolated frame
        (k, 3); t: the tangent of the point's edge (k, 3); side (k,) 0 for edge e, 1 for edge f;
        sigma (k,) fraction along that edge; g (k, 3).

    Returns:
        jac (k, 3, 11) and hess (k, 11, 11) (None without ``hessian``).

    With theta_eff = theta_E + c m (c = sigma - 1/2) and m = theta_f - theta_e + (reference twist):
    d(theta_eff) = (1 - c, c) on (theta_e, theta_f) for points of e, (-c, 1 + c) for points of f,
    plus c (kappa b/(2|e|), kappa b/(2|f|)) on (e, f); its Hessian is c times the reference twist's
    (:func:`twist_hessian_ef`).
    """
    k = len(r)
    le = np.linalg.norm(e, axis=1)
    lf = np.linalg.norm(f, axis=1)
    te, tf = e / le[:, None], f / lf[:, None]
    kb = curvature_binormal(e, f)
    side = np.asarray(side).astype(bool)
    cm = np.asarray(sigma) - 0.5
    dth = np.zeros((k, 8))
    dth[:, 0:3] = (cm / (2.0 * le))[:, None] * kb
    dth[:, 3:6] = (cm / (2.0 * lf))[:, None] * kb
    dth[:, 6] = np.where(side, -cm, 1.0 - cm)
    dth[:, 7] = np.where(side, 1.0 + cm, cm)
    length = np.where(side, lf, le)
    tr = cross(t, r)
    jv = tr[:, :, None] * dth[:, None, :]  # (k, 3, 8)
    dr_dE = -t[:, :, None] * r[:, None, :] / length[:, None, None]
    jv[:, :, 0:3] += np.where(side[:, None, None], 0.0, dr_dE)
    jv[:, :, 3:6] += np.where(side[:, None, None], dr_dE, 0.0)
    jac = jv @ STENCIL_MAP.T  # (k, 3, 11)
    sig = np.asarray(sigma)
    w0 = np.where(side, 0.0, 1.0 - sig)
    w1 = np.where(side, 1.0 - sig, sig)
    w2 = np.where(side, sig, 0.0)
    jac[:, :, 0:3] += w0[:, None, None] * _EYE
    jac[:, :, 4:7] += w1[:, None, None] * _EYE
    jac[:, :, 8:11] += w2[:, None, None] * _EYE
    if not hessian:
        return jac, None
    gt = _dot(g, t)
    pg = g - gt[:, None] * t
    h_EE = (gt[:, None, None] * _sym(_outer(r, t)) - 0.5 * _sym(_outer(r, pg))) / (length**2)[
        :, None, None
    ]
    h_Eth = -(gt / length)[:, None] * tr
    sel_e = np.where(side, 0.0, 1.0)
    hv = np.zeros((k, 8, 8))
    hv[:, 0:3, 0:3] = sel_e[:, None, None] * h_EE
    hv[:, 3:6, 3:6] = (1.0 - sel_e)[:, None, None] * h_EE
    cross_v = np.zeros((k, 8))
    cross_v[:, 0:3] = sel_e[:, None] * h_Eth
    cross_v[:, 3:6] = (1.0 - sel_e)[:, None] * h_Eth
    hv += _sym(_outer(cross_v, dth))
    hv -= _dot(g, r)[:, None, None] * _outer(dth, dth)
    hv[:, 0:6, 0:6] += (_dot(g, tr) * cm)[:, None, None] * twist_hessian_ef(te, tf, le, lf, kb)
    return jac, STENCIL_MAP @ hv @ STENCIL_MAP.T
