"""The virtual tension specimen of the LCE (a material test with the 3D FE model).

Isotropic-phase tension (seed 001 Fig. 2E): an LCE block with its director along x, uniformly far
above T_NI so that it has contracted to its isotropic shape, is stretched along x by a prescribed
end displacement; symmetry planes x = 0, y = 0, z = 0, free lateral faces. Stretch and nominal
stress are measured from the isotropic (natural) state, as in the paper: stretch = current length /
isotropic length, nominal stress = axial force / isotropic cross-section.
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401  (orders MPI before dolfinx/petsc4py)
from mpi4py import MPI
from petsc4py import PETSc

import numpy as np
import ufl

import dolfinx

from lcefem.meshes.block import build_block
from lcefem.models.hyperelastic import LCEElasticity
from lcefem.models.lce import NematicTransition, contraction_ratio
from lcefem.solvers import continuation
from lcefem.solvers.mechanics import (
    HyperelasticProblem,
    assemble_global,
    displacement_space,
    volume_measure,
)
from lcefem.solvers.supports import mirror_planes
from lcefem.solvers.thermomechanics import LCERegion, lce_energy_density

ISOTROPIC_TEMPERATURE = 200.0  # C: Q(200 C) < 1e-9, fully isotropic for the calibrated transition


def isotropic_tension(
    stretches,
    transition: NematicTransition = NematicTransition(),
    elasticity: LCEElasticity = LCEElasticity(),
    cell: str = "hex",
    divisions=(2, 2, 2),
    comm: MPI.Comm | None = None,
) -> np.ndarray:
    """Nominal stress [MPa] at each stretch [-] (from the isotropic length), loading
    monotonically."""
    tm = build_block((1.0, 1.0, 1.0), divisions, cell, comm)
    mesh = tm.mesh
    V = displacement_space(mesh, 2)
    u = dolfinx.fem.Function(V, name="displacement")
    a = float(contraction_ratio(ISOTROPIC_TEMPERATURE, transition))
    end = dolfinx.fem.Constant(mesh, PETSc.ScalarType(a - 1.0))  # u_x on x = 1: natural length a
    fdim = mesh.topology.dim - 1

    def dofs(face, comp):
        return dolfinx.fem.locate_dofs_topological(
            V.sub(comp), fdim, tm.facet_tags.find(tm.facet_tag(face))
        )

    bcs = mirror_planes(tm, V, (("x0", 0), ("y0", 1), ("z0", 2)))
    bcs.append(dolfinx.fem.dirichletbc(end, dofs("x1", 0), V.sub(0)))
    region = LCERegion(["body"], ufl.as_vector([1.0, 0.0, 0.0]), transition, elasticity)
    T = dolfinx.fem.Constant(mesh, PETSc.ScalarType(ISOTROPIC_TEMPERATURE))
    energy = lce_energy_density(u, T, region) * volume_measure(tm)
    problem = HyperelasticProblem(u, energy, bcs, prefix=f"tension_{cell}_")
    # Start from the free isotropic shape (exact: homogeneous contraction).
    u.interpolate(
        lambda X: np.vstack([(a - 1.0) * X[0], (a**-0.5 - 1.0) * X[1], (a**-0.5 - 1.0) * X[2]])
    )
    weight = dolfinx.fem.Function(V)
    weight.x.array[dofs("x1", 0)] = 1.0
    reaction = problem.reaction_form(weight)
    isotropic_area = 1.0 / a  # lateral natural stretch a^-1/2 in each direction
    stresses = []
    current = 1.0
    for lam in stretches:
        start = current

        def set_load(s, start=start, lam=lam):
            end.value = a * (start + s * (lam - start)) - 1.0

        continuation.advance(
            set_load,
            problem.solve,
            problem.save,
            problem.restore,
            where=f"isotropic tension at stretch {lam:.3f}",
        )
        current = lam
        stresses.append(assemble_global(reaction, mesh.comm) / isotropic_area)
    return np.array(stresses)
