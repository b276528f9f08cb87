"""Element laws of the bar-and-hinge model: closed forms and finite-difference checks of every
energy's first and second derivatives (models/bar_hinge.py)."""

import math

import numpy as np
import pytest

from lcefem.models import bar_hinge as bh
from lcefem.models import bar_hinge_materials as bhm
from lcefem.models.hyperelastic import (
    OgdenLaw,
    ogden_uniaxial_energy,
    ogden_uniaxial_nominal_stress,
)

RNG = np.random.default_rng(12345)
# Central differences with h = 1e-6 on O(1) data: truncation ~h^2, round-off ~eps/h ~ 1e-10;
# 1e-6 relative to the largest entry leaves a wide margin and still catches any wrong term.
FD_H = 1e-6
FD_RTOL = 1e-6


def assert_derivatives_match_fd(fun, x, derivatives=2):
    """fun(X, derivatives) -> (value (n,), grad (n, m)[, hess (n, m, m)]) on rows X (n, m)."""
    out = fun(x, derivatives)
    m = x.shape[1]
    g_fd = np.zeros_like(out[1])
    h_fd = np.zeros((x.shape[0], m, m))
    for c in range(m):
        xp, xm = x.copy(), x.copy()
        xp[:, c] += FD_H
        xm[:, c] -= FD_H
        vp, gp = fun(xp, 1)[:2]
        vm, gm = fun(xm, 1)[:2]
        g_fd[:, c] = (vp - vm) / (2 * FD_H)
        h_fd[:, :, c] = (gp - gm) / (2 * FD_H)
    assert np.max(np.abs(out[1] - g_fd)) <= FD_RTOL * max(1.0, np.max(np.abs(out[1])))
    if derivatives == 2:
        assert np.max(np.abs(out[2] - h_fd)) <= FD_RTOL * max(1.0, np.max(np.abs(out[2])))
        assert np.allclose(out[2], np.swapaxes(out[2], 1, 2), atol=1e-12 * np.max(np.abs(out[2])))


def scalar_fd(law, x):
    """d/dx of (w, w') against (w', w'') of a scalar law."""
    w, dw, d2w = law(x)
    wp, dwp, _ = law(x + FD_H)
    wm, dwm, _ = law(x - FD_H)
    # absolute floor: round-off of the values over 2h, relative to their scale
    np.testing.assert_allclose(
        dw, (wp - wm) / (2 * FD_H), rtol=1e-6, atol=1e-9 * max(1.0, np.max(np.abs(dw)))
    )
    np.testing.assert_allclose(
        d2w, (dwp - dwm) / (2 * FD_H), rtol=1e-6, atol=1e-9 * max(1.0, np.max(np.abs(d2w)))
    )


# ---------------------------------------------------------------------------- material laws
def test_stiffening_bar_law_derivatives_and_small_strain_modulus():
    lam = np.linspace(0.7, 1.3, 25)
    e = 2500.0
    scalar_fd(lambda l: bhm.stiffening_bar_law(l, e), lam)
    w, dw, d2w = bhm.stiffening_bar_law(np.array([1.0]), e)
    assert w[0] == 0.0 and dw[0] == 0.0
    assert d2w[0] == pytest.approx(e, rel=1e-14)  # C0 = E
    # S = (dW/dl)/l is the 2nd Piola stress, and dS/dE = C0 at E = 0 (E = (l^2 - 1)/2).
    np.testing.assert_allclose(
        bhm.second_piola_stress(lam, e), bhm.stiffening_bar_law(lam, e)[1] / lam, rtol=1e-13
    )
    green = 1e-7
    lam_e = math.sqrt(1.0 + 2.0 * green)
    assert bhm.second_piola_stress(lam_e, e) / green == pytest.approx(e, rel=1e-5)


def test_stiffening_bar_law_matches_closed_form_energy():
    # W = C0 [(l^5 - 1)/20 - (l - 1)/4]: the brief's formula with (a1, a2) = (5, 1)
    lam = np.array([0.8, 0.95, 1.0, 1.05, 1.2])
    expected = 3.0 * ((lam**5 - 1) / 20.0 + (lam - 1) / (1 * (1 - 5)))
    np.testing.assert_allclose(
        bhm.stiffening_bar_law(lam, 3.0)[0], expected, rtol=1e-12, atol=1e-15
    )


def test_tension_only_ogden_law():
    ogden = OgdenLaw()
    p = np.linspace(1.001, 1.5, 30)
    scalar_fd(lambda q: bhm.tension_only_ogden_law(q, ogden), p)
    w, dw, _ = bhm.tension_only_ogden_law(p, ogden)
    np.testing.assert_allclose(w, ogden_uniaxial_energy(p, ogden), rtol=1e-10)
    np.testing.assert_allclose(dw, ogden_uniaxial_nominal_stress(p, ogden), rtol=1e-12)
    slack = bhm.tension_only_ogden_law(np.array([0.5, 0.9, 0.999999, 1.0]), ogden)
    for arr in slack:
        np.testing.assert_array_equal(arr, 0.0)
    # small-strain modulus 3 mu0 just above the kink
    assert bhm.tension_only_ogden_law(np.array([1.0 + 1e-9]), ogden)[2][0] == pytest.approx(
        3.0 * ogden.shear_modulus, rel=1e-6
    )


def test_enhanced_linear_law():
    k, th0 = 0.7, math.radians(170.0)
    t1, t2 = math.radians(30.0), math.radians(330.0)
    law = lambda th: bhm.enhanced_linear_law(th, th0, k, t1, t2)
    for region in (np.linspace(0.05, 0.5, 9), np.linspace(0.6, 5.6, 9), np.linspace(5.8, 6.23, 9)):
        scalar_fd(law, region)
    mid = np.linspace(t1, t2, 7)
    np.testing.assert_allclose(law(mid)[1], k * (mid - th0), rtol=1e-13)
    # Continuity of psi, M and dM/dtheta at both limits.
    for lim in (t1, t2):
        lo, hi = law(np.array([lim - 1e-10])), law(np.array([lim + 1e-10]))
        for a, b in zip(lo, hi):
            assert a[0] == pytest.approx(b[0], rel=1e-8, abs=1e-9)
    # Barriers: the moment diverges towards 0 and 2 pi (panels cannot pass through each other).
    assert law(np.array([1e-6]))[1][0] < -1e4 * k
    assert law(np.array([2 * math.pi - 1e-6]))[1][0] > 1e4 * k


def test_hinge_stiffness_of_the_published_model():
    # k = 5.5 E tp^3/(12 (Lx + d)/Nx) = 0.698 N mm/(rad mm)
    # (shared/reference/published_reduced_model.md)
    assert bhm.KaptonBarHinge().hinge_stiffness(0.127) == pytest.approx(0.698, abs=5e-4)
    plain = bhm.KaptonBarHinge(bending_factor=1.0).hinge_stiffness(0.127)
    assert plain == pytest.approx(2500 * 0.127**3 / 12 / (37 / 11), rel=1e-12)


def test_lce_rest_fraction_of_the_published_model():
    # published recipes: fraction 0.75 <-> lambda 1.05, 0.95 <-> lambda 1.33
    np.testing.assert_allclose(
        bhm.LCEStripBars().rest_fraction([1.05, 1.33, 1.4]), [0.75, 0.95, 1.0]
    )


# ---------------------------------------------------------------------------- kinematics
def test_dihedral_angle_flat_and_folded():
    xj, xk = np.array([[0.0, 0, 0]]), np.array([[2.0, 0, 0]])
    xi, xl = np.array([[1.0, 1, 0]]), np.array([[1.0, -1, 0]])
    assert bh.dihedral_angle(xj, xk, xi, xl, derivatives=0)[0] == pytest.approx(math.pi)
    for phi in (0.3, 1.2, -0.7):
        wing = np.array([[1.0, math.cos(phi), math.sin(phi)]])
        theta = bh.dihedral_angle(xj, xk, wing, xl, derivatives=0)[0]
        assert theta == pytest.approx(math.pi - phi, abs=1e-14)


def test_dihedral_angle_gradient_and_hessian():
    x = RNG.normal(size=(8, 12))

    def fun(X, d):
        out = bh.dihedral_angle(X[:, 0:3], X[:, 3:6], X[:, 6:9], X[:, 9:12], derivatives=d)
        return out

    assert_derivatives_match_fd(fun, x)
    # rigid motions leave theta unchanged: the gradient is orthogonal to translations
    g = fun(x, 1)[1]
    np.testing.assert_allclose(g.reshape(8, 4, 3).sum(axis=1), 0.0, atol=1e-12)


def test_bar_element_derivatives():
    x = RNG.normal(size=(6, 6)) + np.array([0, 0, 0, 3.0, 0, 0])
    rest = np.full(6, 2.5)
    vol = RNG.uniform(0.5, 2.0, size=6)
    laws = [lambda l: bhm.stiffening_bar_law(l, 100.0), lambda l: bhm.tension_only_ogden_law(l)]
    for law in laws:
        assert_derivatives_match_fd(
            lambda X, d: bh.bar_element(X[:, :3], X[:, 3:], rest, vol, law, derivatives=d), x
        )


def test_hinge_element_derivatives():
    x = RNG.normal(size=(6, 12))
    rest = np.full(6, 2.5)

    def law(th):
        return bhm.enhanced_linear_law(th, rest, 0.7)

    assert_derivatives_match_fd(
        lambda X, d: bh.hinge_element(
            X[:, 0:3], X[:, 3:6], X[:, 6:9], X[:, 9:12], np.full(6, 3.0), law, derivatives=d
        ),
        x,
    )


def test_point_plane_gap_and_contact_derivatives():
    x = RNG.normal(size=(8, 12))
    assert_derivatives_match_fd(
        lambda X, d: bh.point_plane_gap(X[:, 0:3], X[:, 3:6], X[:, 6:9], X[:, 9:12], derivatives=d),
        x,
    )
    g0 = bh.point_plane_gap(x[:, 0:3], x[:, 3:6], x[:, 6:9], x[:, 9:12], derivatives=0)
    rest = g0 + np.where(np.arange(8) % 2 == 0, 0.3, -0.3)  # half in contact, half free
    out = bh.unilateral_contact_element(x[:, 0:3], x[:, 3:6], x[:, 6:9], x[:, 9:12], rest, 2.0)
    assert np.all(out[0][1::2] == 0.0) and np.all(out[0][0::2] > 0.0)
    assert_derivatives_match_fd(
        lambda X, d: bh.unilateral_contact_element(
            X[:, 0:3], X[:, 3:6], X[:, 6:9], X[:, 9:12], rest, 2.0, derivatives=d
        ),
        x,
    )


def test_point_plane_gap_value():
    a, b, c = np.array([[0.0, 0, 0]]), np.array([[0.0, 1, 0]]), np.array([[1.0, 0, 0]])
    p = np.array([[0.3, 0.4, 0.7]])
    assert bh.point_plane_gap(p, a, b, c, derivatives=0)[0] == pytest.approx(0.7)  # normal +z


# ---------------------------------------------------------------------------- N5B8 calibration
@pytest.mark.parametrize("width,height", [(3.0, 3.0), (2.5, 3.5)])
def test_n5b8_areas_reproduce_plane_stress_stretching_energy(width, height):
    """Filipov et al. 2017: the bars' energy under homogeneous strain (e_x, e_y) equals the plane
    stress energy t W H E/(2 (1 - nu^2)) (e_x^2 + e_y^2 + 2 nu e_x e_y) when nu W^2 <= H^2, nu H^2
    <= W^2."""
    t, e_mod, nu = 0.127, 2500.0, 0.34
    a_w, a_h, a_s = bh.n5b8_bar_areas(width, height, t, nu)
    diag = math.hypot(width, height)
    cx, cy = width / diag, height / diag
    for ex, ey in ((1e-3, 0.0), (0.0, 1e-3), (1e-3, -4e-4), (2e-4, 7e-4)):
        bars = (
            2 * 0.5 * e_mod * a_w * width * ex**2
            + 2 * 0.5 * e_mod * a_h * height * ey**2
            + 4 * 0.5 * e_mod * a_s * (diag / 2) * (cx**2 * ex + cy**2 * ey) ** 2
        )
        plate = 0.5 * t * width * height * e_mod / (1 - nu**2) * (ex**2 + ey**2 + 2 * nu * ex * ey)
        assert bars == pytest.approx(plate, rel=1e-12)
