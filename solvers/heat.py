"""Transient heat conduction in a deforming body, written in its reference configuration.

With X the reference coordinates, F = I + Grad u the deformation (u lagging one step in a staggered
scheme), J = det F and C = F^T F, the energy balance per reference volume is (Holzapfel 2000, Sec.
7.3)

    rho c dT/dt - Div(k J C^-1 Grad T) = q                        in the body,
    -k J C^-1 Grad T . N = (h + h_r(T)) (T - T_a) J |F^-T N|     on exposed surfaces,

where q [mW/mm^3] is the Joule power per reference volume of the coil region, h the convective film
coefficient and h_r the linearised radiation coefficient, evaluated at the previous time level
(semi-implicit; first order, like the backward Euler step). Surfaces not listed as exposed are
adiabatic. Units: mm, s, mW, C.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import dolfinx_solver  # noqa: F401  (orders MPI before dolfinx/petsc4py)
from mpi4py import MPI
from petsc4py import PETSc

import numpy as np
import ufl

import dolfinx
import dolfinx.fem.petsc

from lcefem.meshes._gmsh import TaggedMesh
from lcefem.models.errors import ConvergenceError
from lcefem.models.heat import SurfaceExchange, ThermalProperties, radiative_film_coefficient

LU_OPTIONS = {"ksp_type": "preonly", "pc_type": "lu", "pc_factor_mat_solver_type": "mumps"}


#: relative change below which a fixed-point iteration that has stopped contracting is at its
#: round-off floor (the linear solves' own error): accepted rather than iterated to a tolerance it
#: cannot reach. A stiff body (k = 1000 mW/(mm K) with radiation) flip-flops by 1.6e-8 K at 81 C,
#: above the 1e-10 target and far below any temperature that matters (measured; stop 52).
ROUND_OFF_RTOL = 1e-7


def settled(change: float, last_change: float, scale: float, rtol: float) -> bool:
    """Whether a fixed-point iteration has settled: its change at most ``rtol * scale``, or at its
    round-off floor (at most ``ROUND_OFF_RTOL * scale`` and not smaller than 0.9 x the previous
    change: no longer contracting, so more iterations only exchange round-off)."""
    if change <= rtol * scale:
        return True
    return change <= ROUND_OFF_RTOL * scale and change >= 0.9 * last_change


@dataclass
class HeatSetup:
    """What a heat problem needs besides the mesh: materials, heated regions, exposed faces."""

    thermal: ThermalProperties
    exchange: SurfaceExchange
    heated_cells: list[str] = field(default_factory=list)  # cell names receiving the power density
    exposed_facets: list[str] = field(default_factory=list)
    degree: int = 1
    initial_temperature: float | None = None  # C; ambient when None
    radiation: bool = True
    #: exposed facets with an exchange of their own (film coefficient, emissivity, ambient); the
    #: others use ``exchange`` (``lcefem run body``: convection and radiation per boundary)
    facet_exchange: dict[str, SurfaceExchange] = field(default_factory=dict)
    #: cell sets with thermal properties of their own (density, specific heat, conductivity); the
    #: others use ``thermal`` (``lcefem run body``: a region's own properties)
    cell_thermal: dict[str, ThermalProperties] = field(default_factory=dict)


class HeatProblem:
    """Backward-Euler heat solver on a :class:`TaggedMesh`; forms built once, Constants change in
    loops.

    ``extra_source`` [mW/mm^3] and ``extra_flux`` [mW/mm^2, into the body, on the exposed facets]
    are optional UFL expressions added to the right-hand side (manufactured solutions use them).

    Attributes:
        T: temperature [C] at the new time level (Function, Lagrange of ``setup.degree``).
        T_old: temperature at the previous level.
        power_density: Constant q [mW/mm^3] in the heated cells.
        displacement: the Function u [mm] used for the pull-back (None: rigid body).
    """

    def __init__(
        self,
        tmesh: TaggedMesh,
        setup: HeatSetup,
        *,
        displacement=None,
        extra_source=None,
        extra_flux=None,
        bcs=(),
        petsc_options: dict | None = None,
        prefix: str = "lcefem_heat_",
        quadrature_degree: int = 4,
    ):
        mesh = tmesh.mesh
        self.mesh, self.setup = mesh, setup
        V = dolfinx.fem.functionspace(mesh, ("Lagrange", setup.degree))
        self.V = V
        self.T = dolfinx.fem.Function(V, name="temperature")
        self.T_old = dolfinx.fem.Function(V, name="temperature_old")
        t0 = (
            setup.exchange.ambient_temperature
            if setup.initial_temperature is None
            else setup.initial_temperature
        )
        self.T.x.array[:] = t0
        self.T_old.x.array[:] = t0
        self.inv_dt = dolfinx.fem.Constant(mesh, PETSc.ScalarType(0.0))
        self.power_density = dolfinx.fem.Constant(mesh, PETSc.ScalarType(0.0))
        self.displacement = displacement
        self.bcs = list(
            bcs(V) if callable(bcs) else bcs
        )  # a callable receives the temperature space

        # Material data as Constants: forms compile once; set_materials() changes them
        # (calibration).
        def const(value):
            return dolfinx.fem.Constant(mesh, PETSc.ScalarType(value))

        self._rho_c, self._k = const(0.0), const(0.0)
        self._h, self._eps, self._T_a = const(0.0), const(0.0), const(0.0)
        self._cell_fields = self._cell_properties(tmesh, setup) if setup.cell_thermal else None
        self.set_materials(setup.thermal, setup.exchange)
        rho_c, T_a = self._rho_c, self._T_a
        k = self._k
        if self._cell_fields is not None:  # piecewise constant per cell set (DG0)
            rho_c, k = self._cell_fields["rho_c"], self._cell_fields["k"]
        T, w = ufl.TrialFunction(V), ufl.TestFunction(V)
        # A fixed degree: UFL's estimate for the pulled-back conductivity (rational in Grad u) is
        # huge.
        md = {"quadrature_degree": quadrature_degree}
        dx = ufl.Measure("dx", domain=mesh, subdomain_data=tmesh.cell_tags, metadata=md)
        ds = ufl.Measure("ds", domain=mesh, subdomain_data=tmesh.facet_tags, metadata=md)
        if displacement is not None:
            F = ufl.Identity(3) + ufl.grad(displacement)
            J = ufl.det(F)
            K = k * J * ufl.inv(F.T * F)
            N = ufl.FacetNormal(mesh)
            area_ratio = J * ufl.sqrt(ufl.dot(ufl.inv(F).T * N, ufl.inv(F).T * N))
        else:
            K = k * ufl.Identity(3)
            area_ratio = 1.0
        h_total = self._h
        if setup.radiation:
            h_total = h_total + radiative_film_coefficient(self.T_old, T_a, self._eps)
        a = rho_c * self.inv_dt * T * w * dx + ufl.inner(K * ufl.grad(T), ufl.grad(w)) * dx
        L = rho_c * self.inv_dt * self.T_old * w * dx
        for name in setup.heated_cells:
            L += self.power_density * w * dx(tmesh.cell_tag(name))
        if extra_source is not None:
            L += extra_source * w * dx
        for name in setup.exposed_facets:
            tag = tmesh.facet_tag(name)
            h_f, T_af = h_total, T_a
            own = setup.facet_exchange.get(name)
            if own is not None:  # a boundary with its own exchange: Constants of its own
                h_f, T_af = const(own.film_coefficient), const(own.ambient_temperature)
                if setup.radiation:
                    h_f = h_f + radiative_film_coefficient(self.T_old, T_af, const(own.emissivity))
            a += h_f * area_ratio * T * w * ds(tag)
            L += h_f * area_ratio * T_af * w * ds(tag)
            if (
                extra_flux is not None
            ):  # inward flux [mW/mm^2 reference area] (manufactured solutions)
                L += extra_flux * w * ds(tag)
        options = dict(LU_OPTIONS)
        options.update(petsc_options or {})
        self._problem = dolfinx.fem.petsc.LinearProblem(
            a, L, bcs=self.bcs, u=self.T, petsc_options=options, petsc_options_prefix=prefix
        )
        volume_form = dolfinx.fem.form(1.0 * dx)
        self._volume = mesh.comm.allreduce(dolfinx.fem.assemble_scalar(volume_form), op=MPI.SUM)
        self._mean_form = dolfinx.fem.form(self.T * dx)

    def set_materials(self, thermal: ThermalProperties, exchange: SurfaceExchange) -> None:
        """Change the thermal properties and surface exchange without recompiling the forms (with
        ``setup.cell_thermal``, ``thermal`` is that of the cells outside those sets)."""
        self._rho_c.value = thermal.volumetric_heat_capacity
        self._k.value = thermal.conductivity
        self._h.value = exchange.film_coefficient
        self._eps.value = exchange.emissivity
        self._T_a.value = exchange.ambient_temperature
        if self._cell_fields is not None:
            own = self._cell_fields["own"]
            for key, value in (
                ("rho_c", thermal.volumetric_heat_capacity),
                ("k", thermal.conductivity),
            ):
                f = self._cell_fields[key]
                f.x.array[~own] = value
                f.x.scatter_forward()

    @staticmethod
    def _cell_properties(tmesh: TaggedMesh, setup: HeatSetup) -> dict:
        """DG0 rho c [mJ/(mm^3 K)] and k [mW/(mm K)] with each set of ``setup.cell_thermal`` at its
        own values ("own": the cells that carry them; the rest is set by :meth:`set_materials`)."""
        mesh = tmesh.mesh
        Q = dolfinx.fem.functionspace(mesh, ("DG", 0))
        rho_c = dolfinx.fem.Function(Q, name="volumetric_heat_capacity")
        k = dolfinx.fem.Function(Q, name="conductivity")
        own = np.zeros(rho_c.x.array.size, dtype=bool)
        for name, props in setup.cell_thermal.items():
            cells = tmesh.cell_tags.find(tmesh.cell_tag(name))
            dofs = np.asarray(Q.dofmap.list[cells]).reshape(-1)
            rho_c.x.array[dofs] = props.volumetric_heat_capacity
            k.x.array[dofs] = props.conductivity
            own[dofs] = True
        return {"rho_c": rho_c, "k": k, "own": own}

    def step(self, dt: float) -> None:
        """Advance by dt [s] with backward Euler: T_old <- T, then solve for T."""
        self.T_old.x.array[:] = self.T.x.array
        self.inv_dt.value = 1.0 / dt
        self._solve(where=f"heat step dt = {dt:g} s")

    def steady(self, rtol: float = 1e-10, max_iterations: int = 50) -> int:
        """Steady state (1/dt = 0); Picard iterations on the radiation coefficient. Returns
        iterations."""
        self.inv_dt.value = 0.0
        last = np.inf
        for it in range(1, max_iterations + 1):
            self.T_old.x.array[:] = self.T.x.array
            self._solve(where="steady heat")
            change = self.mesh.comm.allreduce(
                float(np.max(np.abs(self.T.x.array - self.T_old.x.array), initial=0.0)), op=MPI.MAX
            )
            scale = self.mesh.comm.allreduce(
                float(np.max(np.abs(self.T.x.array), initial=0.0)), op=MPI.MAX
            )
            if settled(change, last, max(scale, 1.0), rtol):
                return it
            last = change
        raise ConvergenceError(
            "steady heat", f"Picard iteration did not settle in {max_iterations}"
        )

    def _solve(self, where: str) -> None:
        self._problem.solve()
        reason = self._problem.solver.getConvergedReason()
        if reason <= 0:
            raise ConvergenceError(where, f"linear solver diverged (KSP reason {reason})")
        self.T.x.scatter_forward()

    def mean_temperature(self) -> float:
        """Volume average of T [C] over the reference configuration."""
        total = dolfinx.fem.assemble_scalar(self._mean_form)
        return self.mesh.comm.allreduce(total, op=MPI.SUM) / self._volume

    def max_temperature(self) -> float:
        """Largest nodal temperature [C]."""
        n = self.V.dofmap.index_map.size_local
        return self.mesh.comm.allreduce(
            float(np.max(self.T.x.array[:n], initial=-np.inf)), op=MPI.MAX
        )
