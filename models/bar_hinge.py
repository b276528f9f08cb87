"""Elements of the bar-and-hinge (MERLIN-type) reduced-order model of the Kapton ribbon and the
composite beam (seed 001, "Numerical simulation" and Fig. 2F; Liu & Paulino 2017): the kinematics
and element energies with analytic first and second derivatives, vectorised over elements. The
materials (parameter sections and laws: MERLIN2 bar law, tension-only Ogden strips, enhanced-linear
springs) are :mod:`lcefem.models.bar_hinge_materials`.

* **Dihedral angle** theta in (0, 2 pi) of a hinge (axis j -> k, wings i and l; flat = pi), with the
  analytic gradient of Liu & Paulino 2017 (Eqs. 12-15) and its exact Hessian, obtained here by
  differentiating that gradient (checked against finite differences in tests/models).
* **N5B8 bar areas** of a W x H panel of thickness t (Filipov, Liu, Tachi, Schenk, Paulino, "Bar and
  hinge models for scalable analysis of origami", Int. J. Solids Struct. 124:26-45, 2017, Sec. 4.1).
* **Strip bending** (added here; the published model's strips are bars only,
  ``mesh.strip_element``): a straight strip piece clamped to its two bonded panels as an
  Euler-Bernoulli beam, U = (2EI/L)(d_a^2 + d_a d_b + d_b^2) with d_a, d_b its end rotations
  relative to its chord, measured as changes of dihedral angles (:func:`strip_beam_element`).
* **Panel torsion** (added here, ``kapton.twist = "plate"``; the published panels twist with every
  spoke hinge, GJ = k D^3/(2 W), 13.6 x the film's G w t^3/3 on the gridshell's 2.3 x 7 mm panels):
  the spokes keep beta k and a panel bending element (1 - beta) k restores the bending mode, so that
  a one-panel-wide ribbon twists as the plate strip (:func:`panel_twist_fraction`,
  :func:`panel_bending_element`).
* **Strip-ribbon contact** (added here; the published model has none): frictionless unilateral
  point-plane penalty k <g0 - g>_+^2/2 with the signed distance g of a point to a plane through
  three nodes, its gradient and Hessian. Without it a free composite beam lets its ribbon pass
  through its strips and curls into loops (validation/cases/beam_bar_hinge.py, report of issue 4).

Units: mm, N, MPa, mJ; angles in radians inside the functions (parameters state degrees where the
published model does).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from lcefem.models.bar_hinge_materials import KaptonBarHinge

# A law maps a stretch (or an angle) to (energy density, first derivative, second derivative).
Law = Callable[[np.ndarray], tuple[np.ndarray, np.ndarray, np.ndarray]]


# --------------------------------------------------------------------------- kinematics
def _skew(v):
    """[v]_x with [v]_x w = v x w, for v of shape (n, 3) -> (n, 3, 3)."""
    out = np.zeros(v.shape[:-1] + (3, 3))
    out[..., 0, 1], out[..., 0, 2] = -v[..., 2], v[..., 1]
    out[..., 1, 0], out[..., 1, 2] = v[..., 2], -v[..., 0]
    out[..., 2, 0], out[..., 2, 1] = -v[..., 1], v[..., 0]
    return out


def _outer(a, b):
    return a[..., :, None] * b[..., None, :]


def _cross(a, b):
    """a x b for arrays of 3-vectors (..., 3): the arithmetic of np.cross (a1 b2 - a2 b1, ...),
    without its axis handling, which cost more than the products on the gridshell's ~10^4 hinges."""
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    return np.stack((a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0), axis=-1)


def _dot(a, b):
    return np.einsum("...i,...i->...", a, b)


def dihedral_angle(x_j, x_k, x_i, x_l, *, derivatives: int = 2):
    """Dihedral angle of the hinge with axis j -> k and wings i and l (Liu & Paulino 2017, Sec. 2).

    theta in (0, 2 pi), = pi when the two triangles (i, j, k) and (j, k, l) are coplanar and on
    opposite sides of the axis. With e = x_k - x_j, a = x_i - x_j, b = x_k - x_l, m = a x e,
    n = e x b: theta = atan2(|e| a.n, m.n) mapped to [0, 2 pi), and (Liu & Paulino 2017, Eq. 12-15)

        d theta/d x_i = |e| m/|m|^2,    d theta/d x_l = -|e| n/|n|^2,
        d theta/d x_j = (A - 1) d theta/d x_i - B d theta/d x_l,
        d theta/d x_k = (B - 1) d theta/d x_l - A d theta/d x_i,     A = a.e/|e|^2, B = b.e/|e|^2.

    The Hessian is the exact Jacobian of this gradient (product and chain rules on m, n, |e|, A, B),
    taken in the variables (a, e, b) on which theta depends and mapped to the nodes.

    Args:
        x_j, x_k, x_i, x_l: node positions [mm], arrays of shape (n, 3).
        derivatives: 0, 1 or 2.
    Returns:
        theta (n,) [rad]; with derivatives >= 1 the gradient (n, 12) ordered (j, k, i, l) [1/mm];
        with derivatives == 2 the Hessian (n, 12, 12) [1/mm^2].
    """
    e = x_k - x_j
    a = x_i - x_j
    b = x_k - x_l
    m = _cross(a, e)
    n = _cross(e, b)
    e2 = _dot(e, e)
    le = np.sqrt(e2)
    theta = np.arctan2(le * _dot(a, n), _dot(m, n))
    theta = np.where(theta < 0.0, theta + 2.0 * np.pi, theta)
    if derivatives == 0:
        return theta
    m2 = _dot(m, m)
    n2 = _dot(n, n)
    gi = (le / m2)[:, None] * m
    gl = -(le / n2)[:, None] * n
    A = _dot(a, e) / e2
    B = _dot(b, e) / e2
    gj = (A - 1.0)[:, None] * gi - B[:, None] * gl
    gk = (B - 1.0)[:, None] * gl - A[:, None] * gi
    grad = np.concatenate([gj, gk, gi, gl], axis=1)
    if derivatives == 1:
        return theta, grad
    # theta depends on the nodes through a = x_i - x_j, e = x_k - x_j, b = x_k - x_l only:
    # dtheta/da = g_i, dtheta/db = -g_l, dtheta/de = g_k + g_l = B g_l - A g_i. Differentiate these
    # in (a, e, b) and map to the nodes with the constant incidence coefficients.
    eye = np.eye(3)
    # g_i = |e| m/|m|^2 with m = a x e:  dm = -[e]x da + [a]x de.
    pm = (eye - 2.0 * _outer(m, m) / m2[:, None, None]) / m2[:, None, None]
    dgi_da = -le[:, None, None] * pm @ _skew(e)
    dgi_de = _outer(m, e) / (m2 * le)[:, None, None] + le[:, None, None] * pm @ _skew(a)
    # g_l = -|e| n/|n|^2 with n = e x b:  dn = -[b]x de + [e]x db.
    pn = (eye - 2.0 * _outer(n, n) / n2[:, None, None]) / n2[:, None, None]
    dgl_de = -_outer(n, e) / (n2 * le)[:, None, None] + le[:, None, None] * pn @ _skew(b)
    dgl_db = -le[:, None, None] * pn @ _skew(e)
    # A = a.e/|e|^2, B = b.e/|e|^2
    dA_de = (a - 2.0 * A[:, None] * e) / e2[:, None]
    dB_de = (b - 2.0 * B[:, None] * e) / e2[:, None]
    h_aa = dgi_da
    h_ae = dgi_de
    h_bb = -dgl_db
    h_be = -dgl_de
    h_ee = (
        _outer(gl, dB_de)
        + B[:, None, None] * dgl_de
        - _outer(gi, dA_de)
        - A[:, None, None] * dgi_de
    )
    h_ea = np.swapaxes(h_ae, 1, 2)
    h_eb = np.swapaxes(h_be, 1, 2)
    # Rows of the node Hessian contracted over the first variable: R_p(Y) = sum_X C_pX H_XY,
    # C = d(a, e, b)/d(j, k, i, l): j -> (-1, -1, 0), k -> (0, 1, 1), i -> (1, 0, 0), l -> (0, 0,
    # -1).
    rows = {
        "j": (-h_aa - h_ea, -h_ae - h_ee, -h_eb),
        "k": (h_ea, h_ee + h_be, h_eb + h_bb),
        "i": (h_aa, h_ae, None),
        "l": (None, -h_be, -h_bb),
    }
    hess = np.empty((e.shape[0], 12, 12))
    for p, name in enumerate("jkil"):
        ra, re, rb = rows[name]
        r = slice(3 * p, 3 * p + 3)
        hess[:, r, 0:3] = -(re if ra is None else ra + re)
        hess[:, r, 3:6] = re if rb is None else re + rb
        hess[:, r, 6:9] = 0.0 if ra is None else ra
        hess[:, r, 9:12] = 0.0 if rb is None else -rb
    # Exact up to round-off; symmetrise so the assembled tangent is symmetric to machine precision.
    hess = 0.5 * (hess + np.swapaxes(hess, 1, 2))
    return theta, grad, hess


# --------------------------------------------------------------------------- elements
def bar_element(x1, x2, rest_length, volume, law: Law, *, derivatives: int = 2):
    """Energy V w(l) of bars with stretch l = |x2 - x1|/L_r, and its gradient and Hessian.

    Args:
        x1, x2: end positions [mm], (n, 3); rest_length L_r [mm] and volume V [mm^3], (n,);
        law: stretch -> (w, dw/dl, d2w/dl2) per unit volume [MPa].
    Returns:
        energy (n,) [mJ]; gradient (n, 6) [N] ordered (x1, x2); Hessian (n, 6, 6) [N/mm].
        The axial force (tension positive) is V w'(l)/L_r.
    """
    d = x2 - x1
    length = np.sqrt(_dot(d, d))
    lam = length / rest_length
    w, dw, d2w = law(lam)
    energy = volume * w
    if derivatives == 0:
        return energy
    u = d / length[:, None]
    f = volume * dw / rest_length  # axial force [N]
    grad = np.concatenate([-f[:, None] * u, f[:, None] * u], axis=1)
    if derivatives == 1:
        return energy, grad
    uu = _outer(u, u)
    k_mat = (volume * d2w / rest_length**2)[:, None, None] * uu
    k_geo = (f / length)[:, None, None] * (np.eye(3) - uu)
    k22 = k_mat + k_geo
    hess = np.empty((d.shape[0], 6, 6))
    hess[:, :3, :3] = k22
    hess[:, 3:, 3:] = k22
    hess[:, :3, 3:] = -k22
    hess[:, 3:, :3] = -k22
    return energy, grad, hess


def axial_force(x1, x2, rest_length, volume, law: Law):
    """Axial force V w'(l)/L_r [N] (tension positive) of bars."""
    d = x2 - x1
    lam = np.sqrt(_dot(d, d)) / rest_length
    return volume * law(lam)[1] / rest_length


def hinge_element(x_j, x_k, x_i, x_l, length, law: Law, *, derivatives: int = 2):
    """Energy L_h psi(theta) of rotational springs, with gradient and Hessian (Liu & Paulino 2017).

    Args:
        x_j, x_k: hinge axis ends; x_i, x_l: wing nodes [mm], (n, 3); length L_h [mm], (n,);
        law: theta -> (psi, M, dM/dtheta) per unit length.
    Returns:
        energy (n,) [mJ]; gradient (n, 12) [N] ordered (j, k, i, l); Hessian (n, 12, 12) [N/mm].
    """
    out = dihedral_angle(x_j, x_k, x_i, x_l, derivatives=derivatives)
    theta = out if derivatives == 0 else out[0]
    psi, moment, dmoment = law(theta)
    energy = length * psi
    if derivatives == 0:
        return energy
    grad = (length * moment)[:, None] * out[1]
    if derivatives == 1:
        return energy, grad
    hess = (length * dmoment)[:, None, None] * _outer(out[1], out[1]) + (length * moment)[
        :, None, None
    ] * out[2]
    return energy, grad, hess


def point_plane_gap(x_p, x_a, x_b, x_c, *, derivatives: int = 2):
    """Signed height g = (x_p - x_a).n of point p above the plane of a, b, c, n = N/|N|,
    N = (x_c - x_a) x (x_b - x_a), with its gradient and Hessian.

    With u = x_c - x_a, v = x_b - x_a, w = x_p - x_a, q = (I - n n^T) w/|N|:
    dg/dw = n, dg/du = v x q, dg/dv = q x u; the Hessian follows from
    dq = P dw/|N| - M dN, M = (n q^T + q n^T)/|N| + g P/|N|^2, dN = -[v]x du + [u]x dv.

    Returns:
        g (n,) [mm]; gradient (n, 12) ordered (p, a, b, c) [-]; Hessian (n, 12, 12) [1/mm].
    """
    u, v, w = x_c - x_a, x_b - x_a, x_p - x_a
    big_n = _cross(u, v)
    nu = np.sqrt(_dot(big_n, big_n))
    n = big_n / nu[:, None]
    g = _dot(w, n)
    if derivatives == 0:
        return g
    q = (w - g[:, None] * n) / nu[:, None]
    gw, gu, gv = n, _cross(v, q), _cross(q, u)
    grad = np.concatenate([gw, -(gw + gu + gv), gv, gu], axis=1)
    if derivatives == 1:
        return g, grad
    proj = np.eye(3) - _outer(n, n)
    mm = (_outer(n, q) + _outer(q, n)) / nu[:, None, None] + (g / nu**2)[:, None, None] * proj
    su, sv, sq = _skew(u), _skew(v), _skew(q)
    pw = proj / nu[:, None, None]
    h = {
        ("w", "w"): np.zeros_like(proj),
        ("u", "w"): sv @ pw,
        ("v", "w"): -su @ pw,
        ("u", "u"): sv @ mm @ sv,
        ("v", "v"): su @ mm @ su,
        ("u", "v"): -sv @ mm @ su - sq,
    }
    h[("w", "u")] = np.swapaxes(h[("u", "w")], 1, 2)
    h[("w", "v")] = np.swapaxes(h[("v", "w")], 1, 2)
    h[("v", "u")] = np.swapaxes(h[("u", "v")], 1, 2)
    # Node blocks (p, a, b, c): w = p - a, u = c - a, v = b - a.
    coef = {"w": (1.0, -1.0, 0.0, 0.0), "u": (0.0, -1.0, 0.0, 1.0), "v": (0.0, -1.0, 1.0, 0.0)}
    hess = np.zeros((g.shape[0], 12, 12))
    for (r, c), block in h.items():
        for i, ci in enumerate(coef[r]):
            for j, cj in enumerate(coef[c]):
                if ci and cj:
                    hess[:, 3 * i : 3 * i + 3, 3 * j : 3 * j + 3] += ci * cj * block
    return g, grad, 0.5 * (hess + np.swapaxes(hess, 1, 2))


def unilateral_contact_element(
    x_p, x_a, x_b, x_c, rest_gap, stiffness, *, derivatives: int = 2, hess_out=None
):
    """Penalty energy k <g0 - g>_+^2/2 [mJ] keeping point p at least g0 above the plane (a, b, c)
    (:func:`point_plane_gap`); k [N/mm], g0 [mm]. Returns energy, gradient (n, 12) [N] and Hessian
    (n, 12, 12) [N/mm] ordered (p, a, b, c). The derivatives of the gap are evaluated only where the
    contact is active (g < g0): elsewhere gradient and Hessian are zero (most contacts are open).
    ``hess_out``: a zeroed (n, 12, 12) array the Hessian is written into and returned (an
    assembler's slice: only the active contacts' entries are written), instead of a new one."""
    g = point_plane_gap(x_p, x_a, x_b, x_c, derivatives=0)
    pen = np.maximum(rest_gap - g, 0.0)
    energy = 0.5 * stiffness * pen**2
    if derivatives == 0:
        return energy
    n = g.shape[0]
    active = np.flatnonzero(pen > 0)
    grad = np.zeros((n, 12))
    hess = None
    if derivatives == 2:
        hess = np.zeros((n, 12, 12)) if hess_out is None else hess_out
    if active.size:
        k = np.broadcast_to(np.asarray(stiffness, dtype=float), g.shape)[active]
        out = point_plane_gap(
            x_p[active], x_a[active], x_b[active], x_c[active], derivatives=derivatives
        )
        grad[active] = (-k * pen[active])[:, None] * out[1]
        if derivatives == 2:
            hess[active] = (
                k[:, None, None] * _outer(out[1], out[1])
                + (-k * pen[active])[:, None, None] * out[2]
            )
    if derivatives == 1:
        return energy, grad
    return energy, grad, hess


def strip_beam_element(
    x_a, x_a2, x_pa, x_b, x_b2, x_pb, stiffness, rest_a, rest_b, *, derivatives: int = 2
):
    """Bending energy of a straight LCE strip piece clamped at both ends (an Euler-Bernoulli beam
    element in terms of its end rotations relative to its chord), with gradient and Hessian.

    The piece runs from a to b (its line of action: the strip's centroid); a2 and b2 are the nodes
    across the strip's width at each end, and pa, pb a node of the panel (frame) each end is clamped
    to. The end rotations relative to the chord, about the width axis, are the changes of two
    dihedral angles (:func:`dihedral_angle`): d_a = theta(a -> a2; pa, b) - theta_a0 and
    d_b = theta(b -> b2; pb, a) - theta_b0 (both axes point the same way across the width, so d_a
    and d_b are rotations in the same sense; each wrapped to (-pi, pi]). With the beam's end moments
    M_a = (2EI/L)(2 d_a + d_b), M_b = (2EI/L)(d_a + 2 d_b) (slope-deflection equations, e.g.
    Timoshenko & Young, Theory of Structures, ch. 9) the energy is

        U = (2 E I/L) (d_a^2 + d_a d_b + d_b^2),

    so that a uniform curvature kappa (d_a = -d_b = kappa L/2) stores E I kappa^2 L/2.

    Args:
        x_a, x_a2, x_pa, x_b, x_b2, x_pb: node positions [mm], (n, 3) each.
        stiffness: 2 E I/L [N mm], (n,); rest_a, rest_b: as-built dihedral angles [rad], (n,).
    Returns:
        energy (n,) [mJ]; gradient (n, 18) [N] ordered (a, a2, pa, b, b2, pb);
        Hessian (n, 18, 18) [N/mm].
    """
    out_a = dihedral_angle(x_a, x_a2, x_pa, x_b, derivatives=derivatives)
    out_b = dihedral_angle(x_b, x_b2, x_pb, x_a, derivatives=derivatives)
    th_a = out_a if derivatives == 0 else out_a[0]
    th_b = out_b if derivatives == 0 else out_b[0]
    d_a = np.mod(th_a - rest_a + np.pi, 2.0 * np.pi) - np.pi
    d_b = np.mod(th_b - rest_b + np.pi, 2.0 * np.pi) - np.pi
    c = np.asarray(stiffness, dtype=float)
    energy = c * (d_a * d_a + d_a * d_b + d_b * d_b)
    if derivatives == 0:
        return energy
    n = d_a.shape[0]
    # node slots of each hinge's (j, k, i, l) in (a, a2, pa, b, b2, pb)
    slots_a, slots_b = (0, 1, 2, 3), (3, 4, 5, 0)

    def spread(g12, slots):
        g = np.zeros((n, 18))
        for q, s in enumerate(slots):
            g[:, 3 * s : 3 * s + 3] += g12[:, 3 * q : 3 * q + 3]
        return g

    ga, gb = spread(out_a[1], slots_a), spread(out_b[1], slots_b)
    m_a, m_b = c * (2.0 * d_a + d_b), c * (d_a + 2.0 * d_b)
    grad = m_a[:, None] * ga + m_b[:, None] * gb
    if derivatives == 1:
        return energy, grad

    def spread2(h12, slots):
        h = np.zeros((n, 18, 18))
        for p, sp_ in enumerate(slots):
            for q, sq in enumerate(slots):
                h[:, 3 * sp_ : 3 * sp_ + 3, 3 * sq : 3 * sq + 3] += h12[
                    :, 3 * p : 3 * p + 3, 3 * q : 3 * q + 3
                ]
        return h

    hess = (
        c[:, None, None]
        * (2.0 * _outer(ga, ga) + _outer(ga, gb) + _outer(gb, ga) + 2.0 * _outer(gb, gb))
        + m_a[:, None, None] * spread2(out_a[2], slots_a)
        + m_b[:, None, None] * spread2(out_b[2], slots_b)
    )
    return energy, grad, hess


# --------------------------------------------------------------------------- N5B8 calibration
def n5b8_bar_areas(width, height, thickness, poisson_ratio):
    """Bar areas [mm^2] of an N5B8 panel W x H x t (Filipov et al. 2017, Sec. 4.1).

    Matches the plane-stress stretching energy t W H E/(2 (1 - nu^2)) (e_x^2 + e_y^2 + 2 nu e_x e_y)
    of the panel under homogeneous strain exactly when nu W^2 <= H^2 and nu H^2 <= W^2 (the absolute
    values keep the areas positive otherwise, as in Filipov et al. and the published model).

    Returns:
        (area of the two edges of length W, area of the two edges of length H, area of each of the
        four spokes); edges shared by two panels get the sum of both panels' contributions.
    """
    w = np.asarray(width, dtype=float)
    h = np.asarray(height, dtype=float)
    c = thickness / (1.0 - poisson_ratio**2)
    a_w = c * np.abs(h**2 - poisson_ratio * w**2) / (2.0 * h)
    a_h = c * np.abs(w**2 - poisson_ratio * h**2) / (2.0 * w)
    a_s = c * poisson_ratio * (h**2 + w**2) ** 1.5 / (2.0 * h * w)
    return a_w, a_h, a_s


def n5b8_ribbon_bending_stiffness(
    hinge_stiffness: float, panel_length: float, width: float
) -> float:
    """Bending stiffness EI_eff [N mm^2] of a chain of N5B8 panels W x H (H = width) under
    cylindrical bending, every hinge (fold and spoke) with stiffness k per unit length and rigid
    bars.

    Per panel, with the corners on the cylinder and the centre node free (it rises by c):
    fold rotation kappa W - 4c/W on a hinge of length H; each of the four spokes (length D/2,
    D^2 = W^2 + H^2) rotates by 2 c D/(W H). Minimising over c gives c = kappa W^2 H^3/(4 H^3 + 2
    D^3) and U = k kappa^2 W^2 H D^3/(2 (2 H^3 + D^3)) = (EI_eff W/2) kappa^2, so
    EI_eff = k W H D^3/(2 H^3 + D^3) (derived here; checked against the bar-and-hinge energy in
    tests/validation).
    """
    w, h = panel_length, width
    d3 = (w * w + h * h) ** 1.5
    return hinge_stiffness * w * h * d3 / (2.0 * h**3 + d3)


def n5b8_ribbon_twist_stiffness(hinge_stiffness: float, panel_length, width):
    """Torsional stiffness GJ [N mm^2] of a chain of N5B8 panels W x H (H = width, one panel across
    it) with every spoke hinge of stiffness k per unit length and rigid bars.

    In a uniform twist tau (z = tau x y) the corners of a panel rise and fall by tau W H/4, the
    centre node stays on the axis and the fold hinges between panels stay flat; each of the four
    spokes (length D/2, D^2 = W^2 + H^2) folds by tau D/2. The panel stores 4 k (D/2)(tau D/2)^2/2
    = k D^3 tau^2/4 = (GJ W/2) tau^2, so GJ = k D^3/(2 W) (derived here; checked against the
    bar-and-hinge energy in tests/models/test_panel_twist.py). For the gridshell's panels
    (k = 0.698 N mm/(rad mm)): 60.7 N mm^2 (2.3 x 7 mm flanks), 48.4 (7 x 7 mm), against the plate's
    G w t^3/3 = 4.46 N mm^2.
    """
    w = np.asarray(panel_length, dtype=float)
    d3 = (w * w + np.asarray(width, dtype=float) ** 2) ** 1.5
    return hinge_stiffness * d3 / (2.0 * w)


def panel_twist_fraction(kapton: KaptonBarHinge, thickness: float, width, height):
    """Fraction beta [-] of the spokes' stiffness left in the twist mode of W x H panels
    (``kapton.twist = "plate"``): beta = (G H t^3/3)/(k D^3/(2 W)) = 2 G W H t^3/(3 k D^3), which
    gives a one-panel-wide ribbon the plate strip's torsional stiffness G w t^3/3 (Timoshenko &
    Goodier, Theory of Elasticity, torsion of a thin rectangle) whichever side runs along it
    (beta is symmetric in W and H). 1 with ``twist = "n5b8"``.
    """
    w = np.asarray(width, dtype=float)
    h = np.asarray(height, dtype=float)
    if kapton.checked().twist == "n5b8":
        return np.ones(np.broadcast(w, h).shape)
    k = kapton.hinge_stiffness(thickness)
    return 2.0 * kapton.shear_modulus * w * h * thickness**3 / (3.0 * k * (w * w + h * h) ** 1.5)


#: Spoke m of an N5B8 panel (centre c, corners 0..3 in cyclic order) is the hinge (c, m; m - 1, m +
#: 1) (:func:`lcefem.meshes.bar_hinge_structure.n5b8_structure`): its nodes' slots in (c, 0, 1, 2,
#: 3).
SPOKE_SLOTS = tuple((0, 1 + m, 1 + (m - 1) % 4, 1 + (m + 1) % 4) for m in range(4))


def panel_bending_element(
    x_c, x_0, x_1, x_2, x_3, lengths, rest, stiffness, *, derivatives: int = 2
):
    """The N5B8 panel's bending (pyramid) mode as one spring: with the spokes' fold angle changes
    d_m (m = 0..3, each wrapped to (-pi, pi]) and lengths L_m,

        U = k_p (sum_m L_m d_m)^2/(2 sum_m L_m).

    In a rectangle's two out-of-plane modes the spokes fold by (d, d, d, d) (bending: the centre
    rises against the corners) or by (d, -d, d, -d) (twist: the corners rise and fall in turn);
    U stores 2 k_p L d^2 (L = D/2) of the first, as four spokes of stiffness k_p do, and nothing of
    the second. So spokes of stiffness beta k plus this element with k_p = (1 - beta) k keep the
    panel's bending of the published model and scale its twist by beta (``kapton.twist = "plate"``,
    :func:`panel_twist_fraction`).

    Args:
        x_c, x_0..x_3: centre and corner positions [mm], (n, 3) each; lengths L_m [mm] and rest
            (as-built) spoke angles [rad], (n, 4); stiffness k_p [N mm/(rad mm)], (n,).
    Returns:
        energy (n,) [mJ]; gradient (n, 15) [N] ordered (c, 0, 1, 2, 3); Hessian (n, 15, 15) [N/mm].
    """
    xs = (x_c, x_0, x_1, x_2, x_3)
    n = x_c.shape[0]
    lengths = np.asarray(lengths, dtype=float)
    outs = [
        dihedral_angle(*(xs[s] for s in SPOKE_SLOTS[m]), derivatives=derivatives) for m in range(4)
    ]
    theta = np.stack([o if derivatives == 0 else o[0] for o in outs], axis=1)
    d = np.mod(theta - rest + np.pi, 2.0 * np.pi) - np.pi
    total = np.sum(lengths, axis=1)
    c = np.asarray(stiffness, dtype=float) / total
    s = np.sum(lengths * d, axis=1)
    energy = 0.5 * c * s * s
    if derivatives == 0:
        return energy
    g = np.zeros((n, 15))
    for m in range(4):
        for q, slot in enumerate(SPOKE_SLOTS[m]):
            g[:, 3 * slot : 3 * slot + 3] += lengths[:, m, None] * outs[m][1][:, 3 * q : 3 * q + 3]
    grad = (c * s)[:, None] * g
    if derivatives == 1:
        return energy, grad
    hess = c[:, None, None] * _outer(g, g)
    for m in range(4):
        weight = (c * s * lengths[:, m])[:, None, None]
        for a, sa in enumerate(SPOKE_SLOTS[m]):
            for b, sb in enumerate(SPOKE_SLOTS[m]):
                hess[:, 3 * sa : 3 * sa + 3, 3 * sb : 3 * sb + 3] += (
                    weight * outs[m][2][:, 3 * a : 3 * a + 3, 3 * b : 3 * b + 3]
                )
    return energy, grad, hess
