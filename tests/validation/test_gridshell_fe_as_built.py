"""Zero actuation leaves the FE gridshell as built: with every strip at lambda = lambda_N the
residual of the FE beam's energy (Kapton neo-Hookean, LCE W(F U(a)^-1) with a = lambda/lambda_N
along each strip's own direction, passive pads and glue) vanishes at u = 0 on the quarter model,
level 0; one channel actuated, it does not."""

import dolfinx_solver  # noqa: F401

import numpy as np
import pytest
import ufl

import dolfinx

from lcefem.meshes.composite_beam import CompositeBeamGeometry
from lcefem.meshes.gridshell_fe import GridshellFEMesh, build_gridshell_fe, cell_group
from lcefem.models.bar_hinge_materials import PUBLISHED_LAMBDA_N
from lcefem.models.hyperelastic import lce_strain_energy, neo_hookean_strain_energy
from lcefem.models.lce import isochoric_uniaxial
from lcefem.solvers.mechanics import deformation_gradient, displacement_space, volume_measure
from lcefem.solvers.problems.composite_beam import FEMaterials


@pytest.fixture(scope="module")
def model():
    """Quarter gridshell with per-cell stretch a and director n (DG0), residual form compiled
    once."""
    tm = build_gridshell_fe(
        CompositeBeamGeometry(),
        PUBLISHED_LAMBDA_N,
        GridshellFEMesh(level=0),
        cells=3,
        symmetry="quarter",
    )
    V = displacement_space(tm.mesh, 2)
    u = dolfinx.fem.Function(V)
    a = dolfinx.fem.Function(dolfinx.fem.functionspace(tm.mesh, ("DG", 0)))
    director = dolfinx.fem.Function(dolfinx.fem.functionspace(tm.mesh, ("DG", 0, (3,))))
    materials = FEMaterials()
    F = deformation_gradient(u)
    dx = volume_measure(tm)
    energy = (
        neo_hookean_strain_energy(F, materials.kapton) * dx(cell_group(tm, "kapton"))
        + lce_strain_energy(F * isochoric_uniaxial(1.0 / a, director), materials.lce)
        * dx(cell_group(tm, "bottom_strips") + cell_group(tm, "top_strips"))
        + lce_strain_energy(F, materials.lce)
        * dx(cell_group(tm, "bottom_pads") + cell_group(tm, "top_pads") + cell_group(tm, "glue"))
    )
    residual = dolfinx.fem.form(ufl.derivative(energy, u, ufl.TestFunction(V)))
    tags = np.zeros(a.x.array.size, dtype=np.int32)
    tags[tm.cell_tags.indices] = tm.cell_tags.values
    dirs = director.x.array.reshape(-1, 3)
    for channel, axis in (("Bx", 0), ("Tx", 0), ("By", 1), ("Ty", 1)):
        dirs[np.isin(tags, cell_group(tm, channel)), axis] = 1.0  # each strip along its ribbon
    return tm, a, tags, residual


def _residual_norm(residual) -> float:
    return float(np.linalg.norm(dolfinx.fem.assemble_vector(residual).array))


def test_lambda_N_everywhere_is_the_as_built_state(model):
    tm, a, tags, residual = model
    lam_n = tm.info["lambda_N"]
    a.x.array[:] = lam_n / lam_n  # lambda = lambda_N: a = 1
    at_rest = _residual_norm(residual)
    a.x.array[np.isin(tags, cell_group(tm, "Bx"))] = 1.05 / lam_n  # the dome's bottom channel
    actuated = _residual_norm(residual)
    assert actuated > 1e-3  # [N]: a real load
    assert at_rest <= 1e-12 * actuated
