"""Hyperelastic laws (models/hyperelastic.py): closed forms and the published Ogden fit."""

import dolfinx_solver  # noqa: F401
from mpi4py import MPI

import numpy as np
import pytest
import ufl

import dolfinx

from lcefem.meshes.block import build_block
from lcefem.models.hyperelastic import (
    LCEElasticity,
    NeoHookeanSolid,
    OgdenLaw,
    lce_strain_energy,
    lce_uniaxial_nominal_stress,
    neo_hookean_strain_energy,
    ogden_uniaxial_energy,
    ogden_uniaxial_nominal_stress,
)


def test_published_ogden_numbers():
    """Reference file: mu0 = 0.181 MPa; on 10 mm^2 about 0.25 N at 1.05, 0.75 N at 1.2, 1.39 N at
    1.5."""
    assert OgdenLaw().shear_modulus == pytest.approx(0.181, abs=5e-4)
    force = 10.0 * ogden_uniaxial_nominal_stress([1.05, 1.2, 1.5])
    np.testing.assert_allclose(force, [0.25, 0.75, 1.39], atol=0.01)


def test_ogden_stress_is_energy_derivative():
    lam = np.linspace(0.8, 1.6, 9)
    h = 1e-6
    dW = (ogden_uniaxial_energy(lam + h) - ogden_uniaxial_energy(lam - h)) / (2 * h)
    np.testing.assert_allclose(ogden_uniaxial_nominal_stress(lam), dW, rtol=1e-7, atol=1e-10)


def test_fitted_law_within_5_percent_of_ogden():
    """Issue: the uniaxial response must match the published Ogden fit within 5 % for stretch
    1.0-1.5."""
    lam = np.linspace(1.0, 1.5, 101)[1:]
    rel = lce_uniaxial_nominal_stress(lam) / ogden_uniaxial_nominal_stress(lam) - 1.0
    assert np.max(np.abs(rel)) < 0.05
    # and the small-strain moduli agree within the same tolerance: E = 3 mu
    assert 3 * LCEElasticity().shear_modulus == pytest.approx(
        3 * OgdenLaw().shear_modulus, rel=0.05
    )


def _assemble(expr, mesh):
    form = dolfinx.fem.form(expr * ufl.dx(domain=mesh, metadata={"quadrature_degree": 1}))
    return mesh.comm.allreduce(dolfinx.fem.assemble_scalar(form), op=MPI.SUM)


def test_invariant_law_uniaxial_closed_form():
    """The UFL energy under incompressible uniaxial stretch: dW/dlambda equals the closed-form
    stress."""
    mesh = build_block((1.0, 1.0, 1.0), (1, 1, 1), "hex").mesh
    law = LCEElasticity()
    for lam in (1.1, 1.3, 1.5):
        h = 1e-5
        energies = []
        for l in (lam - h, lam + h):
            F = ufl.as_matrix([[l, 0, 0], [0, l**-0.5, 0], [0, 0, l**-0.5]])
            energies.append(_assemble(lce_strain_energy(F, law), mesh))
        assert (energies[1] - energies[0]) / (2 * h) == pytest.approx(
            float(lce_uniaxial_nominal_stress(lam, law)), rel=1e-6
        )


def test_neo_hookean_small_strain_modulus():
    """Uniaxial stress at small strain eps, lateral strain -nu eps: sigma ~ E eps (datasheet E,
    nu)."""
    mesh = build_block((1.0, 1.0, 1.0), (1, 1, 1), "hex").mesh
    solid = NeoHookeanSolid()
    eps, nu = 1e-5, solid.poisson_ratio
    F = ufl.variable(ufl.as_matrix([[1 + eps, 0, 0], [0, 1 - nu * eps, 0], [0, 0, 1 - nu * eps]]))
    P = ufl.diff(neo_hookean_strain_energy(F, solid), F)
    assert _assemble(P[0, 0], mesh) / eps == pytest.approx(solid.youngs_modulus, rel=1e-3)
    assert abs(_assemble(P[1, 1], mesh)) / eps < 1e-3 * solid.youngs_modulus
