"""The LCE strip's bending element (models.bar_hinge.strip_beam_element): closed forms of an
Euler-Bernoulli beam clamped to two end frames, exact derivatives, objectivity."""

import numpy as np
import pytest

from lcefem.models.bar_hinge import strip_beam_element

L, W, P = 30.0, 5.0, 3.0  # piece length, width across, distance of the frame node [mm]


def piece(phi_a: float, phi_b: float, rotation=np.eye(3)):
    """A straight piece along x (chord fixed) whose end frames are rotated by phi_a, phi_b [rad]
    about the width axis y, in the same sense; six nodes (a, a2, pa, b, b2, pb), (1, 3) each."""
    a, b = np.zeros(3), np.array([L, 0.0, 0.0])
    t = lambda phi: np.array([np.cos(phi), 0.0, -np.sin(phi)])  # noqa: E731 (rotation about +y)
    nodes = [a, a + (0, W, 0), a - P * t(phi_a), b, b + (0, W, 0), b + P * t(phi_b)]
    return [(rotation @ n)[None, :] for n in nodes]


def rest():
    x = piece(0.0, 0.0)
    from lcefem.models.bar_hinge import dihedral_angle

    return (
        dihedral_angle(x[0], x[1], x[2], x[3], derivatives=0),
        dihedral_angle(x[3], x[4], x[5], x[0], derivatives=0),
    )


@pytest.mark.parametrize("kappa", [1e-3, 0.01, 0.03])
def test_uniform_curvature_stores_EI_kappa2_L_over_2(kappa):
    # A circular arc of curvature kappa through both ends: end tangents at -/+ kappa L/2 from the
    # chord (rotations in opposite senses); U = E I kappa^2 L/2 (Euler-Bernoulli), to O(kappa^2 L^2)
    # of the small-rotation angles (exact here: the dihedral angles are the tangent angles).
    ei = 1.8
    ra, rb = rest()
    x = piece(-kappa * L / 2, kappa * L / 2)
    u = strip_beam_element(*x, np.array([2 * ei / L]), ra, rb, derivatives=0)[0]
    assert u == pytest.approx(ei * kappa**2 * L / 2, rel=1e-9)


def test_end_moments_follow_the_slope_deflection_equations():
    # One end rotated by phi, the other held: M_a = 4 E I phi/L, M_b = 2 E I phi/L (carry-over 1/2).
    ei, phi = 1.8, 0.02
    ra, rb = rest()
    c = np.array([2 * ei / L])
    u = lambda pa, pb: strip_beam_element(*piece(pa, pb), c, ra, rb, derivatives=0)[0]  # noqa: E731
    h = 1e-5
    m_a = (u(phi + h, 0.0) - u(phi - h, 0.0)) / (2 * h)
    m_b = (u(phi, h) - u(phi, -h)) / (2 * h)
    assert m_a == pytest.approx(4 * ei * phi / L, rel=1e-6)
    assert m_b == pytest.approx(2 * ei * phi / L, rel=1e-6)


def test_rigid_motion_stores_nothing():
    ra, rb = rest()
    th = 0.7
    rot = np.array(
        [[np.cos(th), -np.sin(th), 0], [np.sin(th), np.cos(th), 0], [0, 0, 1]]
    ) @ np.array([[1, 0, 0], [0, np.cos(1.1), -np.sin(1.1)], [0, np.sin(1.1), np.cos(1.1)]])
    e, g, _ = strip_beam_element(*piece(0.0, 0.0, rot), np.array([0.12]), ra, rb)
    assert abs(e[0]) < 1e-24 and np.abs(g).max() < 1e-12


def test_gradient_and_hessian_match_finite_differences():
    rng = np.random.default_rng(3)
    x0 = np.concatenate(piece(0.1, -0.05), axis=0) + 0.3 * rng.normal(size=(6, 3))
    c, ra, rb = np.array([0.4]), np.array([3.0]), np.array([3.3])

    def f(v):
        return strip_beam_element(
            *(v.reshape(6, 3)[k][None] for k in range(6)), c, ra, rb, derivatives=1
        )

    _, g, h = strip_beam_element(*(x0[k][None] for k in range(6)), c, ra, rb)
    v0, eps = x0.ravel(), 1e-6
    gfd, hfd = np.zeros(18), np.zeros((18, 18))
    for i in range(18):
        vp, vm = v0.copy(), v0.copy()
        vp[i] += eps
        vm[i] -= eps
        (ep, gp), (em, gm) = f(vp), f(vm)
        gfd[i] = (ep[0] - em[0]) / (2 * eps)
        hfd[:, i] = (gp[0] - gm[0]) / (2 * eps)
    assert np.allclose(gfd, g[0], atol=1e-7 * np.abs(g).max())
    assert np.allclose(hfd, h[0], atol=1e-6 * np.abs(h).max())
