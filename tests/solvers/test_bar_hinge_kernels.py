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
