"""Staggered thermo-mechanics of LCE bodies: heat step -> temperature field -> F_s(T) -> mechanics.

Each time step first advances the heat equation (pulled back with the last converged displacement),
then brings the mechanical equilibrium from the old to the new temperature field with the shared
step controller (:class:`lcefem.solvers.continuation.PathFollower`): T_mech = T_old + s (T_new -
T_old), s: 0 -> 1, tangent predictor, halving s on a failed Newton solve.

The LCE's elastic energy is W(F_e) with F_e = F F_s(T)^-1 (models.lce, models.hyperelastic); because
det F_s = 1 the energy per reference volume needs no Jacobian factor. Passive regions (Kapton) use a
compressible neo-Hookean energy.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import dolfinx_solver  # noqa: F401  (orders MPI before dolfinx/petsc4py)
from petsc4py import PETSc

import numpy as np

import dolfinx

from lcefem.meshes._gmsh import TaggedMesh
from lcefem.models.errors import InputError
from lcefem.models.hyperelastic import (
    LCEElasticity,
    NeoHookeanSolid,
    lce_strain_energy,
    neo_hookean_strain_energy,
)
from lcefem.models.lce import (
    MeasuredContraction,
    NematicTransition,
    inverse_spontaneous_deformation,
    isochoric_uniaxial,
)
from lcefem.solvers import continuation
from lcefem.solvers.heat import HeatProblem, HeatSetup
from lcefem.solvers.mechanics import (
    HyperelasticProblem,
    deformation_gradient,
    displacement_space,
    volume_measure,
)


@dataclass
class LCERegion:
    """Cells made of LCE with director field ``director`` (a UFL unit vector in reference
    coordinates). ``stretch`` (None: the temperature's) is a prescribed spontaneous stretch relative
    to the as-built state, a = lambda / lambda_N [-] (a UFL scalar, e.g. a Constant a ramp changes):
    the energy is then W(F U(1/a)) whatever the temperature (the composite beam's prescribed
    lambdas)."""

    cells: Sequence[str]
    director: object
    transition: NematicTransition | MeasuredContraction = field(default_factory=NematicTransition)
    elasticity: LCEElasticity = field(default_factory=LCEElasticity)
    stretch: object = None


@dataclass
class PassiveRegion:
    cells: Sequence[str]
    solid: NeoHookeanSolid = field(default_factory=NeoHookeanSolid)


def lce_energy_density(u, T, region: LCERegion):
    """W(F F_s(T)^-1) [mJ/mm^3] for displacement u and temperature T (UFL)."""
    F = deformation_gradient(u)
    Fe = F * inverse_spontaneous_deformation(T, region.director, region.transition)
    return lce_strain_energy(Fe, region.elasticity)


class ThermoMechanicalModel:
    """Heat + finite-strain mechanics on one tagged mesh, built once and stepped in time.

    Args:
        tmesh: mesh with named cell and facet tags.
        heat_setup: thermal materials, heated cells, exposed facets, element degree.
        lce: LCE regions; passive: passive regions (every cell must belong to one region).
        dirichlet: ``f(V) -> list[DirichletBC]`` building the displacement conditions.
        external_work: ``f(u) -> UFL form`` of the work of dead loads [mJ] (None: none).
        degree: displacement degree (2: P2/Q2).
        heat_source: extra heat source [mW/mm^3] (UFL, e.g. a DG0 Function of coil power densities).
        heat_bcs: fixed temperatures, DirichletBCs or ``f(V_T) -> list`` (HeatProblem's ``bcs``).
    """

    def __init__(
        self,
        tmesh: TaggedMesh,
        heat_setup: HeatSetup,
        lce: Sequence[LCERegion],
        passive: Sequence[PassiveRegion] = (),
        dirichlet: Callable[[dolfinx.fem.FunctionSpace], list] = lambda V: [],
        external_work: Callable | None = None,
        *,
        degree: int = 2,
        petsc_options: dict | None = None,
        prefix: str = "lcefem_",
        heat_source=None,
        heat_bcs=(),
    ):
        self.tmesh = tmesh
        V = displacement_space(tmesh.mesh, degree)
        self.u = dolfinx.fem.Function(V, name="displacement")
        self.heat = HeatProblem(
            tmesh,
            heat_setup,
            displacement=self.u,
            extra_source=heat_source,
            bcs=heat_bcs,
            prefix=f"{prefix}heat_",
        )
        # The temperature the mechanics sees; stepped from T_old to T by continuation.
        self.T_mech = dolfinx.fem.Function(self.heat.V, name="temperature_mechanics")
        self.T_mech.x.array[:] = self.heat.T.x.array
        dx = volume_measure(tmesh)
        energy = 0
        # Transition and elasticity parameters enter the forms as Constants (compiled once,
        # changeable).
        self._constants: list[tuple[LCERegion, dict, dict]] = []
        for region in lce:
            # a measured curve's rows are compiled into the form as literals (a chain of
            # conditionals)
            measured = isinstance(region.transition, MeasuredContraction)
            tc = (
                {}
                if measured
                else {
                    f.name: dolfinx.fem.Constant(
                        tmesh.mesh, PETSc.ScalarType(getattr(region.transition, f.name))
                    )
                    for f in dataclasses.fields(region.transition)
                }
            )
            ec = {
                f.name: dolfinx.fem.Constant(
                    tmesh.mesh, PETSc.ScalarType(getattr(region.elasticity, f.name))
                )
                for f in dataclasses.fields(region.elasticity)
            }
            self._constants.append((region, tc, ec))
            symbolic = LCERegion(
                region.cells,
                region.director,
                region.transition if measured else dataclasses.replace(region.transition, **tc),
                dataclasses.replace(region.elasticity, **ec),
            )
            if region.stretch is not None:
                W = lce_strain_energy(
                    deformation_gradient(self.u)
                    * isochoric_uniaxial(1.0 / region.stretch, region.director),
                    symbolic.elasticity,
                )
            else:
                W = lce_energy_density(self.u, self.T_mech, symbolic)
            energy += W * dx(tuple(tmesh.cell_tag(c) for c in region.cells))
        for region in passive:
            W = neo_hookean_strain_energy(deformation_gradient(self.u), region.solid)
            energy += W * dx(tuple(tmesh.cell_tag(c) for c in region.cells))
        if external_work is not None:
            energy -= external_work(self.u)
        self.bcs = dirichlet(V)
        self.mechanics = HyperelasticProblem(
            self.u,
            energy,
            self.bcs,
            prefix=f"{prefix}mech_",
            petsc_options=petsc_options,
            user_options=tuple(petsc_options or ()),
        )
        self.lce_regions = list(lce)

    def set_lce_parameters(
        self,
        index: int,
        transition: NematicTransition | None = None,
        elasticity: LCEElasticity | None = None,
    ) -> None:
        """Change the transition/elasticity of LCE region ``index`` without recompiling the
        forms."""
        region, tc, ec = self._constants[index]
        if transition is not None and not tc:
            raise InputError(
                f"LCE region {index}: its law is a measured contraction curve (compiled into the "
                "forms); allowed only elasticity changes"
            )
        for params, consts in ((transition, tc), (elasticity, ec)):
            if params is not None:
                for name, c in consts.items():
                    c.value = getattr(params, name)

    #: Stepping of each mechanics update: the whole temperature increment first (tangent predictor),
    #: halved on failure down to 1/256 of it.
    path_control = continuation.PathControl(first_step=1.0, max_step=1.0, min_step=1.0 / 256.0)

    def step(self, dt: float, where: str) -> continuation.StepReport:
        """Advance heat by dt [s], then mechanics to the new temperature (step cutting on
        failure)."""
        self.heat.step(dt)
        return self.equilibrate(where)

    def equilibrate(self, where: str) -> continuation.StepReport:
        """Bring the mechanics from the temperature it last saw to the current heat temperature."""
        follower = temperature_path(
            self.mechanics, self.T_mech, self.heat.T.x.array, self.path_control
        )
        follower.follow(1.0, where)
        return follower.report()


def temperature_path(
    mechanics, T_mech, T_end, control: continuation.PathControl, damping=None
) -> continuation.PathFollower:
    """A path follower that takes the mechanics from the temperature ``T_mech`` holds now to
    ``T_end`` [C] (copied): T_mech = T_start + s (T_end - T_start), s: 0 -> 1, cut on failure;
    ``follow(1.0, where)`` runs it."""
    T_start = T_mech.x.array.copy()
    T_end = np.array(T_end, dtype=float, copy=True)

    def set_load(s: float) -> None:
        T_mech.x.array[:] = T_start + s * (T_end - T_start)

    return continuation.PathFollower(mechanics, set_load, control, damping)


class TemperatureFollower:
    """Staggered time step of a heat problem and a mechanics problem that sees the temperature
    ``T_mech``: one backward-Euler heat step of dt, then the mechanics brought from the old to the
    new temperature, T_mech = T_old + s (T_new - T_old), with the shared step controller
    (:class:`lcefem.solvers.continuation.PathFollower`, load parameter = time, tangent predictor in
    time, step cutting, damped relaxation across folds). Used by the heated FE beam and gridshell.

    Args:
        heat: the :class:`HeatProblem` (its ``T`` at the new level after each step).
        T_mech: Function of the temperature the mechanics' forms use.
        mechanics: the Newton problem.
        control: stepping (first_step, max_step in seconds of simulated time).
        damping: proximal term for the relaxation across folds (or None).
    """

    def __init__(
        self, heat: HeatProblem, T_mech, mechanics, control: continuation.PathControl, damping=None
    ):
        self.heat, self.T_mech = heat, T_mech
        self._span = {
            "T0": T_mech.x.array.copy(),
            "T1": T_mech.x.array.copy(),
            "t0": 0.0,
            "dt": 1.0,
        }
        self.follower = continuation.PathFollower(mechanics, self._set_load, control, damping)
        self.time = 0.0  # [s]

    def _set_load(self, t: float) -> None:
        span = self._span
        s = (t - span["t0"]) / span["dt"]
        self.T_mech.x.array[:] = span["T0"] + s * (span["T1"] - span["T0"])

    def advance(self, dt: float, where: str) -> int:
        """Heat step of ``dt`` [s], then the mechanics to the new temperature; returns the
        step's Newton iterations. Raises ConvergenceError (last converged state kept)."""
        t1 = self.time + dt
        self._span.update(T0=self.T_mech.x.array.copy(), t0=self.time, dt=dt)
        self.heat.step(dt)
        self._span["T1"] = self.heat.T.x.array.copy()
        before = self.follower.iterations
        self.follower.step = min(self.follower.step, dt)
        self.follower.follow(t1, where=where)
        self.time = t1
        return self.follower.iterations - before
