"""Inverse design of the robotic surface (seed 001, Fig. 4; issue 15): from target centre curvatures
(kappa_x, kappa_y) [1/mm] to strip lambdas, then to coil currents.

* Observables: the paper's measure for the gridshell without cover scales, the circle through the
  centre junction and the two ends of the middle x / y ribbon ("circle_x", "circle_y" of
  :func:`lcefem.solvers.analysis.curvature.gridshell_curvatures`; dome negative), optionally the
  centre junction's height [mm] (then a third residual, scaled by ``height_scale``).
* Design variables: one lambda per channel (Tx, Ty, Bx, By; seed 001, Fig. 4A) or per strip (all 42
  strips of the 3 x 3 grid independently), bounds [1.05, lambda_N] (1.05: the paper's most
  contracted setting; lambda_N: as built, slack).
* Numerics: :mod:`lcefem.solvers.bar_hinge.design` (exact sensitivities by the implicit function
  theorem, warm-started forward solves, scipy.optimize.least_squares with bounds).
* Currents: each lambda is turned into the current that holds a strip at it through the existing
  current route (:func:`lcefem.models.lumped_heat.stretch_from_current`, inverted by brentq):
  the "segment" route (our lumped 25 ohm segment) and the "eq1" route (the paper's Eq. 1 at the
  146.6 ohm strip coil). A lambda at lambda_N needs no current (0 A).
* The result is checked by a forward run from the as-built state at the lambdas found (the Newton
  settings and path of ``lcefem run gridshell``, :func:`forward_check`; :func:`reach`): "achieved"
  curvatures are from that run.

Units: mm, 1/mm, A, s.
"""

from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq, lsq_linear

from lcefem.meshes.bar_hinge_structure import BarHingeStructure
from lcefem.meshes.gridshell import CHANNELS, GridshellLayout
from lcefem.meshes.gridshell_layout import Layout
from lcefem.models import lumped_heat
from lcefem.models.bar_hinge_materials import PUBLISHED_LAMBDA_N, BarHingeMaterials
from lcefem.models.errors import ConvergenceError, InputError
from lcefem.solvers.analysis.curvature import centre_junction_point, gridshell_curvatures
from lcefem.solvers.bar_hinge import NewtonOptions
from lcefem.solvers.bar_hinge.design import (
    DesignResult,
    EquilibriumMap,
    solve_design,
    strip_parameters,
)
from lcefem.solvers.problems import gridshell_bh as problem_bh
from lcefem.solvers.problems.gridshell_bh import GridshellBH, GridshellBHConfig
from lcefem.solvers.problems.gridshell_bh_run import GridshellBHRunConfig
from lcefem.validation.studies.gridshell import calibrate
from lcefem.validation.studies.gridshell.calibrate import DEFAULT_MODEL_SET

#: Lower bound of the design lambdas [-]: the paper's most contracted Fig. 4 setting (seed 001,
#: Results: lambda = 1.05 for the contracted channels).
LAMBDA_MIN = 1.05
#: Residual scale of the curvatures [1/mm]: the paper reports them to 0.001 1/mm (seed 001).
CURVATURE_SCALE = 1.0e-3
#: Residual scale of the centre height [mm] (assumed: 0.1 mm, a caliper's reading).
HEIGHT_SCALE = 0.1
#: Forward solves inside the design loop converge to |g| <= 1e-8 N (the sensitivities are exact
#: only at an equilibrium; 1e-6 N leaves ~1e-7 1/mm of noise in the curvatures). Progress budget
#: (NewtonOptions.progress_iterations, as GRIDSHELL_NEWTON's): a warm-started solve whose energy
#: still falls goes on past max_iterations instead of halving its increment (the 5 x 5 layout's
#: design of benchmarks/layout_benchmark.py: 17 increments halved after 50 descending iterations
#: each, 124 s CPU; with the budget none, 49 s; docs/notes/performance_log.md, 2026-12-08).
DESIGN_NEWTON = NewtonOptions(force_tolerance=1.0e-8, progress_iterations=300)
CHANNEL_MODES = ("4", "all", "wiring")
#: A target counts as reached within this [1/mm] (a tenth of the round-trip tolerance): closer is
#: below what the equilibria resolve (contacts at their kinks leave nearby equilibria ~5e-6 1/mm
#: apart on the cylinder: the warm-started loop and the ramp from as built may end on either).
REACHED = 1.0e-5


def channel_selections(structure: BarHingeStructure, mode: str) -> list:
    """Design variables: the four channels ("4"), every strip id ("all") or the layout's wiring tags
    ("wiring": ``layout.wiring``, lcefem.meshes.gridshell_layout)."""
    if mode == "wiring":
        return list(structure.info["wiring"])
    if mode == "4":
        return list(CHANNELS)
    if mode == "all":
        return [s.id for s in structure.info["strips"]]
    raise InputError(f"design.channels = {mode!r}: allowed {', '.join(CHANNEL_MODES)}")


def curvature_observable(structure: BarHingeStructure, height: bool = False):
    """x (n, 3) -> (circle kappa_x, circle kappa_y [1/mm][, centre junction height [mm]])."""

    def obs(x):
        k = gridshell_curvatures(structure, x)
        out = [k["circle_x"], k["circle_y"]]
        if height:
            out.append(centre_junction_point(structure, x)[2])
        return np.asarray(out)

    return obs


#: A design lambda within this [-] of lambda_N is lambda_N (the strip unheated, 0 A). The current
#: that holds a lambda is discontinuous there: any lambda below lambda_N needs the current that
#: brings the strip to the onset of contraction (measured, 'strip' route: 0.0544 A for lambda_N -
#: 1e-12 as for lambda_N - 1e-6, FE-calibrated set; 0.0557 A published), lambda_N itself 0 A. The
#: bounded least squares leave lambdas a round-off below their bound (the measured saddle's program:
#: 7.2e-7 and 9.0e-7 below lambda_N), which printed 0.054 A on a channel meant to be off. Chosen:
#: 1e-5, ten times those; it moves a centre curvature by at most ~1e-6 1/mm (the channels'
#: sensitivity, ~0.1 1/mm per unit lambda: 0.03 1/mm over the 1.05-1.4 range, seed 001 Fig. 4), 1 %
#: of the design tolerance.
LAMBDA_SNAP = 1.0e-5


def snapped(p, lambda_N: float = PUBLISHED_LAMBDA_N) -> np.ndarray:
    """Design lambdas ``p`` [-] with those within :data:`LAMBDA_SNAP` of lambda_N set to
    lambda_N."""
    p = np.array(p, dtype=float)
    p[p >= lambda_N - LAMBDA_SNAP] = lambda_N
    return p


def current_for_lambda(
    lam: float,
    route: lumped_heat.CurrentRouteConfig = lumped_heat.CurrentRouteConfig(),
    lambda_N: float = PUBLISHED_LAMBDA_N,
) -> float:
    """Current [A] that holds a grid strip at ``lam`` through the route (inverse of
    :func:`~lcefem.models.lumped_heat.stretch_from_current`); 0 A for a lambda at or above the
    strip's unheated lambda, or within :data:`LAMBDA_SNAP` below it."""
    if lam >= lambda_N - LAMBDA_SNAP:
        return 0.0

    def f(i):
        with np.errstate(over="ignore"):  # Eq. 1's exponential at large powers: lambda -> 1
            return lumped_heat.stretch_from_current(i, route, lambda_N) - lam

    if f(0.0) <= 1e-12:
        return 0.0
    if f(1.0) > 0:
        raise InputError(
            f"lambda = {lam}: below what 1 A reaches through the {route.thermal_model} route"
        )
    return float(brentq(f, 0.0, 1.0, xtol=1e-12))


@dataclass
class GridshellDesign:
    """A design problem on one surface: structure, support, design variables and the map."""

    structure: BarHingeStructure
    support: str
    mode: str
    eq: EquilibriumMap
    lambda_N: float
    height: bool
    materials: BarHingeMaterials = dataclasses.field(default_factory=BarHingeMaterials)
    model_set: str = DEFAULT_MODEL_SET
    layout: GridshellLayout | None = None  # the grid the structure was built from (None: published)

    @property
    def names(self) -> list[str]:
        return self.eq.params.names


def setup_design(
    mode: str = "4",
    support: str = "rollers",
    height: bool = False,
    lambda_N: float = PUBLISHED_LAMBDA_N,
    layout: GridshellLayout = GridshellLayout(),
    newton: NewtonOptions = DESIGN_NEWTON,
    model_set: str = DEFAULT_MODEL_SET,
) -> GridshellDesign:
    """The design problem on a fresh surface (``layout``: ribbons per direction; ``model_set``: the
    bar-and-hinge elements and factors,
    :data:`lcefem.validation.studies.gridshell.calibrate.MODEL_SETS`)."""
    ms = calibrate.model_set(
        model_set
    )  # its mesh fields (strip element, squares, contact) and materials
    structure, materials = ms.structure(layout), ms.materials_for(layout)
    setup = problem_bh.setup_gridshell(None, support, structure=structure, materials=materials)
    params = strip_parameters(structure, channel_selections(structure, mode), lambda_N)
    eq = EquilibriumMap(
        setup.model,
        setup.held,
        params,
        curvature_observable(structure, height),
        newton_options=newton,
        path_options=problem_bh.GRIDSHELL_PATH,
    )
    return GridshellDesign(
        structure, support, mode, eq, lambda_N, height, materials, model_set, layout
    )


def inverse(
    design: GridshellDesign,
    kx: float,
    ky: float,
    height: float | None = None,
    p0=None,
    max_evaluations: int = 60,
    check: bool = True,
) -> DesignResult:
    """Lambdas whose equilibrium has centre curvatures (kx, ky) [1/mm] (and centre height [mm]),
    reached by the surface actuated from flat.

    The design loop (warm-started least squares from ``p0``, default mid-range) finds lambdas that
    hold the target on the branch it followed; with ``check`` (default), :func:`reach` then finds
    lambdas (or a program of drives) that the run's own path from flat takes to the target:
    ``result.check`` holds its curvatures [1/mm] and the :class:`Reach` ("reach"); ``result.p``
    stays the loop's lambdas (the printed design is ``reach.p``, :func:`design_summary`)."""
    target = [kx, ky] + ([height] if design.height else [])
    if design.height and height is None:
        raise InputError("design: a target height is needed when the height is an observable")
    scale = [CURVATURE_SCALE, CURVATURE_SCALE] + ([HEIGHT_SCALE] if design.height else [])
    n = design.eq.params.size
    p = np.full(n, 0.5 * (LAMBDA_MIN + design.lambda_N)) if p0 is None else np.asarray(p0, float)
    t0 = time.perf_counter()
    result = solve_design(
        design.eq,
        target,
        p,
        LAMBDA_MIN,
        design.lambda_N,
        scale=scale,
        absolute=REACHED / CURVATURE_SCALE,
        max_evaluations=max_evaluations,
    )
    if check:
        found = reach(design, kx, ky, result)
        result.check = {
            "circle_x": found.achieved[0],
            "circle_y": found.achieved[1],
            "seconds": found.seconds,
            "x": found.x,
            "reach": found,
        }
    result.seconds = time.perf_counter() - t0
    result.stats = dataclasses.replace(design.eq.stats)
    return result


#: The run's own path (``lcefem run gridshell``: :class:`GridshellBHRunConfig`'s solver and path,
#: the defaults of :func:`lcefem.solvers.problems.gridshell_bh_run.run_gridshell`). The forward
#: check IS this path: a design is judged by where the surface actuated from flat by the run ends,
#: not by another ramp. (The former check, 20 equal increments of 0.05, and this path can end on
#: different stable equilibria: FE-calibrated set, rollers, at the table design's lambdas the run's
#: path takes 7 increments to circle 0.0018082 1/mm, the equal increments 0.0016564 1/mm.)
RUN_CONFIG = GridshellBHRunConfig()
#: Design tolerance [1/mm]: a design is reached when the run's path from flat ends within this of
#: the target in both curvatures (the round-trip tolerance: a tenth of the 0.001 1/mm the paper
#: reports).
DESIGN_TOLERANCE = 1.0e-4


def run_stages(design: GridshellDesign, stages) -> dict:
    """The surface driven from as built through ``stages`` (design variables per stage, reached one
    after the other), each by the run's own path (:class:`GridshellBH.advance` with
    :data:`RUN_CONFIG`'s Newton and path settings): one stage is ``lcefem run gridshell --lambda``.
    Returns the final circle curvatures [1/mm], positions (n, 3) [mm] and CPU seconds."""
    t0 = time.process_time()
    surface = GridshellBH(
        design.structure,
        GridshellBHConfig(
            materials=design.materials,
            weight=RUN_CONFIG.weight,
            geometry=RUN_CONFIG.geometry,
            support=design.support,
            solver=RUN_CONFIG.solver,
            path=RUN_CONFIG.path,
        ),
    )
    for p in stages:
        surface.set_rest_fractions(design.eq.params.rest_fractions(np.asarray(p, dtype=float)))
        surface.advance(1.0)
    k = gridshell_curvatures(design.structure, surface.x)
    return {
        "circle_x": float(k["circle_x"]),
        "circle_y": float(k["circle_y"]),
        "x": surface.x.copy(),
        "seconds": time.process_time() - t0,
    }


def forward_check(design: GridshellDesign, p) -> dict:
    """Curvatures of ``lcefem run gridshell`` at design variables p: the run's own ramp from the
    as-built state (:func:`run_stages` with one stage)."""
    return run_stages(design, [p])


@dataclass
class Reach:
    """How the surface reaches a target from flat (:func:`reach`).

    ``kind``: "constant" (one set of lambdas, ``stages = [p]``: the run's ramp from flat lands on
    the target), "program" (a sequence of drives, each reached from the previous equilibrium: the
    last holds the target on the branch the earlier ones lead to), or "none" (neither found:
    ``stages`` is the closest constant design). ``achieved``: (kappa_x, kappa_y) [1/mm] at the end
    of the stages along the run's path; ``attempts``: every path tried (stages, achieved,
    distance)."""

    kind: str
    stages: list
    achieved: tuple
    distance: float
    attempts: list
    seconds: float  # CPU
    x: np.ndarray | None = None  # (n, 3) [mm]: the surface at the end of the stages

    @property
    def p(self) -> np.ndarray:
        return self.stages[-1]


def _distance(k: dict, target) -> float:
    return float(max(abs(k["circle_x"] - target[0]), abs(k["circle_y"] - target[1])))


def branch_jacobian(design: GridshellDesign, p, x) -> np.ndarray:
    """d(kappa_x, kappa_y)/dp [1/mm] of the equilibrium x at p (the branch x is on)."""
    design.eq.model.set_rest_fractions(design.eq.params.rest_fractions(p))
    return design.eq.jacobian(np.asarray(x).reshape(-1, 3))[:2]


def reach(
    design: GridshellDesign,
    kx: float,
    ky: float,
    loop: DesignResult,
    *,
    newton_steps: int = 3,
    tolerance: float = DESIGN_TOLERANCE,
    max_paths: int = 12,
) -> Reach:
    """Design variables the surface follows from flat to (kx, ky) [1/mm] along the run's own path.

    1. The design loop's lambdas (``loop``, warm-started: they hold the target on the branch the
       loop followed) are run from flat (:func:`forward_check`).
    2. Gauss-Newton on the residual along the run's path: r(p) = kappa(run from flat at p) - target,
       its Jacobian the exact one of the branch the run ends on (:func:`branch_jacobian`), the step
       a bounded least-squares one in [1.05, lambda_N]; every run is a *seed*: an equilibrium the
       surface reaches from flat.
    3. From each seed (those that landed farthest beyond the first run's branch toward the target
       first; the Gauss-Newton steps stop at the first such jump), the design loop continues on the
       seed's branch to the target (warm-started least squares); its lambdas p_f are run from flat
       (constant design) and, if that run ends on another branch, as the program [seed, p_f]:
       overshoot to the seed, then release to p_f.
    Stops at the first path within ``tolerance`` of the target (both curvatures); at most
    ``max_paths`` paths."""
    t0 = time.process_time()
    target = np.array([kx, ky])
    lo, hi = LAMBDA_MIN, design.lambda_N
    attempts: list[dict] = []

    def attempt(stages):
        stages = [snapped(s, design.lambda_N) for s in stages]
        try:
            r = run_stages(design, stages)
        except ConvergenceError as exc:
            attempts.append({"stages": stages, "failed": str(exc)})
            return None
        r["distance"] = _distance(r, target)
        attempts.append(
            {
                "stages": stages,
                "achieved": (r["circle_x"], r["circle_y"]),
                "distance": r["distance"],
                "seconds": r["seconds"],
            }
        )
        return r

    def done(kind, stages, r):  # the stages as run (attempt): lambdas near lambda_N snapped to it
        return Reach(
            kind,
            [snapped(s, design.lambda_N) for s in stages],
            (r["circle_x"], r["circle_y"]),
            r["distance"],
            attempts,
            time.process_time() - t0,
            r["x"],
        )

    p1 = np.asarray(loop.p, dtype=float)
    r1 = attempt([p1])
    if r1 is not None and r1["distance"] <= tolerance:
        return done("constant", [p1], r1)
    if r1 is None:  # the run from flat at the loop's lambdas finds no equilibrium: nothing to seed
        return Reach(
            "none",
            [p1],
            (float("nan"), float("nan")),
            float("inf"),
            attempts,
            time.process_time() - t0,
        )
    k1 = np.array([r1["circle_x"], r1["circle_y"]])
    jac1 = branch_jacobian(design, p1, r1["x"])
    toward = (target - k1) / max(float(np.linalg.norm(target - k1)), 1e-30)

    def past(ps, rs) -> float:
        """How far [1/mm] the run from flat at ps ended beyond the first run's branch (its tangent
        at p1), toward the target: > 0 for a run that jumped to another branch on the target's
        side."""
        return float(
            (np.array([rs["circle_x"], rs["circle_y"]]) - (k1 + jac1 @ (ps - p1))) @ toward
        )

    seeds = [(p1, r1)]
    p, r = p1, r1
    for _ in range(newton_steps):
        k = np.array([r["circle_x"], r["circle_y"]])
        jac = branch_jacobian(design, p, r["x"])
        step = lsq_linear(jac, target - k, bounds=(lo - p + 1e-12, hi - p - 1e-12)).x
        p_new = np.clip(p + step, lo, hi)
        r_new = attempt([p_new])
        if r_new is None:
            break
        if r_new["distance"] <= tolerance:
            return done("constant", [p_new], r_new)
        seeds.append((p_new, r_new))
        if past(p_new, r_new) > tolerance:  # on another branch, past the target: continue from it
            break
        p, r = p_new, r_new
    # Seeds on the target's side of the first run's branch first (measured saddle on rollers: the
    # second Gauss-Newton run lands on the other branch, beyond the target: the program starts
    # there).
    seeds.sort(key=lambda seed: -past(*seed))
    scale = [CURVATURE_SCALE, CURVATURE_SCALE] + ([HEIGHT_SCALE] if design.height else [])
    goal = list(target) + ([float(loop.target[2])] if design.height else [])
    for ps, rs in seeds:
        if len(attempts) >= max_paths:
            break
        design.eq.reseed(rs["x"], ps)
        try:
            cont = solve_design(
                design.eq,
                goal,
                ps,
                lo,
                hi,
                scale=scale,
                absolute=REACHED / CURVATURE_SCALE,
                max_evaluations=30,
            )
        except ConvergenceError:
            continue
        if np.linalg.norm(cont.residual[:2]) > tolerance:
            continue
        rc = attempt([cont.p])
        if rc is not None and rc["distance"] <= tolerance:
            return done("constant", [cont.p], rc)
        rp = attempt([ps, cont.p])
        if rp is not None and rp["distance"] <= tolerance:
            return done("program", [ps, cont.p], rp)
    best = min(
        (a for a in attempts if "distance" in a and len(a["stages"]) == 1),
        key=lambda a: a["distance"],
    )
    return Reach(
        "none",
        best["stages"],
        best["achieved"],
        best["distance"],
        attempts,
        time.process_time() - t0,
    )


#: A program's schedule (``lcefem run gridshell --schedule``): each drive held until the strips'
#: lumped heat balance has settled. Measured with the FE-calibrated set's grid strip ('strip'
#: thermal model, its exchange factor): from ambient at the current holding lambda = 1.05, the strip
#: is at 1.0514 after 600 s and 1.05003 after 1000 s (time constant ~130 s); an overshoot need only
#: put the surface on the target's branch (600 s), the last drive holds until 1e-4 of its lambda
#: (1200 s).
PROGRAM_HOLDS = (600.0, 1200.0)  # s: every drive but the last, the last
#: Output interval [s] of the program's replay: one quasi-static solve of the surface per interval
#: (each followed by path following from the previous equilibrium).
PROGRAM_OUTPUT_INTERVAL = 50.0
#: Implicit-Euler step [s] of the replay's heat balance (a tenth of the ~5 s it takes the hottest
#: strip to move 0.01 in lambda).
PROGRAM_HEAT_STEP = 0.5


def program_schedule(design: GridshellDesign, stages, labels=None):
    """The :class:`~lcefem.solvers.problems.gridshell_bh_sequence.Schedule` that drives the design
    variables (channels, or strip ids: per-strip designs) through ``stages`` (design variables per
    drive) by the currents that hold
    each drive's lambdas (:func:`currents_for`, the 'strip' thermal model of the design's model
    set), each held :data:`PROGRAM_HOLDS`."""
    from lcefem.solvers.problems.gridshell_bh_sequence import Schedule

    currents = [currents_for(design, p)["strip"] for p in stages]
    times, t = [], 0.0
    for k in range(len(stages)):
        times.append(t)
        t += PROGRAM_HOLDS[0] if k < len(stages) - 1 else PROGRAM_HOLDS[1]
    labels = labels or [f"drive {k + 1}" for k in range(len(stages) - 1)] + ["design"]
    return Schedule(
        tuple(times),
        {name: tuple(c[name] for c in currents) for name in design.names},
        t,
        PROGRAM_OUTPUT_INTERVAL,
        design.support,
        "strip",
        tuple(labels),
        PROGRAM_HEAT_STEP,
        design.model_set,
        design.layout,
    )


def schedule_toml(schedule, comment: str = "") -> str:
    """The schedule file ``lcefem run gridshell --schedule`` reads (gridshell_bh_sequence)."""
    lines = [f"# {line}" for line in comment.splitlines()] + [
        "",
        "[schedule]",
        f"times = [{', '.join(f'{t:g}' for t in schedule.times)}]",
        "labels = [" + ", ".join(f'"{s}"' for s in schedule.labels) + "]",
        f"end = {schedule.end:g}",
        f"output_interval = {schedule.output_interval:g}",
        f'support = "{schedule.support}"',
        f'thermal_model = "{schedule.thermal_model}"',
        f"heat_step = {schedule.heat_step:g}",
    ]
    if schedule.model_set:  # replayed with the model set it was made with
        lines.append(f'model_set = "{schedule.model_set}"')
    lines += ["", "[currents]  # A, one per switch time"]
    lines += [
        f"{sel} = [{', '.join(f'{v:.9g}' for v in vals)}]"
        for sel, vals in schedule.currents.items()
    ]
    if schedule.layout is not None and schedule.layout != Layout.published():
        lines += [""] + layout_toml(schedule.layout)
    return "\n".join(lines) + "\n"


def layout_toml(layout: Layout) -> list[str]:
    """The ``[layout]`` table (lines) of the fields that differ from the published layout, read back
    by :func:`lcefem.meshes.gridshell_layout.layout_from_table` (strings as JSON strings, which are
    TOML basic strings)."""
    import json

    def value(v):
        if isinstance(v, str):
            return json.dumps(v)
        if isinstance(v, (tuple, list)):
            return "[" + ", ".join(value(u) for u in v) + "]"
        return repr(v)

    published = Layout.published()
    lines, wiring = ["[layout]"], None
    for f in dataclasses.fields(Layout):
        v = getattr(layout, f.name)
        if v == getattr(published, f.name):
            continue
        if f.name == "wiring" and not isinstance(v, str):
            wiring = v
            continue
        lines.append(f"{f.name} = {value(v)}")
    if wiring is not None:
        lines += ["", "[layout.wiring]"] + [
            f"{json.dumps(tag)} = {value(sel)}" for tag, sel in wiring
        ]
    return lines


def replay(design: GridshellDesign, schedule) -> dict:
    """Final circle curvatures [1/mm] of the schedule replayed as ``lcefem run gridshell
    --schedule`` does (:func:`~lcefem.solvers.problems.gridshell_bh_sequence.run_sequence` on a
    fresh surface of the schedule's model set and layout,
    :func:`lcefem.validation.studies.gridshell.gridshell_sequence.surface_model`: the design's,
    written into the schedule by :func:`program_schedule`; its grid strip's exchange factor), and
    the CPU seconds."""
    from lcefem.solvers.problems.gridshell_bh_sequence import run_sequence
    from lcefem.validation.studies.gridshell.gridshell_sequence import surface_model

    t0 = time.process_time()
    ms, structure, materials = surface_model(schedule)
    s = run_sequence(
        schedule,
        None,
        progress=False,
        structure=structure,
        frames=False,
        materials=materials,
        exchange_factor=ms.exchange_factor,
    )
    f = s["final"]
    return {
        "circle_x": f["circle kappa_x [1/mm]"],
        "circle_y": f["circle kappa_y [1/mm]"],
        "seconds": time.process_time() - t0,
    }


def lambdas_by_name(design: GridshellDesign, p) -> dict:
    """{design variable: lambda [-]}, lambdas within :data:`LAMBDA_SNAP` of lambda_N printed as
    it."""
    return {str(k): float(v) for k, v in zip(design.names, snapped(p, design.lambda_N))}


def currents_for(design: GridshellDesign, p) -> dict[str, dict[str, float]]:
    """{route: {name: current [A]}} for every thermal model of the current route ('strip' with the
    grid exchange factor calibrated with the design's model set,
    :meth:`calibrate.ModelSet.current_route`)."""
    out = {}
    ms = calibrate.model_set(design.model_set)
    for model in lumped_heat.THERMAL_MODELS:
        route = ms.current_route(lumped_heat.CurrentRouteConfig(thermal_model=model))
        out[model] = {
            str(k): current_for_lambda(float(v), route, design.lambda_N)
            for k, v in zip(design.names, p)
        }
    return out


def design_summary(design: GridshellDesign, result: DesignResult) -> dict:
    """A JSON-able record of one inverse solve: the design (the lambdas the run from flat follows to
    the target, or the program's last drive), its currents, the design loop's own lambdas and
    curvatures, and how the run's path from flat reaches the target."""
    st, check = result.state, result.check
    found: Reach | None = (check or {}).get("reach")
    p = found.p if found is not None else result.p
    out = {
        "target": {
            "kappa_x [1/mm]": float(result.target[0]),
            "kappa_y [1/mm]": float(result.target[1]),
        },
        "support": design.support,
        "lambdas [-]": lambdas_by_name(design, p),
        "currents [A]": currents_for(design, p),
        "lambdas (design loop) [-]": lambdas_by_name(design, result.p),
        "achieved (design loop) [1/mm]": {
            "kappa_x": float(st.observables[0]),
            "kappa_y": float(st.observables[1]),
        },
        "residual [1/mm]": [float(r) for r in result.residual[:2]],
        "residual norm [1/mm]": float(np.linalg.norm(result.residual[:2])),
        "optimizer": {
            "evaluations": result.iterations,
            "message": result.message,
            "optimality": result.optimality,
        },
        "forward solves": result.stats.solves,
        "newton iterations": result.stats.newton_iterations,
        "restarts from as built": result.stats.restarts,
        "design points without an equilibrium": result.stats.failures,
        "time [s]": result.seconds,
    }
    if design.height:
        out["target"]["centre height [mm]"] = float(result.target[2])
        out["achieved (design loop) [1/mm]"]["centre height [mm]"] = float(st.observables[2])
    if found is not None:
        out["reach"] = reach_summary(design, found)
        out["achieved (forward run from as built) [1/mm]"] = {
            "kappa_x": found.achieved[0],
            "kappa_y": found.achieved[1],
        }
        out["distance from the target along the run's path [1/mm]"] = found.distance
        out["design tolerance [1/mm]"] = DESIGN_TOLERANCE
    return out


def reach_summary(design: GridshellDesign, found: Reach) -> dict:
    """JSON-able :class:`Reach`: kind, the drives per stage (lambdas by name), achieved, paths."""
    return {
        "kind": found.kind,
        "stages": [lambdas_by_name(design, s) for s in found.stages],
        "achieved [1/mm]": list(found.achieved),
        "distance [1/mm]": found.distance,
        "paths tried": [
            {
                "stages": [lambdas_by_name(design, s) for s in a["stages"]],
                **(
                    {"achieved [1/mm]": list(a["achieved"]), "distance [1/mm]": a["distance"]}
                    if "achieved" in a
                    else {"failed": a["failed"]}
                ),
            }
            for a in found.attempts
        ],
        "CPU time [s]": found.seconds,
    }


def reachable_set(design: GridshellDesign, levels: int = 4) -> np.ndarray:
    """Centre curvatures (circle kappa_x, kappa_y) [1/mm] over a grid of ``levels`` values per
    design variable in [1.05, lambda_N] (four channels: levels^4 equilibria), visited in a
    boustrophedon order so that each warm-started solve starts from a neighbour. Rows: the
    variables' lambdas, then kappa_x, kappa_y; points where neither the warm start nor a ramp from
    as built reaches the design tolerance are left out (seen once at |g| ~ 1e-8 N)."""
    if design.eq.params.size > 4:
        raise InputError(
            "reachable_set: use the four channels (a grid over 42 strips is too large)"
        )
    values = np.linspace(LAMBDA_MIN, design.lambda_N, levels)
    n = design.eq.params.size
    rows = []

    def visit(prefix, depth, flip):
        order = values[::-1] if flip else values
        for k, v in enumerate(order):
            p = prefix + [v]
            if depth + 1 == n:
                try:
                    st = design.eq.state(np.array(p), jacobian=False)
                except ConvergenceError:  # no equilibrium at the design tolerance: left out
                    continue
                rows.append([*p, *st.observables[:2]])
            else:
                visit(p, depth + 1, (k % 2 == 1) ^ flip)

    visit([], 0, False)
    return np.asarray(rows)
