"""The passive Kapton ribbon's buckling specimen (seed 001, Fig. 2G) in 3D finite strain: a
36 x 7 x 0.127 mm strip of Kapton, fixed-fixed, shortened by a prescribed end displacement.

Mesh: :func:`lcefem.meshes.kapton_ribbon.build_ribbon_fe` (Q2 hexahedra, one through the thickness;
half model about y = W/2). Physics: compressible neo-Hookean Kapton, datasheet E and nu
(:class:`lcefem.models.hyperelastic.NeoHookeanSolid`). Drive: the end shortening [mm]
(:meth:`KaptonSpecimenFE.set_drives`); the path through a list of compressions uses the
project's one path follower (:class:`lcefem.solvers.continuation.PathFollower`).

* :meth:`KaptonSpecimenFE.critical_load` — linearised buckling about the straight state (SLEPc
  generalised eigenproblem, repeated at the estimate: a secant refinement).
* :meth:`KaptonSpecimenFE.add_imperfection` — the first mode as geometric imperfection.
* :meth:`KaptonSpecimenFE.follow` — displacement-controlled path to the final compression.
* :class:`KaptonSpecimenFEConfig`, :func:`run_specimen_fe` — ``lcefem run ribbon-buckling --model
  fe``: the configuration sections and one run through the door (lcefem.solvers.runner.run).

Observables (:meth:`KaptonSpecimenFE.observables`), keys "name [unit]": compressive force [N] on the
whole specimen, mid-span deflection [mm]. Not to be confused with the twisted LCE ribbon
(:mod:`lcefem.solvers.der.ribbon`): this is the passive Kapton specimen.

Units: mm, N, MPa (README).
"""

from __future__ import annotations

import itertools
import math
import pathlib
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import dolfinx_solver  # noqa: F401  (orders MPI before dolfinx/petsc4py)
from mpi4py import MPI
from petsc4py import PETSc

import numpy as np
import ufl

import dolfinx
import dolfinx.fem.petsc

from lcefem.meshes.kapton_ribbon import KaptonFEMesh, KaptonSpecimenGeometry, build_ribbon_fe
from lcefem.models import buckling
from lcefem.models.errors import ConvergenceError, InputError
from lcefem.models.hyperelastic import NeoHookeanSolid, neo_hookean_strain_energy
from lcefem.models.parameters import param
from lcefem.solvers.continuation import PathControl, PathFollower
from lcefem.solvers.exports import FEFields, write_snapshot
from lcefem.solvers.mechanics import (
    HyperelasticProblem,
    assemble_global,
    deformation_gradient,
    displacement_space,
    volume_measure,
)
from lcefem.solvers.problems.kapton_specimen_bh import KaptonSpecimenRun
from lcefem.solvers.problems.protocol import (
    LOAD,
    StepRecord,
    check_quasi_static_step,
    copy_arrays,
    put_arrays,
)
from lcefem.solvers.runner import HistoryExport, PathProblem, StateExport, StateHistory, run
from lcefem.solvers.runtime.checks import check_config, resolved
from lcefem.solvers.runtime.run import Progress
from lcefem.solvers.supports import clamp_face, mirror_planes

_prefix = itertools.count()


@dataclass(frozen=True)
class KaptonSpecimenFEPath:
    """Stepping of the FE buckling test and its imperfection."""

    imperfection: float = param(
        1.0e-3,
        "-",
        "chosen: amplitude/length of the first buckling "
        "eigenmode added to the geometry (the bar-and-hinge run uses the "
        "same amplitude of the fixed-fixed mode shape)",
        minimum=0.0,
        maximum=0.1,
    )
    step: float = param(
        0.02,
        "-",
        "chosen: compression increment in the post-buckling range",
        positive=True,
        maximum=0.25,
    )
    onset_steps: int = param(
        12,
        "-",
        "chosen: geometric increments from 0.2 to 50 x the critical "
        "compression (resolves the rise of the force to its plateau)",
        minimum=2,
        maximum=200,
    )


@dataclass
class CriticalLoad:
    force: float  # [N]
    shortening: float  # [mm]
    mode: dolfinx.fem.Function  # first buckling mode (max |u_z| = 1)
    secant_change: float  # relative change of the critical shortening in the last secant step


class KaptonSpecimenFE:
    """The fixed-fixed Kapton specimen in 3D finite strain (neo-Hookean, datasheet E and nu).

    The left clamp face is held, the right one moved by (-shortening, 0, 0); with the half model
    u_y = 0 on the mid-plane y = W/2. The compressive force is minus the x-reaction on the right
    clamp face, times the symmetry factor.
    """

    def __init__(
        self,
        specimen: KaptonSpecimenGeometry = KaptonSpecimenGeometry(),
        mesh: KaptonFEMesh = KaptonFEMesh(),
        solid: NeoHookeanSolid = NeoHookeanSolid(),
        petsc_options: dict | None = None,
        comm: MPI.Comm | None = None,
    ):
        self.specimen, self.solid = specimen, solid
        self.tmesh = tm = build_ribbon_fe(specimen, mesh, comm)
        self.V = V = displacement_space(tm.mesh, 2)
        self.u = u = dolfinx.fem.Function(V, name="displacement")
        self.end = dolfinx.fem.Constant(tm.mesh, np.zeros(3, dtype=PETSc.ScalarType))  # [mm]
        self.bcs = (
            clamp_face(tm, V, "clamp_left")
            + clamp_face(tm, V, "clamp_right", self.end)
            + mirror_planes(tm, V, [("sym_y", 1)])
        )
        right = dolfinx.fem.locate_dofs_topological(
            V, tm.mesh.topology.dim - 1, tm.facet_tags.find(tm.facet_tag("clamp_right"))
        )
        dx = volume_measure(tm)
        energy = neo_hookean_strain_energy(deformation_gradient(u), solid) * dx
        self.problem = HyperelasticProblem(
            u,
            energy,
            self.bcs,
            prefix=f"lcefem_kaptonfe{next(_prefix)}_",
            petsc_options=petsc_options,
            user_options=tuple(petsc_options or ()),
        )
        weight = dolfinx.fem.Function(V)
        weight.x.array[3 * right] = 1.0
        self._reaction = self.problem.reaction_form(weight)
        self._jacobian = dolfinx.fem.form(
            ufl.derivative(self.problem.residual, u, ufl.TrialFunction(V))
        )
        self.factor = tm.info["symmetry_factor"]
        self.length = specimen.length
        self.ndofs = V.dofmap.index_map.size_global * V.dofmap.index_map_bs
        self._mid = self._node((0.5 * self.length, 0.0, 0.5 * specimen.thickness))
        self.target_shortening = 0.0  # [mm] reached by advance()

    def _node(self, point) -> int:
        X = self.V.tabulate_dof_coordinates()
        return int(np.argmin(np.linalg.norm(X - np.asarray(point), axis=1)))

    def _set_shortening(self, shortening: float) -> None:
        self.end.value = np.array([-shortening, 0.0, 0.0])

    def force(self) -> float:
        """Compressive end force [N] on the whole specimen."""
        return -self.factor * assemble_global(self._reaction, self.tmesh.mesh.comm)

    def mid_deflection(self) -> float:
        """z displacement [mm] of the mid-span node on the ribbon's mid-plane, edge y = 0."""
        return float(self.u.x.array[3 * self._mid + 2])

    def observables(self) -> dict[str, float]:
        """Named observables, keys "name [unit]"."""
        shortening = -float(self.end.value[0])
        return {
            "end shortening [mm]": shortening,
            "compression [-]": shortening / self.length,
            "force [N]": self.force(),
            "mid-span deflection [mm]": self.mid_deflection(),
        }

    def write_fields(self, folder, t: float = 0.0) -> list[pathlib.Path]:
        """displacement.bp (Q2, VTX, ParaView) of the current state in ``folder``."""
        return [write_snapshot(folder, "displacement.bp", [self.u], t)]

    def axial_stiffness(self, shortening: float) -> float:
        """Secant axial stiffness F/shortening [N/mm] of the straight specimen."""
        self.straight_state(shortening)
        return self.force() / shortening

    def straight_state(self, shortening: float) -> None:
        """Equilibrium of the perfect (flat) specimen on its straight (unbuckled) path, from the
        uniform-strain guess u_x = -shortening x/L (Newton stays on the symmetric path)."""
        X = self.V.tabulate_dof_coordinates()
        guess = np.zeros_like(X)
        guess[:, 0] = -shortening * X[:, 0] / self.length
        self.problem.restore(guess.ravel())
        self._set_shortening(shortening)
        ok, its, reason = self.problem.solve()
        if not ok:
            raise ConvergenceError(f"straight state at shortening {shortening:g} mm", reason)

    def tangent(self) -> PETSc.Mat:
        A = dolfinx.fem.petsc.assemble_matrix(self._jacobian, bcs=self.bcs, diag=1.0)
        A.assemble()
        return A

    def critical_load(self, secant_steps: int = 2, start: float | None = None) -> CriticalLoad:
        """Linearised buckling about the straight state: with K(d) the tangent at shortening d and
        K0 = K(0), K(d) ~ K0 + (d/d_r)(K(d_r) - K0) vanishes first at d = -d_r/theta, theta the most
        negative eigenvalue of (K(d_r) - K0) phi = theta K0 phi (SLEPc, generalised Hermitian);
        repeated with d_r = d so that the linearisation is taken at the critical state.
        Starts from the Euler load of the specimen (4 pi^2 E I/L^2), or from the critical
        shortening ``start`` [mm] when given (e.g. that of a coarser mesh: one secant step then
        lands where two from the Euler estimate do)."""
        from slepc4py import SLEPc

        spec = self.specimen
        area = spec.width * spec.thickness
        euler = 4.0 * math.pi**2 * self.solid.youngs_modulus * spec.second_moment / spec.length**2
        d_r = (
            euler * spec.length / (self.solid.youngs_modulus * area)
            if start is None
            else float(start)
        )
        self.problem.restore(np.zeros(self.u.x.array.size))
        self._set_shortening(0.0)
        K0 = self.tangent()
        change = float("nan")
        for _ in range(secant_steps):
            self.straight_state(d_r)
            dK = self.tangent()
            dK.axpy(-1.0, K0)
            eps = SLEPc.EPS().create(self.tmesh.mesh.comm)
            eps.setOperators(dK, K0)
            eps.setProblemType(SLEPc.EPS.ProblemType.GHEP)
            eps.setDimensions(1, PETSc.DECIDE)
            eps.setWhichEigenpairs(SLEPc.EPS.Which.SMALLEST_REAL)
            eps.setTolerances(1e-10, 500)
            ksp = eps.getST().getKSP()
            ksp.setType("preonly")
            ksp.getPC().setType("lu")
            ksp.getPC().setFactorSolverType("mumps")
            eps.solve()
            if eps.getConverged() < 1:
                raise ConvergenceError("buckling eigenproblem", "SLEPc found no eigenpair")
            vr = dK.createVecRight()
            theta = eps.getEigenpair(0, vr).real
            eps.destroy()
            dK.destroy()
            if not theta < 0:
                raise ConvergenceError(
                    "buckling eigenproblem", f"no negative eigenvalue ({theta:g})"
                )
            d_new = -d_r / theta
            change = abs(d_new - d_r) / d_new
            d_r = d_new
        K0.destroy()
        self.straight_state(d_r)
        force = self.force()
        mode = dolfinx.fem.Function(self.V, name="buckling_mode")
        # the eigenvector holds this rank's owned dofs; the ghosts come from their owners, and the
        # scale is the largest |u_z| over all ranks (the same mode for every partition)
        index_map = self.V.dofmap.index_map
        mode.x.array[: index_map.size_local * self.V.dofmap.index_map_bs] = vr.array_r
        mode.x.scatter_forward()
        scale = self.tmesh.mesh.comm.allreduce(
            np.max(np.abs(mode.x.array.reshape(-1, 3)[:, 2])), op=MPI.MAX
        )
        mode.x.array[:] /= scale
        self.problem.restore(np.zeros(self.u.x.array.size))
        self._set_shortening(0.0)
        return CriticalLoad(force, d_r, mode, change)

    def add_imperfection(self, mode: dolfinx.fem.Function, amplitude: float) -> None:
        """Move the mesh (the stress-free reference) by ``amplitude`` [mm] x the mode (max |u_z| =
        1)."""
        from scipy.spatial import cKDTree

        X = self.V.tabulate_dof_coordinates()
        geom = self.tmesh.mesh.geometry.x
        dist, idx = cKDTree(X).query(geom)
        if np.max(dist) > 1e-9:
            raise RuntimeError("geometry nodes are not displacement nodes")
        geom[:, :] += amplitude * mode.x.array.reshape(-1, 3)[idx]

    def compression_schedule(
        self, c_cr: float, c_max: float, path: KaptonSpecimenFEPath
    ) -> np.ndarray:
        """Compressions: geometric from 0.2 to 50 c_cr, then steps of ``path.step`` to c_max."""
        onset = np.geomspace(0.2 * c_cr, min(50.0 * c_cr, c_max), path.onset_steps)
        start = onset[-1]
        n = max(1, int(math.ceil((c_max - start) / path.step - 1e-9)))
        return np.concatenate([onset, np.linspace(start, c_max, n + 1)[1:]])

    def follow(
        self,
        compressions,
        control: PathControl = PathControl(first_step=1.0, max_step=1.0, min_step=1e-3),
        on_step: Callable[[float, int], None] | None = None,
    ) -> PathFollower:
        """Displacement-controlled path through the given compressions (end shortening / L) with
        adaptive sub-steps (load parameter t = compression); ``on_step(compression, iterations)``
        after each given compression is reached. Returns the follower (iteration counts)."""
        follower = PathFollower(
            self.problem, lambda t: self._set_shortening(t * self.length), control
        )
        for c in compressions:
            before = follower.iterations
            follower.step = max(follower.step, float(c) - follower.t)
            follower.follow(float(c), where=f"ribbon compression {100 * float(c):.3g} %")
            if on_step is not None:
                on_step(float(c), follower.iterations - before)
        return follower

    # -- the Problem protocol (lcefem.solvers.problems.protocol) --------------------------------
    drive = "end shortening [mm]"

    def drive_tags(self) -> tuple[str, ...]:
        return ("clamp_right",)  # the moved clamp face; clamp_left is held

    def set_drives(self, drives: Mapping[str, float]) -> None:
        """Target end shortening [mm] of the moved clamp (0 <= d < L), reached by
        :meth:`advance`."""
        for tag, value in drives.items():
            if tag not in self.drive_tags():
                raise InputError(
                    f"drive {tag!r}: not a driven face of the specimen (allowed clamp_right)"
                )
            if not isinstance(value, (int, float)) or not 0.0 <= value < self.length:
                raise InputError(
                    f"end shortening[{tag}] = {value} mm: must be in [0, {self.length:g}) mm"
                )
            self.target_shortening = float(value)

    def advance(self, dt: float = 1.0) -> StepRecord:
        """From the present end shortening the fraction ``dt`` (0 < dt <= 1) of the way to the
        target of :meth:`set_drives`, with the path follower of :meth:`follow` (load parameter:
        compression = shortening / L); the record's ``detail``: the :class:`PathFollower`."""
        dt = check_quasi_static_step(dt)
        start = -float(self.end.value[0]) / self.length
        goal = start + dt * (self.target_shortening / self.length - start)
        follower = PathFollower(
            self.problem,
            lambda c: self._set_shortening(c * self.length),
            PathControl(first_step=1.0, max_step=1.0, min_step=1e-3),
            t0=start,
        )
        if goal != start:
            follower.follow(goal, where=f"ribbon compression {100 * goal:.3g} %")
        return StepRecord(
            dt, self.observables(), follower.iterations, follower.cuts, clock=LOAD, detail=follower
        )

    def fields(self) -> dict:
        return {"displacement [mm]": self.u}

    def save_state(self) -> dict:
        return {"u": copy_arrays([self.u]), "shortening": -float(self.end.value[0])}

    def restore_state(self, state: dict) -> None:
        put_arrays([self.u], state["u"])
        self._set_shortening(state["shortening"])


__all__ = ["CriticalLoad", "KaptonSpecimenFE", "KaptonSpecimenFEPath"]


# -- one run (``lcefem run ribbon-buckling --model fe``) ------------------------------------------
@dataclass(frozen=True)
class KaptonSpecimenFEConfig:
    run: KaptonSpecimenRun = field(default_factory=KaptonSpecimenRun)
    specimen: KaptonSpecimenGeometry = field(default_factory=KaptonSpecimenGeometry)
    mesh: KaptonFEMesh = field(default_factory=KaptonFEMesh)
    kapton: NeoHookeanSolid = field(default_factory=NeoHookeanSolid)
    path: KaptonSpecimenFEPath = field(default_factory=KaptonSpecimenFEPath)

    def validated(self) -> "KaptonSpecimenFEConfig":
        check_config(self)
        self.specimen.checked()
        self.mesh.checked()
        return self

    def resolved(self) -> dict:
        return resolved(self)


FE_COLUMNS = [
    "compression [-]",
    "end shortening [mm]",
    "force [N]",
    "mid-span deflection [mm]",
    "newton iterations [-]",
]


def run_specimen_fe(
    cfg: KaptonSpecimenFEConfig, out: pathlib.Path, progress: bool = True, report=None
) -> dict:
    """The FE buckling test through the run skeleton: critical load, then the path of the specimen
    with a mode imperfection to ``run.compression`` (history.csv of :data:`FE_COLUMNS`,
    displacement.bp, summary.json); returns the summary. ``report(out, cfg, model, critical,
    history) -> dict`` (optional: the validation's plot, closed forms and measured values) runs
    before the summary is written; its entries join the results."""
    cfg = cfg.validated()
    out = pathlib.Path(out)
    started = time.perf_counter()
    model = KaptonSpecimenFE(cfg.specimen, cfg.mesh, cfg.kapton)
    critical = model.critical_load()
    length = cfg.specimen.length
    model.add_imperfection(critical.mode, cfg.path.imperfection * length)
    schedule = model.compression_schedule(
        critical.shortening / length, cfg.run.compression, cfg.path
    )
    bar = Progress(100 * cfg.run.compression, "ribbon buckling (FE)", "%", enabled=progress)

    def row(step) -> dict:
        c, its = step
        return {
            "compression [-]": c,
            "end shortening [mm]": c * length,
            "force [N]": model.force(),
            "mid-span deflection [mm]": model.mid_deflection(),
            "newton iterations [-]": its,
        }

    def drive(on_step):
        """The compression schedule (the path follower's targets, one row each), from the start."""
        on_step((0.0, 0))
        return model.follow(schedule, on_step=lambda c, its: on_step((c, its)))

    def summarize(run, follower) -> dict:
        wall = time.perf_counter() - started
        history = run.history
        extra = report(out, cfg, model, critical, history) if report is not None else {}
        c, f = history.column("compression [-]"), history.column("force [N]")
        at = {p: float(np.interp(p, c, f)) for p in (0.1, 0.25, 0.5) if p <= c[-1] + 1e-12}
        return {
            "model": "fe",
            "results": {
                "critical load [N]": critical.force,
                "critical end shortening [mm]": critical.shortening,
                **(extra or {}),
                **{f"force at {100 * p:g} % compression [N]": v for p, v in at.items()},
                "force at final compression [N]": float(f[-1]),
                "final compression [-]": float(c[-1]),
                "force ratio final / critical [-]": float(f[-1] / critical.force),
                "elastica force ratio at final compression [-]": buckling.elastica_force_ratio(
                    float(c[-1])
                ),
            },
            "dofs": model.ndofs,
            "increments": len(schedule),
            "newton_iterations": follower.iterations,
            "cut_steps": follower.cuts,
            "wall_time [s]": wall,
        }

    history = HistoryExport(
        tuple(FE_COLUMNS),
        row,
        where=lambda step: f"compression {step[0]:.4g}",
        at=lambda step: 100 * step[0],
    )
    fields = FEFields(
        "displacement.bp", (model.u,), model.tmesh.mesh.comm, lambda step: step[0], start=False
    )
    # the load fraction [-] of a state: its compression over the run's
    problem = PathProblem(
        drive, clock=LOAD, at=lambda step: step[0] / cfg.run.compression, comm=model.tmesh.mesh.comm
    )
    return run(
        problem,
        problem.program(),
        [StateHistory(history), StateExport(fields)],
        out,
        config=cfg.resolved(),
        progress=bar,
        summarize=lambda skeleton, records: summarize(skeleton, records[-1].detail),
    )
