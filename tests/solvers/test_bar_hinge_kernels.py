"""The compiled hinge kernel against the models' definition (dihedral_angle, hinge_element)."""

import numpy as np

from lcefem.models import bar_hinge as law
from lcefem.models import bar_hinge_materials as bhm
from lcefem.solvers.bar_hinge.kernels import hinge_forces


def test_hinge_kernel_matches_hinge_element():
    rng = np.random.default_rng(7)
    n = 200
    xj, xk = rng.normal(size=(n, 3)), rng.normal(size=(n, 3))
    xi, xl = rng.normal(size=(n, 3)), rng.normal(size=(n, 3))
    length = rng.uniform(0.5, 2.0, n)
    rest, k = rng.uniform(2.0, 4.0, n), rng.uniform(0.1, 1.0, n)

    def spring(theta):
        return bhm.enhanced_linear_law(theta, rest, k, np.radians(30.0), np.radians(330.0))

    _, grad_ref, hess_ref = law.hinge_element(xj, xk, xi, xl, length, spring)
    theta = law.dihedral_angle(xj, xk, xi, xl, derivatives=0)
    _, moment, dmoment = spring(theta)
    grad, hess = np.empty((n, 12)), np.empty((n, 12, 12))
    hinge_forces(xj, xk, xi, xl, length * moment, length * dmoment, grad, hess)
    scale_g = np.max(np.abs(grad_ref), axis=1, keepdims=True)
    scale_h = np.max(np.abs(hess_ref), axis=(1, 2), keepdims=True)
    assert np.max(np.abs(grad - grad_ref) / scale_g) < 1e-12
    assert np.max(np.abs(hess - hess_ref) / scale_h) < 1e-11
    assert np.array_equal(hess, np.swapaxes(hess, 1, 2))


def _random_panels(rng, n):
    """n flat-ish N5B8 panels (centre, corners 0..3 in cyclic order) with random displacements."""
    corners = np.array([[0.0, 0.0, 0.0], [2.3, 0.0, 0.0], [2.3, 7.0, 0.0], [0.0, 7.0, 0.0]])
    x = np.concatenate([corners.mean(axis=0, keepdims=True), corners])
    return [x[s] + 0.3 * rng.normal(size=(n, 3)) for s in range(5)]


def test_panel_kernel_matches_panel_bending_element():
    """The model's panel block (compiled kernel) against law.panel_bending_element."""
    from lcefem.solvers.bar_hinge.model import BarHingeModel

    rng = np.random.default_rng(11)
    n = 100
    xs = _random_panels(rng, n)
    flat = _random_panels(np.random.default_rng(12), n)
    rest = np.stack(
        [
            law.dihedral_angle(*(flat[q] for q in law.SPOKE_SLOTS[m]), derivatives=0)
            for m in range(4)
        ],
        axis=1,
    )
    lengths, stiffness = rng.uniform(3.0, 4.0, (n, 4)), rng.uniform(0.1, 0.7, n)
    block = {"lengths": lengths, "rest": rest, "stiffness": stiffness}
    e_ref, g_ref, h_ref = law.panel_bending_element(*xs, lengths, rest, stiffness)
    energy, grad, hess = BarHingeModel._panels(block, xs, 2, None)
    assert np.array_equal(energy, e_ref)
    assert np.max(np.abs(grad - g_ref)) < 1e-12 * np.max(np.abs(g_ref))
    assert np.max(np.abs(hess - h_ref)) < 1e-11 * np.max(np.abs(h_ref))
    assert np.max(np.abs(hess - np.swapaxes(hess, 1, 2))) < 1e-13 * np.max(np.abs(h_ref))


def test_strip_beam_kernel_matches_strip_beam_element():
    """The compiled strip-beam kernel against law.strip_beam_element."""
    from lcefem.solvers.bar_hinge.kernels import BEAM_SLOT_TABLE, strip_beam_forces

    rng = np.random.default_rng(13)
    n = 100
    base = np.array([[0, 0, 0], [0, 1, 0], [-1, 0, 0.2], [3, 0, 0], [3, 1, 0], [4, 0, 0.2]], float)
    xs = [base[s] + 0.2 * rng.normal(size=(n, 3)) for s in range(6)]
    c = rng.uniform(0.5, 2.0, n)
    rest_a = law.dihedral_angle(*(base[s][None] for s in (0, 1, 2, 3)), derivatives=0)
    rest_b = law.dihedral_angle(*(base[s][None] for s in (3, 4, 5, 0)), derivatives=0)
    rest_a, rest_b = np.full(n, rest_a[0]), np.full(n, rest_b[0])
    _, g_ref, h_ref = law.strip_beam_element(*xs, c, rest_a, rest_b)
    th_a = law.dihedral_angle(xs[0], xs[1], xs[2], xs[3], derivatives=0)
    th_b = law.dihedral_angle(xs[3], xs[4], xs[5], xs[0], derivatives=0)
    d_a = np.mod(th_a - rest_a + np.pi, 2.0 * np.pi) - np.pi
    d_b = np.mod(th_b - rest_b + np.pi, 2.0 * np.pi) - np.pi
    grad, hess = np.empty((n, 18)), np.empty((n, 18, 18))
    strip_beam_forces(
        np.stack(xs), c, c * (2 * d_a + d_b), c * (d_a + 2 * d_b), BEAM_SLOT_TABLE, grad, hess
    )
    assert np.max(np.abs(grad - g_ref)) < 1e-12 * np.max(np.abs(g_ref))
    assert np.max(np.abs(hess - h_ref)) < 1e-11 * np.max(np.abs(h_ref))
