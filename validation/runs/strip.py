"""A single LCE strip heated by its embedded coil, in 3D finite strain (seed 001, Fig. 2).

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

import argparse
import dataclasses
import math
import pathlib
import time
from dataclasses import dataclass, field

import dolfinx_solver  # noqa: F401  (orders MPI before dolfinx/petsc4py)
import numpy as np
import ufl
from mpi4py import MPI
from petsc4py import PETSc

import dolfinx

from lcefem.meshes.strip import StripGeometry, StripMesh, build_strip_mesh
from lcefem.models.errors import ConvergenceError, InputError
from lcefem.models.heat import Coil, SurfaceExchange, ThermalProperties
from lcefem.models.hyperelastic import LCEElasticity
from lcefem.models.lce import NematicTransition, spontaneous_stretch
from lcefem.models.limits import MAX_CURRENT
from lcefem.models.parameters import param
from lcefem.solvers.exports import FieldExport
from lcefem.solvers.heat import HeatSetup
from lcefem.solvers.mechanics import assemble_global, surface_measure
from lcefem.solvers.thermomechanics import LCERegion, ThermoMechanicalModel
from lcefem.solvers.run import Progress, Run, add_out_arguments, check_config, resolved
from lcefem.validation.config import config_from_toml, override

COLUMNS = ["time [s]", "T_mean [C]", "T_max [C]", "T_surface [C]", "stretch [-]", "force [N]",
           "end_area_ratio [-]", "newton_iterations [-]", "step_cuts [-]"]
BOUNDARY_CONDITIONS = ("free", "held")


@dataclass(frozen=True)
class StripRun:
    """What the experimenter sets: current, duration, boundary condition."""

    current: float = param(0.2, "A", "seed 001: 0.1, 0.15, 0.2 A transients; 0.04-0.09 A hold currents",
                           minimum=0.0, maximum=MAX_CURRENT)
    duration: float = param(30.0, "s", "seed 001: 0.2 A kept under 30 s", positive=True)
    dt: float = param(0.5, "s", "chosen: time step (backward Euler)", positive=True)
    bc: str = param("free", "-", "'free' (one end clamped, other free) or 'held' (both ends clamped "
                    "at the nematic length; seed 001 Fig. 2D)")
    tip_load: float = param(0.0, "N", "dead load on the free end (seed 001 hung an 8.2 g clip: 0.080 N)",
                            minimum=0.0)
    output_every: int = param(1, "-", "write fields every n steps", minimum=1)
    steady: bool = param(False, "-", "solve the steady state (thermal equilibrium) instead of a transient")


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

    def validated(self) -> "StripConfig":
        check_config(self)
        if self.run.bc not in BOUNDARY_CONDITIONS:
            raise InputError(f"run.bc = {self.run.bc!r}: allowed {', '.join(BOUNDARY_CONDITIONS)}")
        if self.run.dt > self.run.duration:
            raise InputError(f"run.dt = {self.run.dt} s: must be <= run.duration = {self.run.duration} s")
        if self.mesh.cell not in ("hex", "tet"):
            raise InputError(f"mesh.cell = {self.mesh.cell!r}: allowed hex, tet")
        if self.run.tip_load and self.run.bc != "free":
            raise InputError("run.tip_load: only with run.bc = 'free'")
        return self

    def resolved(self) -> dict:
        return resolved(self)


@dataclass
class StripResult:
    history: dict[str, np.ndarray]
    summary: dict
    out: pathlib.Path | None
    model: object = None  # the ThermoMechanicalModel (for renders and further analysis)


class StripSimulation:
    """Builds the strip model once; :meth:`run` steps it in time and records observables."""

    def __init__(self, config: StripConfig, comm: MPI.Comm = MPI.COMM_WORLD):
        self.config = config = config.validated()
        self.comm = comm
        tr = config.transition
        self.tmesh = tm = build_strip_mesh(config.geometry, tr.lambda_N, config.mesh, comm)
        info = tm.info
        self.dims = info
        held = config.run.bc == "held"
        heat = HeatSetup(config.thermal, config.exchange, heated_cells=["coil"],
                         exposed_facets=["sides"] if held else ["sides", "end"])
        mesh = tm.mesh
        fdim = mesh.topology.dim - 1
        clamp = tm.facet_tags.find(tm.facet_tag("clamp"))
        end = tm.facet_tags.find(tm.facet_tag("end"))
        W, H = info["width"], info["thickness"]

        quarter = info["symmetry"] == "quarter"
        sym = {1: "sym_y", 2: "sym_z"}

        def dirichlet(V):
            bcs = []
            if held:
                zero = np.zeros(3, dtype=PETSc.ScalarType)
                bcs += [dolfinx.fem.dirichletbc(zero, dolfinx.fem.locate_dofs_topological(V, fdim, f), V)
                        for f in (clamp, end)]
            else:
                bcs.append(_component_bc(V, 0, dolfinx.fem.locate_dofs_topological(V.sub(0), fdim, clamp)))
            for comp in (1, 2):
                if quarter:  # symmetry planes: no normal displacement
                    facets = tm.facet_tags.find(tm.facet_tag(sym[comp]))
                    bcs.append(_component_bc(V, comp, dolfinx.fem.locate_dofs_topological(
                        V.sub(comp), fdim, facets)))
                elif not held:  # clamp-face centre lines held in symmetry: no rigid motion
                    centre, tol = (0.5 * W, 0.5 * H)[comp - 1], 1e-6 * min(W, H)
                    Vc, _ = V.sub(comp).collapse()
                    dofs = dolfinx.fem.locate_dofs_geometrical(
                        (V.sub(comp), Vc), lambda x, c=comp, m=centre: np.isclose(x[0], 0.0, atol=tol)
                        & np.isclose(x[c], m, atol=tol))[0]
                    bcs.append(_component_bc(V, comp, dofs))
            return bcs

        ds = surface_measure(tm)
        end_area = W * H
        self.tip_traction = dolfinx.fem.Constant(mesh, PETSc.ScalarType(config.run.tip_load / end_area))

        def external_work(u):
            return self.tip_traction * u[0] * ds(tm.facet_tag("end"))

        director = ufl.as_vector([1.0, 0.0, 0.0])  # along the strip axis (as stretched in stage 2)
        region = LCERegion(["lce", "coil"], director, tr, config.elasticity)
        self.model = ThermoMechanicalModel(tm, heat, [region], dirichlet=dirichlet,
                                           external_work=external_work if config.run.tip_load else None,
                                           petsc_options=config.petsc)
        u = self.model.u
        coil_volume = info["coil_area"] * info["length"]
        self.power = config.coil.power(config.run.current)  # mW
        self.model.heat.power_density.value = self.power / coil_volume
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
        self._current_end_area = dolfinx.fem.form(ufl.det(F) * ufl.sqrt(ufl.dot(FinvTN, FinvTN))
                                                  * ds(tm.facet_tag("end")))
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
            spontaneous_stretch(self.model.heat.T, tr), self.model.heat.V.element.interpolation_points)
        self.ndofs = {"displacement": V.dofmap.index_map.size_global * V.dofmap.index_map_bs,
                      "temperature": self.model.heat.V.dofmap.index_map.size_global}

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
        return {"time [s]": t, "T_mean [C]": heat.mean_temperature(), "T_max [C]": heat.max_temperature(),
                "T_surface [C]": self.surface_temperature(), "stretch [-]": self.stretch(), "force [N]": self.force(),
                "end_area_ratio [-]": self.end_area_ratio(), "newton_iterations [-]": iterations,
                "step_cuts [-]": cuts}

    def steady_state(self, rtol: float = 1e-8, max_iterations: int = 30) -> dict[str, float]:
        """Thermal and mechanical equilibrium at the set current: fixed point between the steady heat
        equation (pulled back with the current displacement) and the mechanics. Returns observables."""
        previous = self.stretch()
        iterations = 0
        for it in range(1, max_iterations + 1):
            self.model.heat.steady()
            iterations += self.model.equilibrate(where=f"steady state, fixed-point iteration {it}").iterations
            lam = self.stretch()
            if abs(lam - previous) <= rtol * lam:
                return self.observe(float("inf"), iterations, 0)
            previous = lam
        raise ConvergenceError("steady state", f"stretch still changing after {max_iterations} "
                               "heat-mechanics fixed-point iterations")

    # -- time loop --------------------------------------------------------------------------
    def run(self, out: pathlib.Path | None = None, progress: bool = True, fields: bool = True) -> StripResult:
        cfg = self.config
        bar = Progress(cfg.run.duration, f"strip {cfg.run.current:g} A {cfg.run.bc}", "s",
                       enabled=progress and not cfg.run.steady, comm=self.comm)
        started = time.perf_counter()
        with Run(out, config=cfg.resolved(), columns=COLUMNS, progress=bar, comm=self.comm) as run:
            exports = []
            if out is not None and fields:
                exports = [run.output(FieldExport(out / "thermal.bp", [self.model.heat.T, self.lambda_s],
                                                  self.comm)),
                           run.output(FieldExport(out / "displacement.bp", [self.model.u], self.comm))]

            def record(row, step, where):
                run.record(row, where, at=min(row["time [s]"], cfg.run.duration),
                           postfix=f"T_mean={row['T_mean [C]']:.1f}C stretch={row['stretch [-]']:.4f} "
                                   f"F={row['force [N]']:.3f}N")
                if exports and step % cfg.run.output_every == 0:
                    self.lambda_s.interpolate(self._lambda_expr)
                    for e in exports:
                        e.write(row["time [s]"] if math.isfinite(row["time [s]"]) else 0.0)

            summary = {"power [mW]": self.power, "mesh": self._mesh_summary()}
            if cfg.run.steady:
                obs = self.steady_state()
                record(obs, 0, "steady state")
                summary["steady_state"] = obs
            else:
                summary.update(self._transient(record))
            summary["wall_time [s]"] = time.perf_counter() - started
            summary = run.complete(summary)
        return StripResult(run.history.as_arrays(), summary, out, self.model)

    def _transient(self, record) -> dict:
        """Backward-Euler steps to run.duration; returns the summary entries of a transient."""
        cfg = self.config
        n_steps = max(1, int(math.ceil(cfg.run.duration / cfg.run.dt - 1e-9)))
        dt = cfg.run.duration / n_steps
        # Initial state (a tip load, if any, is applied before heating).
        rep = self.model.equilibrate(where="t = 0 s (initial load)") if cfg.run.tip_load else None
        rows = [self.observe(0.0, rep.iterations if rep else 0, rep.cuts if rep else 0)]
        record(rows[-1], 0, "t = 0 s")
        total_its = 0
        for step in range(1, n_steps + 1):
            t = step * dt
            where = f"t = {t:.4g} s"
            rep = self.model.step(dt, where=where)
            total_its += rep.iterations
            rows.append(self.observe(t, rep.iterations, rep.cuts))
            record(rows[-1], step, where)
        return {"as_built": {k: self.dims[k] for k in ("length", "width", "thickness", "coil_side",
                                                        "length_isotropic", "lambda_N")},
                "metrics": transient_metrics(_as_arrays(rows), cfg.transition),
                "steps": n_steps, "dt [s]": dt, "newton_iterations": total_its}

    def _mesh_summary(self) -> dict:
        return {"cells": self.tmesh.mesh.topology.index_map(3).size_global,
                "cell_type": self.config.mesh.cell, "symmetry": self.config.mesh.symmetry,
                "element_size [mm]": self.dims["element_size"], "dofs": self.ndofs,
                "mpi_ranks": self.comm.size}


def _component_bc(V, component: int, dofs) -> dolfinx.fem.DirichletBC:
    """u_component = 0 on ``dofs`` (indices in the sub-space V.sub(component))."""
    return dolfinx.fem.dirichletbc(PETSc.ScalarType(0), dofs, V.sub(component))


def _as_arrays(rows: list[dict]) -> dict[str, np.ndarray]:
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


#: Temperature whose crossing time seed 001 reports ('T_NI (~70 C) within 10 s' at 0.2 A) [C].
SEED_T_NI = 70.0


def transient_metrics(history: dict[str, np.ndarray], transition: NematicTransition) -> dict:
    """Times to 70 C (mean and surface temperature) and to 95 % of the full contraction
    (lambda_N -> 1), final values, and the largest force with the time to reach 95 % of it."""
    t = history["time [s]"]
    lam_n = transition.lambda_N
    target95 = lam_n - 0.95 * (lam_n - 1.0)
    force = history["force [N]"]
    return {
        "time_to_70C_mean [s]": first_crossing(t, history["T_mean [C]"], SEED_T_NI),
        "time_to_70C_surface [s]": first_crossing(t, history["T_surface [C]"], SEED_T_NI),
        "time_to_95pct_contraction [s]": first_crossing(t, history["stretch [-]"], target95, rising=False),
        "final_stretch [-]": float(history["stretch [-]"][-1]),
        "final_T_mean [C]": float(history["T_mean [C]"][-1]),
        "max_force [N]": float(np.max(force)),
        "time_to_95pct_force [s]": first_crossing(t, force, 0.95 * float(np.max(force)))
        if np.max(force) > 0 else float("nan"),
    }


def run_strip(config: StripConfig, out: pathlib.Path | None = None, progress: bool = True,
              fields: bool = True, comm: MPI.Comm = MPI.COMM_WORLD) -> StripResult:
    """Build and run one strip simulation (see module docstring)."""
    return StripSimulation(config, comm).run(None if out is None else pathlib.Path(out), progress=progress,
                                             fields=fields)


# -- command line -------------------------------------------------------------------------------
def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--current", type=float, help="coil current [A] (default 0.2)")
    p.add_argument("--duration", type=float, help="simulated time [s] (default 30)")
    p.add_argument("--dt", type=float, help="time step [s] (default 0.5)")
    p.add_argument("--bc", choices=BOUNDARY_CONDITIONS, help="free strip or held at nematic length")
    p.add_argument("--tip-load", type=float, help="dead load on the free end [N]")
    p.add_argument("--steady", action="store_true", default=None,
                   help="solve the thermal steady state instead of a transient")
    p.add_argument("--mesh-level", type=int, help="refinement level l: element size = mesh-size / (l + 1) (default 1)")
    p.add_argument("--mesh-size", type=float, help="level-0 element size [mm] (default 2)")
    p.add_argument("--cell", choices=("hex", "tet"), help="hexahedra (Q2) or tetrahedra (P2)")
    p.add_argument("--symmetry", choices=("quarter", "full"), help="mesh a quarter (default) or all")
    p.add_argument("--resistance", type=float, help=f"coil resistance [ohm] (default {Coil().resistance:g})")
    p.add_argument("--config", help="TOML case file; sections: " + ", ".join(
        f.name for f in dataclasses.fields(StripConfig)))
    p.add_argument("--no-fields", action="store_true", help="skip the VTX field files")
    add_out_arguments(p, "results/strip")


def config_from_args(args: argparse.Namespace) -> StripConfig:
    cfg = config_from_toml(args.config, StripConfig())
    cfg = override(cfg, "run", current=args.current, duration=args.duration, dt=args.dt, bc=args.bc,
                   tip_load=args.tip_load, steady=args.steady)
    cfg = override(cfg, "mesh", level=args.mesh_level, size=args.mesh_size, cell=args.cell,
                   symmetry=args.symmetry)
    return override(cfg, "coil", resistance=args.resistance)


def prepare(args: argparse.Namespace) -> StripConfig:
    """The validated configuration (before the output folder is touched)."""
    return config_from_args(args).validated()


def main(args: argparse.Namespace) -> int:
    cfg = args.prepared
    result = run_strip(cfg, args.out, progress=not args.quiet, fields=not args.no_fields)
    if MPI.COMM_WORLD.rank == 0 and cfg.run.steady:
        obs = result.summary["steady_state"]
        print(f"lcefem: strip {cfg.run.current:g} A ({cfg.run.bc}) steady state: stretch "
              f"{obs['stretch [-]']:.4f}, T_mean {obs['T_mean [C]']:.1f} C, force {obs['force [N]']:.4f} N; "
              f"results in {result.out}")
    elif MPI.COMM_WORLD.rank == 0:
        m = result.summary["metrics"]
        print(f"lcefem: strip {cfg.run.current:g} A ({cfg.run.bc}), {result.summary['steps']} steps in "
              f"{result.summary['wall_time [s]']:.1f} s; final stretch {m['final_stretch [-]']:.4f}, "
              f"T_mean {m['final_T_mean [C]']:.1f} C, force {result.history['force [N]'][-1]:.4f} N; "
              f"results in {result.out}")
    return 0
