"""The passive Kapton buckling specimen (seed 001, Fig. 2G) in the bar-and-hinge model, fixed-fixed.

* :func:`solve_specimen_buckling` — the specimen shortened by a prescribed end displacement; force
  from the reaction at the moving clamp.
* :func:`critical_load` — the bifurcation load of the perfect (flat) specimen: the end shortening at
  which the tangent stiffness of the straight equilibrium first loses positive definiteness
  (Sylvester inertia of the sparse LDL^T), found by bisection.
* :class:`KaptonSpecimenBH` — the same specimen as a problem object (drive: end shortening [mm]).
* Closed forms: :mod:`lcefem.models.buckling` (Euler, elastica),
  :func:`lcefem.models.bar_hinge.n5b8_ribbon_bending_stiffness`; :func:`closed_forms` of a
  configuration.
* :class:`KaptonSpecimenConfig`, :func:`run_specimen` — ``lcefem run ribbon-buckling``: the
  configuration sections and one run through the run skeleton (history.csv, ribbon.pvd +
  ribbon_steps/*.vtp, summary.json).

Units: mm, N, mJ.
"""

from __future__ import annotations

import pathlib
import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from lcefem.meshes.bar_hinge_structure import BarHingeStructure
from lcefem.meshes.kapton_ribbon import (
    KaptonBarHingeMesh,
    KaptonSpecimenGeometry,
    build_ribbon_bar_hinge,
)
from lcefem.models import bar_hinge as law
from lcefem.models import bar_hinge_materials as bhm
from lcefem.models import buckling
from lcefem.models.bar_hinge_materials import BarHingeMaterials
from lcefem.models.errors import InputError
from lcefem.models.parameters import param
from lcefem.solvers.bar_hinge import (
    BarHingeModel,
    NewtonOptions,
    PathOptions,
    PathResult,
    PathState,
    follow_path,
    held_dofs,
    newton,
)
from lcefem.solvers.exports import BarHingeFrames
from lcefem.solvers.problems.protocol import LOAD, StepRecord, check_quasi_static_step, path_record
from lcefem.solvers.runner import HistoryExport, run_quasi_static
from lcefem.solvers.runtime.checks import check_config, resolved
from lcefem.solvers.runtime.run import Progress

#: Default stepping of the end shortening (0 -> 50 %); small increments resolve the force curve.
SPECIMEN_PATH = PathOptions(initial_increment=0.01, max_increment=0.02, easy_iterations=10)


@dataclass
class KaptonSpecimenSolution:
    structure: BarHingeStructure
    model: BarHingeModel
    path: PathResult
    compression: np.ndarray  # end shortening / free length [-], per state
    force: np.ndarray  # compressive force [N], per state
    max_compression: float


def specimen_model(
    specimen: KaptonSpecimenGeometry, mesh: KaptonBarHingeMesh, materials: BarHingeMaterials
):
    """(structure, model, held DOFs of the left clamp, of the right clamp)."""
    structure = build_ribbon_bar_hinge(specimen, mesh)
    model = BarHingeModel.from_materials(structure, materials)
    left = held_dofs(structure.node_sets["left_clamp"])
    right = held_dofs(structure.node_sets["right_clamp"])
    return structure, model, left, right


def compressive_force(reactions: np.ndarray, held: np.ndarray, right_x: np.ndarray) -> float:
    """Compressive end force [N]: minus the x-forces the supports apply to the moving clamp (the
    gradient of the energy at the held DOFs is the force the supports apply)."""
    mask = np.isin(held, right_x)
    return -float(np.sum(reactions[mask]))


@dataclass
class KaptonSpecimenSetup:
    """The specimen's structure, model, held DOFs and end-shortening path, built before solving."""

    specimen: KaptonSpecimenGeometry
    max_compression: float
    structure: BarHingeStructure
    model: BarHingeModel
    held: np.ndarray
    right_x: np.ndarray  # x DOFs of the moving clamp
    load: Callable[[float], np.ndarray]

    def force(self, state: PathState) -> float:
        """Compressive force [N] at a converged state."""
        return compressive_force(state.reactions, self.held, self.right_x)


def setup_specimen(
    max_compression: float = 0.5,
    specimen: KaptonSpecimenGeometry = KaptonSpecimenGeometry(),
    mesh: KaptonBarHingeMesh = KaptonBarHingeMesh(),
    materials: BarHingeMaterials = BarHingeMaterials(),
) -> KaptonSpecimenSetup:
    """Clamps held, the right one moved by -t * max_compression * length along x."""
    if not isinstance(max_compression, (int, float)) or not 0.0 < max_compression < 0.95:
        raise InputError(
            f"compression = {max_compression}: must be in (0, 0.95) (end shortening / free length)"
        )
    structure, model, left, right = specimen_model(specimen, mesh, materials)
    held = np.concatenate([left, right])
    right_x = right[right % 3 == 0]
    base = structure.nodes.reshape(-1)[held].copy()
    shift = np.where(np.isin(held, right_x), -max_compression * specimen.length, 0.0)
    return KaptonSpecimenSetup(
        specimen,
        float(max_compression),
        structure,
        model,
        held,
        right_x,
        lambda t: base + t * shift,
    )


def solve_specimen_buckling(
    max_compression: float = 0.5,
    specimen: KaptonSpecimenGeometry = KaptonSpecimenGeometry(),
    mesh: KaptonBarHingeMesh = KaptonBarHingeMesh(),
    materials: BarHingeMaterials = BarHingeMaterials(),
    *,
    newton_options: NewtonOptions = NewtonOptions(),
    path: PathOptions = SPECIMEN_PATH,
    on_step: Callable[[PathState], None] | None = None,
    progress: Callable[[float], None] | None = None,
    setup: KaptonSpecimenSetup | None = None,
) -> KaptonSpecimenSolution:
    """Fixed-fixed specimen shortened to ``max_compression`` of its free length (displacement
    control).

    The compressive force is the sum of the x-components of the internal forces on the right
    clamp's nodes (the reaction the testing machine applies).
    """
    setup = setup or setup_specimen(max_compression, specimen, mesh, materials)
    forces: list[float] = []

    def record(state: PathState) -> None:
        forces.append(setup.force(state))
        if on_step is not None:
            on_step(state)

    result = follow_path(
        setup.model,
        setup.structure.nodes,
        setup.held,
        setup.load,
        newton_options=newton_options,
        path_options=path,
        on_step=record,
        progress=progress,
    )
    compression = np.array([s.t * setup.max_compression for s in result.states])
    return KaptonSpecimenSolution(
        setup.structure, setup.model, result, compression, np.array(forces), setup.max_compression
    )


def critical_load(
    specimen: KaptonSpecimenGeometry = KaptonSpecimenGeometry(),
    mesh: KaptonBarHingeMesh = KaptonBarHingeMesh(),
    materials: BarHingeMaterials = BarHingeMaterials(),
    *,
    rel_tol: float = 1e-4,
) -> tuple[float, float]:
    """Bifurcation of the perfect (flat) specimen: (critical compressive force [N], end shortening
    [mm]).

    Along the straight path (imperfection 0) the equilibrium is computed with plain Newton (no
    inertia control, so it stays straight) and the number of negative pivots of the tangent is
    counted; the first end shortening where it becomes positive is bracketed by doubling and
    refined by bisection to ``rel_tol``.
    """
    flat = KaptonBarHingeMesh(panels=mesh.panels, clamp_length=mesh.clamp_length, imperfection=0.0)
    structure, model, left, right = specimen_model(specimen, flat, materials)
    held = np.concatenate([left, right])
    right_x = right[right % 3 == 0]
    free = np.setdiff1d(np.arange(model.ndof), held)
    plain = NewtonOptions(inertia_control=False)
    base = structure.nodes.reshape(-1).copy()

    def state(shortening: float):
        # Start from the straight state under uniform strain (x = X (1 - e/L) inside the span).
        x = base.copy()
        x[right_x] -= shortening
        inner = free[free % 3 == 0]
        x[inner] = base[inner] * (1.0 - shortening / specimen.length)
        res = newton(model, x, free, plain)
        if not res.converged:
            raise RuntimeError(f"straight path lost at shortening {shortening} mm: {res.reason}")
        grad = model.evaluate(res.x, derivatives=1)[1]
        return res.negative_pivots, -float(np.sum(grad[right_x]))

    lo, hi = 0.0, 1e-4 * specimen.length
    while state(hi)[0] == 0:
        lo, hi = hi, 2.0 * hi
        if hi > 0.5 * specimen.length:
            raise RuntimeError("no bifurcation up to 50 % shortening")
    while hi - lo > rel_tol * hi:
        mid = 0.5 * (lo + hi)
        if state(mid)[0] == 0:
            lo = mid
        else:
            hi = mid
    return state(lo)[1], lo


class KaptonSpecimenBH:
    """The bar-and-hinge specimen as a problem (lcefem.solvers.problems.protocol.Problem): the
    right clamp's end shortening [mm] is the drive, reached by :meth:`advance` along the path
    follower from the present state (:func:`solve_specimen_buckling` is the same path in one
    call)."""

    drive = "end shortening [mm]"

    def __init__(
        self,
        specimen: KaptonSpecimenGeometry = KaptonSpecimenGeometry(),
        mesh: KaptonBarHingeMesh = KaptonBarHingeMesh(),
        materials: BarHingeMaterials = BarHingeMaterials(),
        *,
        newton_options: NewtonOptions = NewtonOptions(),
        path: PathOptions = SPECIMEN_PATH,
    ):
        self.specimen, self.newton_options, self.path = specimen, newton_options, path
        self.structure, self.model, left, right = specimen_model(specimen, mesh, materials)
        self.held = np.concatenate([left, right])
        self.right_x = right[right % 3 == 0]
        self._base = self.structure.nodes.reshape(-1)[self.held].copy()
        self._moving = np.isin(self.held, self.right_x)
        self.x = self.structure.nodes.copy()
        self.shortening = self.target_shortening = 0.0  # [mm]
        self.force = 0.0  # [N] compressive, at the present state

    def drive_tags(self) -> tuple[str, ...]:
        return ("right_clamp",)  # the moved clamp's node set; left_clamp is held

    def set_drives(self, drives) -> None:
        for tag, value in drives.items():
            if tag not in self.drive_tags():
                raise InputError(
                    f"drive {tag!r}: not a driven clamp of the specimen (allowed right_clamp)"
                )
            if (
                not isinstance(value, (int, float))
                or not 0.0 <= value < 0.95 * self.specimen.length
            ):
                raise InputError(
                    f"end shortening[{tag}] = {value} mm: must be in [0, "
                    f"{0.95 * self.specimen.length:g}) mm (95 % of the free length)"
                )
            self.target_shortening = float(value)

    def advance(
        self,
        dt: float = 1.0,
        on_step: Callable[[PathState], None] | None = None,
        progress: Callable[[float], None] | None = None,
    ) -> StepRecord:
        """The fraction ``dt`` (0 < dt <= 1) of the way from the present end shortening to the
        target (from the flat specimen the path of :func:`setup_specimen`, to the last bit);
        ``on_step(state)`` after every converged increment, ``progress(t)``. Raises
        ConvergenceError (the present state is kept)."""
        start = self.shortening
        goal = start + check_quasi_static_step(dt) * (self.target_shortening - start)
        self._ramp = (start, goal, dt)
        result = follow_path(
            self.model,
            self.x,
            self.held,
            lambda t: self._base - np.where(self._moving, start + t * (goal - start), 0.0),
            newton_options=self.newton_options,
            path_options=self.path,
            on_step=on_step,
            progress=progress,
        )
        last = result.states[-1]
        self.x, self.shortening = last.x.copy(), goal
        self.force = compressive_force(last.reactions, self.held, self.right_x)
        return path_record(dt, self.observables(), result)

    def increment_record(self, state: PathState) -> StepRecord:
        """The :class:`StepRecord` of one converged increment of :meth:`advance` (``at``: its
        fraction of the way; the one door, lcefem.solvers.runner.run, records every increment)."""
        start, goal, frac = self._ramp
        d = start + state.t * (goal - start)
        return StepRecord(
            state.t * frac,
            self._observe(d, compressive_force(state.reactions, self.held, self.right_x), state.x),
            state.iterations,
            clock=LOAD,
            detail=state,
        )

    def _observe(self, shortening: float, force: float, x) -> dict[str, float]:
        mid = np.argmin(
            np.abs(self.structure.nodes[:, 0] - 0.5 * self.specimen.length)
            + np.abs(self.structure.nodes[:, 1])
        )
        return {
            "end shortening [mm]": shortening,
            "compression [-]": shortening / self.specimen.length,
            "force [N]": force,
            "mid-span deflection [mm]": float(x[mid, 2] - self.structure.nodes[mid, 2]),
        }

    def observables(self) -> dict[str, float]:
        return self._observe(self.shortening, self.force, self.x)

    def fields(self) -> dict:
        return {"node positions [mm]": self.x}

    def save_state(self) -> dict:
        return {
            "x": self.x.copy(),
            "shortening": self.shortening,
            "target": self.target_shortening,
            "force": self.force,
        }

    def restore_state(self, state: dict) -> None:
        self.x = state["x"].copy()
        self.shortening, self.target_shortening, self.force = (
            state["shortening"],
            state["target"],
            state["force"],
        )


# -- one run (``lcefem run ribbon-buckling``) ---------------------------------------------------
@dataclass(frozen=True)
class KaptonSpecimenRun:
    """What the experimenter sets: how far to shorten the specimen."""

    compression: float = param(
        0.5,
        "-",
        "seed 001 Fig. 2G: compression up to 50 % (end shortening over length)",
        positive=True,
        maximum=0.9,
    )


@dataclass(frozen=True)
class KaptonSpecimenConfig:
    run: KaptonSpecimenRun = field(default_factory=KaptonSpecimenRun)
    specimen: KaptonSpecimenGeometry = field(default_factory=KaptonSpecimenGeometry)
    mesh: KaptonBarHingeMesh = field(default_factory=KaptonBarHingeMesh)
    kapton: bhm.KaptonBarHinge = field(default_factory=bhm.KaptonBarHinge)
    solver: NewtonOptions = field(default_factory=NewtonOptions)
    path: PathOptions = field(default_factory=lambda: SPECIMEN_PATH)

    def validated(self) -> "KaptonSpecimenConfig":
        check_config(self)
        self.specimen.checked()
        self.mesh.checked()
        return self

    @property
    def materials(self) -> BarHingeMaterials:
        return BarHingeMaterials(kapton=self.kapton)

    def resolved(self) -> dict:
        return resolved(self)


def closed_forms(cfg: KaptonSpecimenConfig) -> dict[str, float]:
    """Euler loads [N] of the specimen: datasheet EI, with the 5.5 factor, and the chain's own
    EI."""
    spec, kap = cfg.specimen, cfg.kapton
    ei = kap.youngs_modulus * spec.second_moment
    k = kap.hinge_stiffness(spec.thickness)
    ei_chain = law.n5b8_ribbon_bending_stiffness(k, spec.length / cfg.mesh.panels, spec.width)
    return {
        "Euler, E I (datasheet E)": buckling.euler_fixed_fixed(ei, spec.length),
        f"Euler, {kap.bending_factor:g} E I": buckling.euler_fixed_fixed(
            kap.bending_factor * ei, spec.length
        ),
        "Euler, bar-and-hinge chain EI": buckling.euler_fixed_fixed(ei_chain, spec.length),
    }


COLUMNS = ["compression [-]", "end shortening [mm]", "force [N]", "newton iterations [-]"]


def specimen_problem(config: KaptonSpecimenConfig) -> KaptonSpecimenBH:
    """The bar-and-hinge buckling specimen of a (validated) configuration."""
    cfg = config.validated()
    return KaptonSpecimenBH(
        cfg.specimen, cfg.mesh, cfg.materials, newton_options=cfg.solver, path=cfg.path
    )


def run_specimen(
    config: KaptonSpecimenConfig, out: pathlib.Path, progress: bool = True, report=None
) -> dict:
    """The bar-and-hinge buckling test: :class:`KaptonSpecimenBH` driven to ``run.compression``
    through the runner (:func:`lcefem.solvers.runner.run_quasi_static`; history.csv of
    :data:`COLUMNS`, ribbon.pvd + ribbon_steps/*.vtp), the critical load of the perfect specimen
    and the closed forms (summary.json); returns the summary.
    ``report(out, cfg, solution, critical_load [N], closed_forms) -> dict`` (optional: the
    validation's plot and measured values) runs before the summary is written; its entries join
    the results."""
    cfg = config.validated()
    out = pathlib.Path(out)
    problem = specimen_problem(cfg)
    model, length, compression_max = problem.model, cfg.specimen.length, cfg.run.compression

    def force(state) -> float:
        return compressive_force(state.reactions, problem.held, problem.right_x)

    def row(state) -> dict:
        c = state.t * compression_max
        return {
            "compression [-]": c,
            "end shortening [mm]": c * length,
            "force [N]": force(state),
            "newton iterations [-]": state.iterations,
        }

    started = time.perf_counter()

    def summarize(run, path: PathResult) -> dict:
        solution = KaptonSpecimenSolution(
            problem.structure,
            model,
            path,
            np.array([s.t * compression_max for s in path.states]),
            np.array([force(s) for s in path.states]),
            float(compression_max),
        )
        p_cr, shortening_cr = critical_load(cfg.specimen, cfg.mesh, cfg.materials)
        wall = time.perf_counter() - started
        euler = closed_forms(cfg)
        extra = report(out, cfg, solution, p_cr, euler) if report is not None else {}
        compression, force_ = solution.compression, solution.force
        return {
            "model": "bar-hinge",
            "results": {
                "critical load [N]": p_cr,
                "critical end shortening [mm]": shortening_cr,
                **(extra or {}),
                **{f"{k} [N]": v for k, v in euler.items()},
                "force at final compression [N]": float(force_[-1]),
                "final compression [-]": float(compression[-1]),
                "force ratio final / critical [-]": float(force_[-1] / p_cr),
                "elastica force ratio at final compression [-]": buckling.elastica_force_ratio(
                    float(compression[-1])
                ),
            },
            "dofs": int(model.ndof),
            "increments": len(path.states) - 1,
            "newton_iterations": int(sum(path.newton_iterations)),
            "failed_increments": path.failed_increments,
            "wall_time [s]": wall,
        }

    return run_quasi_static(
        problem,
        {"right_clamp": compression_max * length},
        out,
        config=cfg.resolved(),
        history=HistoryExport(tuple(COLUMNS), row),
        fields=BarHingeFrames("ribbon", problem.structure, model),
        progress=Progress(100 * compression_max, "ribbon buckling", "%", enabled=progress),
        summarize=summarize,
        progress_scale=100 * compression_max,
    )
