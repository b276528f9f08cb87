"""The composite beam (seed 001, Fig. 3) in the bar-and-hinge model: actuated by prescribing the
strips' relative lengths lambda_T and lambda_B (the paper's quasi-static route). The rest lengths
are ramped linearly from the as-built (nematic) lengths to lambda/lambda_N times them; statically
determinate supports at the middle panel; the curvature is measured by
:func:`lcefem.solvers.analysis.curvature.beam_curvature`. Used by ``lcefem run beam``, the
validation cases and the benchmarks.

* :func:`setup_beam` — structure, model, held DOFs and the ramp, built before solving;
* :func:`solve_beam` — the ramp from the as-built state
  (:func:`lcefem.solvers.bar_hinge.follow_path`);
* :class:`CompositeBeamBH` — the same beam as a problem (the Problem protocol: drives lambda per
  strip tag, advance, observables, save/restore);
* :class:`BeamConfig`, :func:`run_beam` — ``lcefem run beam``: the configuration sections and one
  run through the run skeleton (history.csv, beam.pvd + beam_steps/*.vtp, summary.json).

Units: mm, N, mJ.
"""

from __future__ import annotations

import pathlib
import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from lcefem.meshes.bar_hinge_structure import BarHingeStructure
from lcefem.meshes.composite_beam import (
    BeamBarHingeMesh,
    CompositeBeamGeometry,
    build_beam_bar_hinge,
)
from lcefem.models.bar_hinge_materials import BarHingeMaterials
from lcefem.models.empirical import Eq2, eq2_curvature
from lcefem.models.errors import InputError
from lcefem.models.limits import check_lambda
from lcefem.models.parameters import param
from lcefem.solvers.analysis.curvature import beam_curvature
from lcefem.solvers.bar_hinge import (
    BarHingeModel,
    NewtonOptions,
    PathOptions,
    PathResult,
    PathState,
    follow_path,
    isostatic_supports,
)
from lcefem.solvers.bar_hinge.strip_beams import bar_hinge_model
from lcefem.solvers.exports import BarHingeFrames
from lcefem.solvers.problems.protocol import LOAD, StepRecord, check_quasi_static_step, path_record
from lcefem.solvers.program import Program
from lcefem.solvers.runner import HistoryExport, run_quasi_static
from lcefem.solvers.runtime.checks import check_config, resolved
from lcefem.solvers.runtime.run import Progress

#: Default stepping of the actuation ramp (see PathOptions).
BEAM_PATH = PathOptions(initial_increment=0.05, max_increment=0.2, easy_iterations=10)


@dataclass
class BeamSolution:
    lambda_top: float
    lambda_bottom: float
    structure: BarHingeStructure
    model: BarHingeModel
    path: PathResult
    curvature: float  # [1/mm], at the end of the ramp

    @property
    def final(self) -> PathState:
        return self.path.states[-1]


def beam_load(
    model: BarHingeModel, lambda_top: float, lambda_bottom: float, held: np.ndarray
) -> Callable[[float], np.ndarray]:
    """Load path t -> held DOF values: rest fractions f(t) = 1 + t (lambda/lambda_N - 1)."""
    targets = {
        "top_strips": float(model.lce.rest_fraction(lambda_top)),
        "bottom_strips": float(model.lce.rest_fraction(lambda_bottom)),
    }
    names = {b.name for b in model.strip_sets()}
    fixed = model.reference.reshape(-1)[held].copy()

    def load(t: float) -> np.ndarray:
        model.set_rest_fractions({k: 1.0 + t * (v - 1.0) for k, v in targets.items() if k in names})
        return fixed

    return load


def lambdas_at(
    t: float, lambda_top: float, lambda_bottom: float, lambda_N: float
) -> tuple[float, float]:
    """(lambda_T, lambda_B) along the linear ramp at load factor t."""
    return (lambda_N + t * (lambda_top - lambda_N), lambda_N + t * (lambda_bottom - lambda_N))


@dataclass
class BeamSetup:
    """The beam's structure, model, held DOFs and load path, built before solving."""

    lambda_top: float
    lambda_bottom: float
    structure: BarHingeStructure
    model: BarHingeModel
    held: np.ndarray
    load: Callable[[float], np.ndarray]


def setup_beam(
    lambda_top: float,
    lambda_bottom: float,
    geometry: CompositeBeamGeometry = CompositeBeamGeometry(),
    mesh: BeamBarHingeMesh = BeamBarHingeMesh(),
    materials: BarHingeMaterials = BarHingeMaterials(),
) -> BeamSetup:
    """Structure, model, statically determinate supports at the middle panel, and the ramp."""
    lam_n = materials.lce.lambda_N
    check_lambda("lambda_top", lambda_top, lam_n)
    check_lambda("lambda_bottom", lambda_bottom, lam_n)
    structure = build_beam_bar_hinge(geometry, mesh)
    model = bar_hinge_model(structure, materials)
    held = isostatic_supports(*structure.node_sets["centre_support"])
    return BeamSetup(
        lambda_top,
        lambda_bottom,
        structure,
        model,
        held,
        beam_load(model, lambda_top, lambda_bottom, held),
    )


def solve_beam(
    lambda_top: float,
    lambda_bottom: float,
    geometry: CompositeBeamGeometry = CompositeBeamGeometry(),
    mesh: BeamBarHingeMesh = BeamBarHingeMesh(),
    materials: BarHingeMaterials = BarHingeMaterials(),
    *,
    newton_options: NewtonOptions = NewtonOptions(),
    path: PathOptions = BEAM_PATH,
    on_step: Callable[[PathState], None] | None = None,
    progress: Callable[[float], None] | None = None,
    setup: BeamSetup | None = None,
) -> BeamSolution:
    """Composite beam at (lambda_T, lambda_B), ramped from the as-built state (see module
    docstring).

    ``setup`` (from :func:`setup_beam` with the same arguments) lets a caller hold the model, e.g.
    to write bar forces in ``on_step``.
    """
    setup = setup or setup_beam(lambda_top, lambda_bottom, geometry, mesh, materials)
    result = follow_path(
        setup.model,
        setup.structure.nodes,
        setup.held,
        setup.load,
        newton_options=newton_options,
        path_options=path,
        on_step=on_step,
        progress=progress,
    )
    return BeamSolution(
        lambda_top,
        lambda_bottom,
        setup.structure,
        setup.model,
        result,
        beam_curvature(setup.structure, result.states[-1].x),
    )


class CompositeBeamBH:
    """The bar-and-hinge beam as a problem (lcefem.solvers.problems.protocol.Problem): the strips'
    relative lengths lambda_T, lambda_B [-] are the drives (tags ``top_strips``, ``bottom_strips``),
    reached by :meth:`advance` along the path follower from the present state, the rest fractions
    ramped linearly as in :func:`solve_beam` (which is the same path in one call)."""

    drive = "lambda [-]"

    def __init__(
        self,
        geometry: CompositeBeamGeometry = CompositeBeamGeometry(),
        mesh: BeamBarHingeMesh = BeamBarHingeMesh(),
        materials: BarHingeMaterials = BarHingeMaterials(),
        *,
        newton_options: NewtonOptions = NewtonOptions(),
        path: PathOptions = BEAM_PATH,
    ):
        self.lambda_N = materials.lce.lambda_N
        self.newton_options, self.path = newton_options, path
        setup = setup_beam(self.lambda_N, self.lambda_N, geometry, mesh, materials)
        self.structure, self.model, self.held = setup.structure, setup.model, setup.held
        self._fixed = self.model.reference.reshape(-1)[self.held].copy()
        self.x = self.structure.nodes.copy()
        self.lambdas = {tag: self.lambda_N for tag in self.drive_tags()}  # reached [-]
        self.targets = dict(self.lambdas)  # set [-]

    def drive_tags(self) -> tuple[str, ...]:
        present = {b.name for b in self.model.strip_sets()}
        return tuple(t for t in ("top_strips", "bottom_strips") if t in present)

    def set_drives(self, drives) -> None:
        for tag, value in drives.items():
            if tag not in self.drive_tags():
                raise InputError(
                    f"drive {tag!r}: not a strip tag of the beam (allowed "
                    f"{', '.join(self.drive_tags())})"
                )
            self.targets[tag] = check_lambda(f"lambda[{tag}]", value, self.lambda_N)

    def advance(
        self,
        dt: float = 1.0,
        on_step: Callable[[PathState], None] | None = None,
        progress: Callable[[float], None] | None = None,
    ) -> StepRecord:
        """The fraction ``dt`` (0 < dt <= 1) of the way from the present lambdas to the targets,
        the rest fractions f = lambda/lambda_N ramped linearly (from the as-built state the ramp of
        :func:`beam_load`, to the last bit); ``on_step(state)`` after every converged increment
        (its ``t`` the fraction of this advance), ``progress(t)``. Raises ConvergenceError (the
        present state is kept)."""
        frac = check_quasi_static_step(dt)
        start = dict(self.lambdas)
        goal = {k: start[k] + frac * (self.targets[k] - start[k]) for k in start}
        f0 = {k: float(self.model.lce.rest_fraction(v)) for k, v in start.items()}
        f1 = {k: float(self.model.lce.rest_fraction(v)) for k, v in goal.items()}

        def load(t: float) -> np.ndarray:
            self.model.set_rest_fractions({k: f0[k] + t * (f1[k] - f0[k]) for k in start})
            return self._fixed

        self._ramp = (f0, f1, frac)

        try:
            result = follow_path(
                self.model,
                self.x,
                self.held,
                load,
                newton_options=self.newton_options,
                path_options=self.path,
                on_step=on_step,
                progress=progress,
            )
        except Exception:
            self.model.set_rest_fractions({k: v / self.lambda_N for k, v in start.items()})
            raise
        self.x, self.lambdas = result.states[-1].x.copy(), goal
        self.model.set_rest_fractions({k: v / self.lambda_N for k, v in goal.items()})
        return path_record(frac, self.observables(), result)

    def increment_record(self, state: PathState) -> StepRecord:
        """The :class:`StepRecord` of one converged increment of :meth:`advance` (``at``: its
        fraction of the way; the one door, lcefem.solvers.runner.run, records every increment)."""
        f0, f1, frac = self._ramp
        lambdas = {k: (f0[k] + state.t * (f1[k] - f0[k])) * self.lambda_N for k in f0}
        return StepRecord(
            state.t * frac,
            {
                **{f"lambda {k} [-]": v for k, v in lambdas.items()},
                "curvature [1/mm]": float(beam_curvature(self.structure, state.x)),
            },
            state.iterations,
            clock=LOAD,
            detail=state,
        )

    def observables(self) -> dict[str, float]:
        return {
            **{f"lambda {k} [-]": v for k, v in self.lambdas.items()},
            "curvature [1/mm]": float(beam_curvature(self.structure, self.x)),
        }

    def fields(self) -> dict:
        return {"node positions [mm]": self.x}

    def save_state(self) -> dict:
        return {"x": self.x.copy(), "lambdas": dict(self.lambdas), "targets": dict(self.targets)}

    def restore_state(self, state: dict) -> None:
        self.x = state["x"].copy()
        self.lambdas, self.targets = dict(state["lambdas"]), dict(state["targets"])
        self.model.set_rest_fractions({k: v / self.lambda_N for k, v in self.lambdas.items()})


# -- one run (``lcefem run beam``) ---------------------------------------------------------------
@dataclass(frozen=True)
class BeamRun:
    """What the experimenter sets: the strips' relative lengths."""

    lambda_top: float = param(1.33, "-", "seed 001 Fig. 4C (dome): lambda_T = 1.33", minimum=1.0)
    lambda_bottom: float = param(1.05, "-", "seed 001 Fig. 4C (dome): lambda_B = 1.05", minimum=1.0)


@dataclass(frozen=True)
class BeamConfig(BarHingeMaterials):
    """The bar-and-hinge beam's sections: its materials (kapton, lce, glue, strip_contact, contact,
    ogden: inherited from the one definition,
    :class:`lcefem.models.bar_hinge_materials.BarHingeMaterials`) plus the run, geometry, mesh, Eq.
    2 and solver sections."""

    run: BeamRun = field(default_factory=BeamRun)
    geometry: CompositeBeamGeometry = field(default_factory=CompositeBeamGeometry)
    mesh: BeamBarHingeMesh = field(default_factory=BeamBarHingeMesh)
    eq2: Eq2 = field(default_factory=Eq2)
    solver: NewtonOptions = field(default_factory=NewtonOptions)
    path: PathOptions = field(default_factory=lambda: BEAM_PATH)

    def validated(self) -> "BeamConfig":
        check_config(self)
        self.geometry.checked()
        self.mesh.checked()
        for name in ("lambda_top", "lambda_bottom"):
            check_lambda(f"run.{name}", getattr(self.run, name), self.lce.lambda_N)
        return self

    def resolved(self) -> dict:
        return resolved(self)


COLUMNS = [
    "load factor [-]",
    "lambda_top [-]",
    "lambda_bottom [-]",
    "curvature [1/mm]",
    "eq2 curvature [1/mm]",
    "bottom strip force [N]",
    "top strip force [N]",
    "newton iterations [-]",
]
SIGN_CONVENTION = (
    "positive when the beam bends towards its bottom strips (top strips longer), as Eq. 2; "
    "circle fit through the middle stations"
)


def beam_problem(config: BeamConfig) -> CompositeBeamBH:
    """The bar-and-hinge beam of a (validated) configuration."""
    cfg = config.validated()
    return CompositeBeamBH(
        cfg.geometry, cfg.mesh, cfg.materials, newton_options=cfg.solver, path=cfg.path
    )


def beam_program(config: BeamConfig) -> Program:
    """The run section as a load program: the strips' lambdas reached in one advance, a record per
    converged increment (no start row, as the beam's history)."""
    return Program.quasi_static(
        {"top_strips": config.run.lambda_top, "bottom_strips": config.run.lambda_bottom},
        record_start=False,
    )


def run_beam(config: BeamConfig, out: pathlib.Path, progress: bool = True, report=None) -> dict:
    """Drive :class:`CompositeBeamBH` to ``config.run``'s lambdas through the runner
    (:func:`lcefem.solvers.runner.run_quasi_static`) and write history.csv (:data:`COLUMNS`),
    beam.pvd + beam_steps/*.vtp and summary.json into ``out``; returns the summary.
    ``report(out, config, solution, history) -> dict`` (optional: the validation's plots and notes)
    runs before the summary is written; its entries join the results."""
    cfg = config.validated()
    out = pathlib.Path(out)
    lam_t, lam_b, lam_n = cfg.run.lambda_top, cfg.run.lambda_bottom, cfg.lce.lambda_N
    problem = beam_problem(cfg)
    structure, model = problem.structure, problem.model

    def row(state) -> dict:
        forces = model.bar_forces(state.x)
        lt, lb = lambdas_at(state.t, lam_t, lam_b, lam_n)
        return {
            "load factor [-]": state.t,
            "lambda_top [-]": lt,
            "lambda_bottom [-]": lb,
            "curvature [1/mm]": beam_curvature(structure, state.x),
            "eq2 curvature [1/mm]": float(eq2_curvature(lt, lb, cfg.eq2)),
            "bottom strip force [N]": 2.0 * float(np.mean(forces["bottom_strips"])),
            "top strip force [N]": 2.0 * float(np.mean(forces["top_strips"]))
            if "top_strips" in forces
            else 0.0,
            "newton iterations [-]": state.iterations,
        }

    started = time.perf_counter()

    def summarize(run, path: PathResult) -> dict:
        solution = BeamSolution(
            lam_t, lam_b, structure, model, path, beam_curvature(structure, path.states[-1].x)
        )
        history = run.history
        extra = report(out, cfg, solution, history) if report is not None else {}
        return {
            "model": "bar-hinge",
            "results": {
                "curvature [1/mm]": solution.curvature,
                "eq2 curvature [1/mm]": float(eq2_curvature(lam_t, lam_b, cfg.eq2)),
                **(extra or {}),
                "sign convention": SIGN_CONVENTION,
                "bottom strip force [N]": float(history.column("bottom strip force [N]")[-1]),
                "top strip force [N]": float(history.column("top strip force [N]")[-1]),
            },
            "dofs": int(model.ndof),
            "nodes": int(structure.num_nodes),
            "increments": len(path.states) - 1,
            "newton_iterations": int(sum(path.newton_iterations)),
            "failed_increments": path.failed_increments,
            "wall_time [s]": time.perf_counter() - started,
        }

    drives = {
        tag: {"top_strips": lam_t, "bottom_strips": lam_b}[tag] for tag in problem.drive_tags()
    }
    return run_quasi_static(
        problem,
        drives,
        out,
        config=cfg.resolved(),
        history=HistoryExport(tuple(COLUMNS), row),
        fields=BarHingeFrames("beam", structure, model),
        progress=Progress(
            1.0, f"beam lambda_T={lam_t:g} lambda_B={lam_b:g}", "load", ".3f", progress
        ),
        summarize=summarize,
    )
