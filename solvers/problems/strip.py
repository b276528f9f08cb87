"""A single LCE strip heated by its embedded coil, in 3D finite strain (seed 001, Fig. 2): the
thermo-mechanical strip problem (``lcefem run strip``; CLI glue in
:mod:`lcefem.validation.app.commands.strip`).

Drives: the coil current per strip tag (:meth:`StripSimulation.set_drives`, tag ``coil``; the
current -> power step is :class:`lcefem.models.heat.Coil`), or a prescribed temperature field
(:meth:`StripSimulation.set_temperature`) or spontaneous-stretch field
(:meth:`StripSimulation.set_spontaneous_stretch`): uniform, per cell tag, or a callable of the
reference coordinates. Advance: :meth:`StripSimulation.advance` (one backward-Euler step of the heat
equation, then the mechanics with the one path follower), :meth:`StripSimulation.run` (the whole
transient through the run skeleton).

Free strip: the clamp face (x = 0) cannot move along the axis and its centre lines are held in
symmetry (u_y = 0 on y = W/2, u_z = 0 on z = H/2): no rigid-body motion and no constraint on the
free contraction. Held strip: both end faces fully clamped at the as-built (nematic) length; the
force is the axial reaction at the end face (positive in tension).

The run writes, in --out DIR: history.csv (one row per step), thermal.bp and displacement.bp
(VTX, ParaView), summary.json (resolved configuration, metrics, timings). Files carry a .part
suffix until the run completes; a run that fails keeps the converged steps as *.partial.* and
writes failure.json.
"""

from __future__ import annotations

import pathlib
import time
from collections.abc import Mapping
from dataclasses import dataclass, field

import dolfinx_solver  # noqa: F401  (orders MPI before dolfinx/petsc4py)
from mpi4py import MPI
from petsc4py import PETSc

import numpy as np
import ufl

import dolfinx

from lcefem.meshes.strip import StripGeometry, StripMesh, build_strip_mesh, strip_mesh_counts
from lcefem.models.errors import ConvergenceError, InputError
from lcefem.models.heat import Coil, SurfaceExchange, ThermalProperties
from lcefem.models.hyperelastic import LCEElasticity
from lcefem.models.lce import (
    MeasuredContraction,
    NematicTransition,
    spontaneous_stretch,
    temperature_for_stretch,
)
from lcefem.models.limits import (
    ABSOLUTE_ZERO,
    DECOMPOSITION_TEMPERATURE,
    check_current,
    check_time_step,
    current_param,
)
from lcefem.models.parameters import param
from lcefem.solvers import cost
from lcefem.solvers.contraction_curve import LCECurve, law_summary
from lcefem.solvers.exports import Fields, History
from lcefem.solvers.heat import HeatSetup
from lcefem.solvers.mechanics import assemble_global, surface_measure
from lcefem.solvers.problems.protocol import TIME, StepRecord, copy_arrays, put_arrays
from lcefem.solvers.program import Program
from lcefem.solvers.runner import run as run_door
from lcefem.solvers.runtime.checks import check_config, resolved
from lcefem.solvers.runtime.run import Progress
from lcefem.solvers.supports import (
    clamp_face,
    component_bc,
    mirror_planes,
    nodes_on_line,
    plane_clamp,
)
from lcefem.solvers.thermomechanics import LCERegion, ThermoMechanicalModel

COLUMNS = [
    "time [s]",
    "T_mean [C]",
    "T_max [C]",
    "T_surface [C]",
    "stretch [-]",
    "force [N]",
    "end_area_ratio [-]",
    "newton_iterations [-]",
    "step_cuts [-]",
]
BOUNDARY_CONDITIONS = ("free", "held")


@dataclass(frozen=True)
class StripRun:
    """What the experimenter sets: current, duration, boundary condition."""

    current: float = current_param(
        0.2, "seed 001: 0.1, 0.15, 0.2 A transients; 0.04-0.09 A hold currents"
    )
    duration: float = param(30.0, "s", "seed 001: 0.2 A kept under 30 s", positive=True)
    dt: float = param(0.5, "s", "chosen: time step (backward Euler)", positive=True)
    bc: str = param(
        "free",
        "-",
        "'free' (one end clamped, other free) or 'held' (both ends clamped "
        "at the nematic length; seed 001 Fig. 2D)",
    )
    tip_load: float = param(
        0.0, "N", "dead load on the free end (seed 001 hung an 8.2 g clip: 0.080 N)", minimum=0.0
    )
    output_every: int = param(1, "-", "write fields every n steps", minimum=1)
    steady: bool = param(
        False, "-", "solve the steady state (thermal equilibrium) instead of a transient"
    )


@dataclass(frozen=True)
class StripConfig:
    run: StripRun = field(default_factory=StripRun)
    transition: NematicTransition = field(default_factory=NematicTransition)
    elasticity: LCEElasticity = field(default_factory=LCEElasticity)
    thermal: ThermalProperties = field(default_factory=ThermalProperties)
    exchange: SurfaceExchange = field(default_factory=SurfaceExchange)
    coil: Coil = field(default_factory=Coil)
    geometry: StripGeometry = field(default_factory=StripGeometry)
    mesh: StripMesh = field(default_factory=StripMesh)
    petsc: dict = field(default_factory=dict)
    lce: LCECurve = field(default_factory=LCECurve)

    def law(self) -> NematicTransition | MeasuredContraction:
        """The contraction law: the [transition] sigmoid, or the measured curve of ``lce.curve``
        (its lambda_N then sets the as-built length L_iso lambda_N and the section)."""
        return self.lce.law(self.transition)

    def validated(self) -> "StripConfig":
        check_config(self)
        self.law()  # a bad curve file is an InputError before any mesh
        if self.run.bc not in BOUNDARY_CONDITIONS:
            raise InputError(f"run.bc = {self.run.bc!r}: allowed {', '.join(BOUNDARY_CONDITIONS)}")
        if self.run.dt > self.run.duration:
            raise InputError(
                f"run.dt = {self.run.dt} s: must be <= run.duration = {self.run.duration} s"
            )
        if self.mesh.cell not in ("hex", "tet"):
            raise InputError(f"mesh.cell = {self.mesh.cell!r}: allowed hex, tet")
        if self.run.tip_load and self.run.bc != "free":
            raise InputError("run.tip_load: only with run.bc = 'free'")
        self.estimate().check()
        return self

    def estimate(self) -> cost.Estimate:
        """Steps, cells, DOFs and memory of this run, before the mesh is built
        (lcefem.solvers.cost)."""
        counts = strip_mesh_counts(self.geometry, self.law().lambda_N, self.mesh)
        dofs = 3.0 * counts["nodes"]
        est = cost.Estimate().count("cells", counts["cells"]).count("dofs", dofs)
        est.memory(
            f"mesh.size = {self.mesh.size} mm, mesh.level = {self.mesh.level}",
            f"{cost.describe(counts['cells'], 'cells')} ({cost.describe(dofs, 'DOFs')})",
            cost.fe_memory(dofs),
        )
        if not self.run.steady:
            cost.time_steps(
                f"run.dt = {self.run.dt} s (run.duration = {self.run.duration} s)",
                self.run.duration,
                self.run.dt,
                est,
            )
        return est

    def resolved(self) -> dict:
        out = resolved(self)
        out["lce"].update(law_summary(self.law()))
        return out


@dataclass
class StripResult:
    history: dict[str, np.ndarray]
    summary: dict
    out: pathlib.Path | None
    model: object = None  # the ThermoMechanicalModel (for renders and further analysis)


class StripSimulation:
    """Builds the strip model once; :meth:`run` steps it in time and records observables."""

    def __init__(self, config: StripConfig, comm: MPI.Comm | None = None):
        self.config = config = config.validated()
        self.law = tr = config.law()
        self.tmesh = tm = build_strip_mesh(config.geometry, tr.lambda_N, config.mesh, comm)
        self.comm = comm = tm.mesh.comm
        info = tm.info
        self.dims = info
        held = config.run.bc == "held"
        heat = HeatSetup(
            config.thermal,
            config.exchange,
            heated_cells=["coil"],
            exposed_facets=["sides"] if held else ["sides", "end"],
        )
        mesh = tm.mesh
        fdim = mesh.topology.dim - 1
        end = tm.facet_tags.find(tm.facet_tag("end"))
        W, H = info["width"], info["thickness"]
        quarter = info["symmetry"] == "quarter"

        def dirichlet(V):
            if held:  # both end faces clamped
                bcs = clamp_face(tm, V, "clamp") + clamp_face(tm, V, "end")
            else:  # the clamp face slides in its plane
                bcs = plane_clamp(tm, V, "clamp", 0)
            if quarter:  # symmetry planes: no normal displacement
                return bcs + mirror_planes(tm, V, (("sym_y", 1), ("sym_z", 2)))
            for comp in () if held else (1, 2):  # clamp-face centre lines held: no rigid motion
                centre, tol = (0.5 * W, 0.5 * H)[comp - 1], 1e-6 * min(W, H)
                bcs.append(
                    component_bc(
                        V,
                        comp,
                        nodes_on_line(
                            V,
                            comp,
                            lambda x, c=comp, m=centre: np.isclose(x[0], 0.0, atol=tol)
                            & np.isclose(x[c], m, atol=tol),
                        ),
                    )
                )
            return bcs

        ds = surface_measure(tm)
        end_area = W * H
        self.tip_traction = dolfinx.fem.Constant(
            mesh, PETSc.ScalarType(config.run.tip_load / end_area)
        )

        def external_work(u):
            return self.tip_traction * u[0] * ds(tm.facet_tag("end"))

        director = ufl.as_vector([1.0, 0.0, 0.0])  # along the strip axis (as stretched in stage 2)
        region = LCERegion(["lce", "coil"], director, tr, config.elasticity)
        self.model = ThermoMechanicalModel(
            tm,
            heat,
            [region],
            dirichlet=dirichlet,
            external_work=external_work if config.run.tip_load else None,
            petsc_options=config.petsc,
        )
        u = self.model.u
        self._coil_volume = info["coil_area"] * info["length"]  # [mm^3]
        self._set_current({"coil": config.run.current})
        # Observables, compiled once.
        one = dolfinx.fem.Constant(mesh, PETSc.ScalarType(1.0))
        self._area_end = assemble_global(dolfinx.fem.form(one * ds(tm.facet_tag("end"))), comm)
        self._area_clamp = assemble_global(dolfinx.fem.form(one * ds(tm.facet_tag("clamp"))), comm)
        self._ux_end = dolfinx.fem.form(u[0] * ds(tm.facet_tag("end")))
        self._area_sides = assemble_global(dolfinx.fem.form(one * ds(tm.facet_tag("sides"))), comm)
        self._T_sides = dolfinx.fem.form(self.model.heat.T * ds(tm.facet_tag("sides")))
        self._ux_clamp = dolfinx.fem.form(u[0] * ds(tm.facet_tag("clamp")))
        F = ufl.Identity(3) + ufl.grad(u)
        N = ufl.FacetNormal(mesh)
        FinvTN = ufl.inv(F).T * N
        self._current_end_area = dolfinx.fem.form(
            ufl.det(F) * ufl.sqrt(ufl.dot(FinvTN, FinvTN)) * ds(tm.facet_tag("end"))
        )
        V = u.function_space
        self.symmetry_factor = info["symmetry_factor"]  # force on the whole section
        if held:
            weight = dolfinx.fem.Function(V)
            dofs = dolfinx.fem.locate_dofs_topological(V.sub(0), fdim, end)
            weight.x.array[dofs] = 1.0
            self._reaction = self.model.mechanics.reaction_form(weight)
        else:
            self._reaction = None
        # Output fields: spontaneous stretch interpolated into the temperature space.
        self.lambda_s = dolfinx.fem.Function(self.model.heat.V, name="spontaneous_stretch")
        self._lambda_expr = dolfinx.fem.Expression(
            spontaneous_stretch(self.model.heat.T, tr),
            self.model.heat.V.element.interpolation_points,
        )
        self.ndofs = {
            "displacement": V.dofmap.index_map.size_global * V.dofmap.index_map_bs,
            "temperature": self.model.heat.V.dofmap.index_map.size_global,
        }
        self.time = 0.0  # [s] simulated by advance()

    # -- drives -----------------------------------------------------------------------------
    #: Cell tags that carry a coil (the heated cells of the heat problem).
    COILS = ("coil",)

    def _set_current(self, drives: Mapping[str, float]) -> None:
        """Coil current [A] per strip tag (:attr:`COILS`); the Joule power I^2 R [mW]
        (:meth:`lcefem.models.heat.Coil.power`) is spread over the coil's volume."""
        for tag, current in drives.items():
            if tag not in self.COILS:
                raise InputError(
                    f"drive {tag!r}: not a coil tag of the strip (allowed {', '.join(self.COILS)})"
                )
            check_current(f"current[{tag}]", current)
            self.power = self.config.coil.power(float(current))  # [mW]
            self.model.heat.power_density.value = self.power / self._coil_volume

    def _nodal_field(self, values, name: str, base: np.ndarray) -> np.ndarray:
        """Nodal values (temperature space) of a uniform value, a {cell tag: value} mapping (other
        nodes keep ``base``) or a callable f(x) of the reference coordinates x (3, n) [mm]."""
        V = self.model.heat.V
        if callable(values):
            f = dolfinx.fem.Function(V)
            f.interpolate(values)
            return f.x.array.copy()
        out = np.array(base, dtype=float, copy=True)
        if not isinstance(values, Mapping):
            out[:] = float(values)
            return out
        for tag, value in values.items():
            if tag not in self.tmesh.cells:
                raise InputError(
                    f"{name}[{tag!r}]: not a cell tag of the strip (allowed "
                    f"{', '.join(sorted(self.tmesh.cells))})"
                )
            cells = self.tmesh.cell_tags.find(self.tmesh.cell_tag(tag))
            out[dolfinx.fem.locate_dofs_topological(V, 3, cells)] = float(value)
        return out

    def _prescribe(self, T: np.ndarray, where: str):
        self.model.heat.T.x.array[:] = T
        self.model.heat.T.x.scatter_forward()
        return self.model.equilibrate(where)

    def set_temperature(self, temperature, where: str = "prescribed temperature"):
        """Prescribe the temperature field T [C] (uniform, per cell tag, or a callable of the
        reference coordinates) and bring the mechanics to it (the one path follower); later heat
        steps continue from it. Returns the step report (iterations, cuts)."""
        T = self._nodal_field(temperature, "temperature", self.model.heat.T.x.array)
        if not np.all((T > ABSOLUTE_ZERO) & (T < DECOMPOSITION_TEMPERATURE)):
            raise InputError(
                f"temperature: must lie in ({ABSOLUTE_ZERO:g}, "
                f"{DECOMPOSITION_TEMPERATURE:g}) C (got {T.min():g} .. {T.max():g})"
            )
        return self._prescribe(T, where)

    def set_spontaneous_stretch(self, stretch, where: str = "prescribed spontaneous stretch"):
        """Prescribe the spontaneous stretch lambda_s [-] (relative to the isotropic length;
        1 < lambda_s <= lambda_N) uniform, per cell tag or a callable, through the temperature at
        which the transition gives it (:func:`lcefem.models.lce.temperature_for_stretch`); returns
        the step report."""
        tr = self.law
        now = np.asarray(spontaneous_stretch(self.model.heat.T.x.array, tr), dtype=float)
        lam = self._nodal_field(stretch, "spontaneous_stretch", now)
        if not np.all((lam > 1.0) & (lam <= tr.lambda_N * (1.0 + 1e-12))):
            raise InputError(
                f"spontaneous_stretch: must lie in (1, lambda_N = {tr.lambda_N:g}] "
                f"(got {lam.min():g} .. {lam.max():g})"
            )
        return self._prescribe(temperature_for_stretch(np.minimum(lam, tr.lambda_N), tr), where)

    def advance(self, dt: float, where: str | None = None) -> StepRecord:
        """One backward-Euler heat step of ``dt`` [s], then the mechanics to the new temperature
        (the one path follower); returns its :class:`StepRecord` (the observables with the step's
        Newton iterations and cuts). ``dt`` must be > 0 s and at most the longest run
        (lcefem.models.limits.check_time_step, the command line's bound)."""
        check_time_step("dt", dt)
        report = self.model.step(dt, where=where or f"t = {self.time + dt:.4g} s")
        self.time += dt
        return StepRecord(
            self.time,
            self.observe(self.time, report.iterations, report.cuts),
            report.iterations,
            report.cuts,
            detail=report,
        )

    # -- observables ------------------------------------------------------------------------
    def stretch(self) -> float:
        """Active length over the isotropic length [-]."""
        ux_end = assemble_global(self._ux_end, self.comm) / self._area_end
        ux_clamp = assemble_global(self._ux_clamp, self.comm) / self._area_clamp
        return (self.dims["length"] + ux_end - ux_clamp) / self.dims["length_isotropic"]

    def force(self) -> float:
        """Axial force [N] on the held end (tension positive); the tip load for a free strip."""
        if self._reaction is None:
            return float(self.config.run.tip_load)
        return self.symmetry_factor * assemble_global(self._reaction, self.comm)

    def surface_temperature(self) -> float:
        """Mean temperature [C] of the lateral surface (what the seed's infrared camera saw)."""
        return assemble_global(self._T_sides, self.comm) / self._area_sides

    def end_area_ratio(self) -> float:
        return assemble_global(self._current_end_area, self.comm) / self._area_end

    def observe(self, t: float, iterations: int = 0, cuts: int = 0) -> dict[str, float]:
        heat = self.model.heat
        return {
            "time [s]": t,
            "T_mean [C]": heat.mean_temperature(),
            "T_max [C]": heat.max_temperature(),
            "T_surface [C]": self.surface_temperature(),
            "stretch [-]": self.stretch(),
            "force [N]": self.force(),
            "end_area_ratio [-]": self.end_area_ratio(),
            "newton_iterations [-]": iterations,
            "step_cuts [-]": cuts,
        }

    def steady_state(self, rtol: float = 1e-8, max_iterations: int = 30) -> dict[str, float]:
        """Thermal and mechanical equilibrium at the set current: fixed point between the steady
        heat equation (pulled back with the current displacement) and the mechanics. Returns
        observables."""
        previous = self.stretch()
        iterations = 0
        for it in range(1, max_iterations + 1):
            self.model.heat.steady()
            iterations += self.model.equilibrate(
                where=f"steady state, fixed-point iteration {it}"
            ).iterations
            lam = self.stretch()
            if abs(lam - previous) <= rtol * lam:
                return self.observe(float("inf"), iterations, 0)
            previous = lam
        raise ConvergenceError(
            "steady state",
            f"stretch still changing after {max_iterations} heat-mechanics fixed-point iterations",
        )

    # -- the run (the one door, lcefem.solvers.runner.run) --------------------------------------
    def program(self) -> Program:
        """:func:`strip_program` of this strip's configuration."""
        return strip_program(self.config)

    def default_exports(self, fields: bool = True) -> list:
        """history.csv (:data:`COLUMNS`), and with ``fields`` thermal.bp (temperature, spontaneous
        stretch) and displacement.bp, a frame every run.output_every records."""
        cfg = self.config
        history = History(
            columns=tuple(COLUMNS),
            postfix=lambda r: (
                f"T_mean={r.observables['T_mean [C]']:.1f}C "
                f"stretch={r.observables['stretch [-]']:.4f} "
                f"F={r.observables['force [N]']:.3f}N"
            ),
        )
        if not fields:
            return [history]
        every = cfg.run.output_every
        return [
            history,
            Fields("thermal.bp", ("temperature [C]", "spontaneous stretch [-]"), every=every),
            Fields("displacement.bp", ("displacement [mm]",), every=every),
        ]

    def run(
        self,
        out: pathlib.Path | None = None,
        progress: bool = True,
        fields: bool = True,
        crossing_temperature: float | None = None,
        program: Program | None = None,
        exports: list | None = None,
    ) -> StripResult:
        """The run (history.csv, fields, summary.json in ``out``) through the one door
        (:func:`lcefem.solvers.runner.run`): ``program`` (default :meth:`program`), ``exports``
        (default :meth:`default_exports`; without ``out`` only the history, in memory);
        ``crossing_temperature`` [C]: the summary's metrics report when it is crossed
        (:func:`transient_metrics`)."""
        cfg = self.config
        program = program or self.program()
        if exports is None:
            exports = self.default_exports(fields and out is not None)
        bar = Progress(
            program.end,
            f"strip {cfg.run.current:g} A {cfg.run.bc}",
            "s",
            enabled=progress and not program.steady,
            comm=self.comm,
        )
        started = time.perf_counter()
        head = {
            "power [mW]": self.power,
            "mesh": self._mesh_summary(),
            "cost estimate": cfg.estimate().as_dict(),
        }
        found = {}

        def summarize(run, records) -> dict:
            found["history"] = run.history
            if program.steady:
                result = {"steady_state": dict(records[-1].observables)}
            else:
                h = program.end / len(records[1:]) if records[1:] else program.end
                result = {
                    "as_built": {
                        k: self.dims[k]
                        for k in (
                            "length",
                            "width",
                            "thickness",
                            "coil_side",
                            "length_isotropic",
                            "lambda_N",
                        )
                    },
                    "metrics": transient_metrics(
                        _as_arrays([r.observables for r in records]), self.law, crossing_temperature
                    ),
                    "steps": len(records) - 1,
                    "dt [s]": h,
                    "newton_iterations": sum(r.iterations for r in records[1:]),
                }
            return {**head, **result, "wall_time [s]": time.perf_counter() - started}

        summary = run_door(
            self,
            program,
            exports,
            out,
            config=cfg.resolved(),
            progress=bar,
            summarize=summarize,
            comm=self.comm,
        )
        history = found["history"]
        return StripResult(
            history.as_arrays() if history is not None else {}, summary, out, self.model
        )

    def start(self) -> StepRecord:
        """The state at t = 0: a tip load, if any, applied before heating."""
        rep = (
            self.model.equilibrate(where="t = 0 s (initial load)")
            if self.config.run.tip_load
            else None
        )
        its, cuts = (rep.iterations, rep.cuts) if rep else (0, 0)
        return StepRecord(0.0, self.observe(0.0, its, cuts), its, cuts, detail=rep)

    def steady(self) -> StepRecord:
        """The steady state at the set current (:meth:`steady_state`), at t = inf."""
        obs = self.steady_state()
        return StepRecord(float("inf"), obs, int(obs["newton_iterations [-]"]))

    def reaction(self, tag: str, component: int = 0) -> float:
        """Support reaction [N] of the whole strip (symmetry factor included) on the facet tag
        ``tag`` along ``component`` (0 axial): what the body exerts on that face's support."""
        forms = self.__dict__.setdefault("_reactions", {})
        if (tag, component) not in forms:
            tm = self.tmesh
            if tag not in tm.facets:
                raise InputError(
                    f"reaction tag {tag!r}: not a facet tag of the strip (allowed "
                    f"{', '.join(sorted(tm.facets))})"
                )
            V = self.model.u.function_space
            weight = dolfinx.fem.Function(V)
            dofs = dolfinx.fem.locate_dofs_topological(
                V.sub(component), tm.mesh.topology.dim - 1, tm.facet_tags.find(tm.facet_tag(tag))
            )
            weight.x.array[dofs] = 1.0
            forms[(tag, component)] = self.model.mechanics.reaction_form(weight)
        return self.symmetry_factor * assemble_global(forms[(tag, component)], self.comm)

    def _mesh_summary(self) -> dict:
        return {
            "cells": self.tmesh.mesh.topology.index_map(3).size_global,
            "cell_type": self.config.mesh.cell,
            "symmetry": self.config.mesh.symmetry,
            "element_size [mm]": self.dims["element_size"],
            "dofs": self.ndofs,
            "mpi_ranks": self.comm.size,
        }

    # -- the Problem protocol (lcefem.solvers.problems.protocol) --------------------------------
    drive = "current [A]"

    def drive_tags(self) -> tuple[str, ...]:
        return self.COILS

    def set_drives(self, drives: Mapping[str, float]) -> None:
        self._set_current(drives)

    def observables(self) -> dict[str, float]:
        return self.observe(self.time)

    def fields(self) -> dict:
        self.lambda_s.interpolate(self._lambda_expr)
        return {
            "displacement [mm]": self.model.u,
            "temperature [C]": self.model.heat.T,
            "spontaneous stretch [-]": self.lambda_s,
        }

    def _state_functions(self) -> list:
        return [self.model.u, self.model.heat.T, self.model.heat.T_old, self.model.T_mech]

    def save_state(self) -> dict:
        return {
            "arrays": copy_arrays(self._state_functions()),
            "time": self.time,
            "power": self.power,
        }

    def restore_state(self, state: dict) -> None:
        put_arrays(self._state_functions(), state["arrays"])
        self.time, self.power = state["time"], state["power"]
        self.model.heat.power_density.value = self.power / self._coil_volume


def _as_arrays(rows) -> dict[str, np.ndarray]:
    return {c: np.array([r[c] for r in rows]) for c in COLUMNS}


def first_crossing(t: np.ndarray, y: np.ndarray, level: float, rising: bool = True) -> float:
    """First time [s] at which y crosses ``level`` (linear interpolation); nan if never."""
    s = (y - level) if rising else (level - y)
    idx = np.nonzero(s >= 0)[0]
    if len(idx) == 0:
        return float("nan")
    i = idx[0]
    if i == 0:
        return float(t[0])
    return float(t[i - 1] + (t[i] - t[i - 1]) * (-s[i - 1]) / (s[i] - s[i - 1]))


def transient_metrics(
    history: dict[str, np.ndarray],
    transition: NematicTransition | MeasuredContraction,
    crossing_temperature: float | None = None,
) -> dict:
    """Times to ``crossing_temperature`` [C] (mean and surface temperature; keys
    "time_to_<T>C_mean [s]", "time_to_<T>C_surface [s]"; only if it is given: a temperature an
    experiment reports the crossing of), to 95 % of the full contraction (lambda_N -> 1), final
    values, and the largest force with the time to reach 95 % of it."""
    t = history["time [s]"]
    lam_n = transition.lambda_N
    target95 = lam_n - 0.95 * (lam_n - 1.0)
    force = history["force [N]"]
    crossing = {}
    if crossing_temperature is not None:
        T = float(crossing_temperature)
        crossing = {
            f"time_to_{T:g}C_mean [s]": first_crossing(t, history["T_mean [C]"], T),
            f"time_to_{T:g}C_surface [s]": first_crossing(t, history["T_surface [C]"], T),
        }
    return {
        **crossing,
        "time_to_95pct_contraction [s]": first_crossing(
            t, history["stretch [-]"], target95, rising=False
        ),
        "final_stretch [-]": float(history["stretch [-]"][-1]),
        "final_T_mean [C]": float(history["T_mean [C]"][-1]),
        "max_force [N]": float(np.max(force)),
        "time_to_95pct_force [s]": first_crossing(t, force, 0.95 * float(np.max(force)))
        if np.max(force) > 0
        else float("nan"),
    }


def strip_program(config: StripConfig) -> Program:
    """The run section as a program: the coil current for run.duration [s] in equal steps of at
    most run.dt [s], or the steady state at it (run.steady)."""
    r = config.run
    if r.steady:
        return Program(
            TIME, ((0.0, {"coil": r.current}),), 1.0, 1.0, steady=True, record_start=False
        )
    return Program.in_time({"coil": r.current}, r.duration, r.dt)


def strip_exports(problem: StripSimulation) -> list:
    """The strip's default exports (:meth:`StripSimulation.default_exports`)."""
    return problem.default_exports()


def run_strip(
    config: StripConfig,
    out: pathlib.Path | None = None,
    progress: bool = True,
    fields: bool = True,
    comm: MPI.Comm | None = None,
    crossing_temperature: float | None = None,
    program: Program | None = None,
    exports: list | None = None,
) -> StripResult:
    """Build and run one strip simulation (see module docstring); ``crossing_temperature`` [C]: see
    :func:`transient_metrics`; ``program``, ``exports``: see :meth:`StripSimulation.run` (a case
    file's ``[program]`` and ``[[exports]]``)."""
    return StripSimulation(config, comm).run(
        None if out is None else pathlib.Path(out),
        progress=progress,
        fields=fields,
        crossing_temperature=crossing_temperature,
        program=program,
        exports=exports,
    )
