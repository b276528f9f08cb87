"""Quasi-static finite-strain elasticity: minimise Pi(u) = sum_r int W_r(F) dV - W_ext(u).

The residual R(u; v) = dPi/du [v] and its Jacobian are derived by UFL from the energy, so every
material law enters only through its strain energy density (mJ/mm^3). PETSc SNES (Newton with a
backtracking line search, MUMPS LU) solves each load step; the caller cuts steps on failure
(:mod:`lcefem.solvers.continuation`).
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401  (orders MPI before dolfinx/petsc4py)
import numpy as np
import ufl
from mpi4py import MPI
from petsc4py import PETSc

import dolfinx
import dolfinx.fem.petsc

from lcefem.meshes._gmsh import TaggedMesh
from lcefem.solvers.run import raise_if_interrupted

#: Quadrature degree for hyperelastic forms: UFL's own estimate for an energy with an inverse
#: spontaneous deformation asks for enormous tables (70 GiB seen); 4 integrates P2/Q2 stiffness well.
QUADRATURE_DEGREE = 4

NEWTON_OPTIONS = {
    "snes_type": "newtonls",
    "snes_linesearch_type": "cp",  # critical-point search: R is the gradient of Pi
    "snes_rtol": 1e-10,
    "snes_atol": 1e-9,  # N: nodal force residual
    "snes_stol": 0.0,
    "snes_max_it": 25,
    "ksp_type": "preonly",
    "pc_type": "lu",
    "pc_factor_mat_solver_type": "mumps",
}


def displacement_space(mesh: dolfinx.mesh.Mesh, degree: int = 2) -> dolfinx.fem.FunctionSpace:
    """Vector Lagrange space (P2 on tetrahedra, Q2 on hexahedra by default) for u [mm]."""
    return dolfinx.fem.functionspace(mesh, ("Lagrange", degree, (mesh.geometry.dim,)))


def volume_measure(tmesh: TaggedMesh, degree: int = QUADRATURE_DEGREE) -> ufl.Measure:
    """dx with the cell tags and a fixed quadrature degree."""
    return ufl.Measure("dx", domain=tmesh.mesh, subdomain_data=tmesh.cell_tags,
                       metadata={"quadrature_degree": degree})


def surface_measure(tmesh: TaggedMesh, degree: int = QUADRATURE_DEGREE) -> ufl.Measure:
    return ufl.Measure("ds", domain=tmesh.mesh, subdomain_data=tmesh.facet_tags,
                       metadata={"quadrature_degree": degree})


def deformation_gradient(u) -> ufl.core.expr.Expr:
    """F = I + Grad u (reference configuration = mesh)."""
    return ufl.Identity(len(u)) + ufl.grad(u)


class HyperelasticProblem:
    """Newton solver for the stationary points of an energy functional ``energy`` (UFL rank-0 form).

    Args:
        u: displacement Function [mm] (its values are the initial guess and receive the solution).
        energy: Pi(u) as a UFL form [mJ], e.g. ``W(F) * dx - dot(t, u) * ds``.
        bcs: Dirichlet conditions (their values may change between solves).
        prefix: PETSc options prefix, unique per problem.
        petsc_options: overrides of :data:`NEWTON_OPTIONS`.
    """

    def __init__(self, u: dolfinx.fem.Function, energy: ufl.Form, bcs=(), *,
                 prefix: str = "lcefem_mech_", petsc_options: dict | None = None):
        self.u = u
        V = u.function_space
        self.test = ufl.TestFunction(V)
        self.residual = ufl.derivative(energy, u, self.test)
        jacobian = ufl.derivative(self.residual, u, ufl.TrialFunction(V))
        options = dict(NEWTON_OPTIONS)
        options.update(petsc_options or {})
        self._problem = dolfinx.fem.petsc.NonlinearProblem(
            self.residual, u, bcs=list(bcs), J=jacobian, petsc_options=options,
            petsc_options_prefix=prefix)
        self.energy_form = dolfinx.fem.form(energy)
        self.last_iterations = 0

    @property
    def snes(self):
        return self._problem.solver

    def solve(self) -> tuple[bool, int, str]:
        """One Newton solve from the current u. Returns (converged, iterations, reason text)."""
        try:
            self._problem.solve()
        except PETSc.Error as exc:  # e.g. a factorisation failure
            raise_if_interrupted(exc)  # Ctrl-C inside a PETSc callback is not a failed solve
            return False, self.snes.getIterationNumber(), f"PETSc error {exc}"
        reason = self.snes.getConvergedReason()
        its = self.snes.getIterationNumber()
        self.last_iterations = its
        self.u.x.scatter_forward()
        ok = reason > 0 and bool(np.all(np.isfinite(self.u.x.array)))
        return ok, its, f"SNES reason {reason} ({_snes_reason_name(reason)}) after {its} iterations"

    def save(self) -> np.ndarray:
        return self.u.x.array.copy()

    def restore(self, state: np.ndarray) -> None:
        self.u.x.array[:] = state
        self.u.x.scatter_forward()

    def total_energy(self) -> float:
        """Pi(u) [mJ]."""
        comm = self.u.function_space.mesh.comm
        return comm.allreduce(dolfinx.fem.assemble_scalar(self.energy_form), op=MPI.SUM)

    def reaction_form(self, weight: dolfinx.fem.Function) -> dolfinx.fem.Form:
        """Compiled R(u; weight): with ``weight`` equal to a unit vector on the dofs of a constrained
        face and 0 elsewhere, this is the force [N] the body exerts on that face's support."""
        return dolfinx.fem.form(ufl.replace(self.residual, {self.test: weight}))


def assemble_global(form: dolfinx.fem.Form, comm: MPI.Comm) -> float:
    return comm.allreduce(dolfinx.fem.assemble_scalar(form), op=MPI.SUM)


def _snes_reason_name(reason: int) -> str:
    for name in dir(PETSc.SNES.ConvergedReason):
        if not name.startswith("_") and getattr(PETSc.SNES.ConvergedReason, name) == reason:
            return name
    return "unknown"
