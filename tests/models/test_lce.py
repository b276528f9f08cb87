"""Nematic order, spontaneous stretch and the spontaneous-strain tensor (models/lce.py)."""

import dolfinx_solver  # noqa: F401
from mpi4py import MPI

import numpy as np
import pytest
import ufl

import dolfinx

from lcefem.meshes.block import build_block
from lcefem.models.hyperelastic import LCEElasticity, lce_strain_energy
from lcefem.models.lce import (
    NematicTransition,
    contraction_ratio,
    inverse_spontaneous_deformation,
    order_parameter,
    order_parameter_from_stretch,
    spontaneous_deformation,
    spontaneous_stretch,
)

P = NematicTransition()


def test_reference_temperature_gives_nematic_stretch():
    assert spontaneous_stretch(P.T_ref, P) == pytest.approx(P.lambda_N, rel=1e-14)
    assert contraction_ratio(P.T_ref, P) == pytest.approx(1.0, rel=1e-14)


def test_isotropic_limit_and_monotone_decrease():
    T = np.linspace(0.0, 250.0, 501)
    lam = spontaneous_stretch(T, P)
    assert np.all(np.diff(lam) < 0)
    assert lam[-1] == pytest.approx(1.0, abs=1e-9)  # 250 C: far above T_NI
    assert order_parameter(250.0, P) == pytest.approx(0.0, abs=1e-9)


def test_warner_terentjev_inverse():
    """lambda = ((1 + 2Q)/(1 - Q))^(1/3) and Q(lambda) are inverse (Q ~ 0.37 for 1.4:
    materials.md)."""
    for lam in (1.05, 1.4, 1.628):
        q = order_parameter_from_stretch(lam)
        assert ((1 + 2 * q) / (1 - q)) ** (1 / 3) == pytest.approx(lam, rel=1e-14)
    assert order_parameter_from_stretch(1.4) == pytest.approx(0.37, abs=0.01)
    assert order_parameter_from_stretch(1.63) == pytest.approx(0.53, abs=0.01)


def _evaluate(expr, mesh):
    """Value of a spatially constant UFL expression (mean over a unit cube)."""
    form = dolfinx.fem.form(expr * ufl.dx(domain=mesh, metadata={"quadrature_degree": 1}))
    return mesh.comm.allreduce(dolfinx.fem.assemble_scalar(form), op=MPI.SUM)


@pytest.fixture(scope="module")
def cube():
    return build_block((1.0, 1.0, 1.0), (1, 1, 1), "hex").mesh


def test_spontaneous_deformation_is_isochoric_uniaxial(cube):
    T_c = dolfinx.fem.Constant(cube, 0.0)  # Constants: the forms compile once for all cases
    n_c = dolfinx.fem.Constant(cube, np.zeros(3))
    Fs = spontaneous_deformation(T_c, n_c, P)
    Fs_inv = inverse_spontaneous_deformation(T_c, n_c, P)
    eye = Fs * Fs_inv - ufl.Identity(3)
    for T in (25.0, 60.0, 70.0, 90.0, 200.0):
        for n in ((1.0, 0.0, 0.0), (0.0, 0.6, 0.8), (0.48, 0.6, 0.64)):
            T_c.value, n_c.value = T, n
            assert _evaluate(ufl.det(Fs), cube) == pytest.approx(1.0, abs=1e-12)
            assert _evaluate(ufl.inner(eye, eye), cube) == pytest.approx(0.0, abs=1e-24)
            assert _evaluate(ufl.dot(n_c, Fs * n_c), cube) == pytest.approx(
                float(contraction_ratio(T, P)), rel=1e-12
            )


def test_identity_at_reference_temperature(cube):
    n = ufl.as_vector((0.0, 0.6, 0.8))
    diff = spontaneous_deformation(ufl.as_ufl(P.T_ref), n, P) - ufl.Identity(3)
    assert _evaluate(ufl.inner(diff, diff), cube) == pytest.approx(0.0, abs=1e-28)


def test_zero_energy_and_stress_at_rest(cube):
    """W(F_e = I) = 0 and P = dW/dF = 0 at F = F_s (stress-free spontaneous shape) at any
    temperature."""
    n = ufl.as_vector((0.48, 0.6, 0.64))
    for T in (25.0, 75.0):
        F = ufl.variable(spontaneous_deformation(ufl.as_ufl(T), n, P))
        W = lce_strain_energy(
            F * inverse_spontaneous_deformation(ufl.as_ufl(T), n, P), LCEElasticity()
        )
        stress = ufl.diff(W, F)
        assert _evaluate(W, cube) == pytest.approx(0.0, abs=1e-14)
        assert _evaluate(ufl.inner(stress, stress), cube) == pytest.approx(0.0, abs=1e-24)
