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
  settings of ``lcefem run gridshell``, in 20 equal increments, :data:`CHECK_PATH`): "achieved"
  curvatures are from that run.

Units: mm, 1/mm, A, s.
"""

from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from lcefem.meshes.bar_hinge_structure import BarHingeStructure
from lcefem.meshes.gridshell import CHANNELS, GridshellLayout
from lcefem.models.bar_hinge_materials import PUBLISHED_LAMBDA_N, BarHingeMaterials
from lcefem.models.errors import ConvergenceError, InputError
from lcefem.solvers.analysis.curvature import gridshell_curvatures, junction_centre_points
from lcefem.solvers.bar_hinge import NewtonOptions, PathOptions
from lcefem.solvers.bar_hinge.design import (DesignResult, EquilibriumMap, solve_design,
                                             strip_parameters)
from lcefem.models import lumped_heat
from lcefem.solvers.problems import gridshell_bh as problem_bh
from lcefem.validation import calibrate
from lcefem.validation.calibrate import DEFAULT_MODEL_SET

#: Lower bound of the design lambdas [-]: the paper's most contracted Fig. 4 setting (seed 001,
#: Results: lambda = 1.05 for the contracted channels).
LAMBDA_MIN = 1.05
#: Residual scale of the curvatures [1/mm]: the paper reports them to 0.001 1/mm (seed 001).
CURVATURE_SCALE = 1.0e-3
#: Residual scale of the centre height [mm] (assumed: 0.1 mm, a caliper's reading).
HEIGHT_SCALE = 0.1
#: Forward solves inside the design loop converge to |g| <= 1e-8 N (the sensitivities are exact
#: only at an equilibrium; 1e-6 N leaves ~1e-7 1/mm of noise in the curvatures).
DESIGN_NEWTON = NewtonOptions(force_tolerance=1.0e-8)
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
    n = structure.info["ribbons"]

    def obs(x):
        k = gridshell_curvatures(structure, x)
        out = [k["circle_x"], k["circle_y"]]
        if height:
            out.append(junction_centre_points(structure, x)[n // 2, n // 2, 2])
        return np.asarray(out)
    return obs


def current_for_lambda(lam: float, route: lumped_heat.CurrentRouteConfig = lumped_heat.CurrentRouteConfig(),
                       lambda_N: float = PUBLISHED_LAMBDA_N) -> float:
    """Current [A] that holds a grid strip at ``lam`` through the route (inverse of
    :func:`~lcefem.models.lumped_heat.stretch_from_current`); 0 A for a lambda at or above the
    strip's unheated lambda."""
    def f(i):
        with np.errstate(over="ignore"):  # Eq. 1's exponential at large powers: lambda -> 1
            return lumped_heat.stretch_from_current(i, route, lambda_N) - lam
    if f(0.0) <= 1e-12:
        return 0.0
    if f(1.0) > 0:
        raise InputError(f"lambda = {lam}: below what 1 A reaches through the {route.thermal_model} "
                         "route")
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

    @property
    def names(self) -> list[str]:
        return self.eq.params.names


def setup_design(mode: str = "4", support: str = "rollers", height: bool = False,
                 lambda_N: float = PUBLISHED_LAMBDA_N, layout: GridshellLayout = GridshellLayout(),
                 newton: NewtonOptions = DESIGN_NEWTON, model_set: str = DEFAULT_MODEL_SET) -> GridshellDesign:
    """The design problem on a fresh surface (``layout``: ribbons per direction; ``model_set``: the
    bar-and-hinge elements and factors, :data:`lcefem.validation.calibrate.MODEL_SETS`)."""
    ms = calibrate.model_set(model_set)  # its mesh fields (strip element, squares, contact) and materials
    structure, materials = ms.structure(layout), ms.materials_for(layout)
    setup = problem_bh.setup_gridshell(None, support, structure=structure, materials=materials)
    params = strip_parameters(structure, channel_selections(structure, mode), lambda_N)
    eq = EquilibriumMap(setup.model, setup.held, params, curvature_observable(structure, height),
                        newton_options=newton, path_options=problem_bh.GRIDSHELL_PATH)
    return GridshellDesign(structure, support, mode, eq, lambda_N, height, materials, model_set)


#: Forward check: the design-loop equilibrium and the ramp from the as-built state agree when their
#: curvatures differ by less than this [1/mm] (a tenth of the round-trip tolerance); otherwise the
#: design continues from the ramp's equilibrium (another branch: clamped saddle).
BRANCH_TOLERANCE = 1.0e-5


def inverse(design: GridshellDesign, kx: float, ky: float, height: float | None = None,
            p0=None, max_evaluations: int = 60, check: bool = True, rounds: int = 3) -> DesignResult:
    """Lambdas whose equilibrium has centre curvatures (kx, ky) [1/mm] (and centre height [mm]).

    With ``check``, the lambdas found are run from the as-built state (:func:`forward_check`); when
    that ramp ends on another equilibrium than the warm-started design loop, the design restarts
    from the ramp's equilibrium (up to ``rounds`` times); ``result.check`` holds the last run."""
    target = [kx, ky] + ([height] if design.height else [])
    if design.height and height is None:
        raise InputError("design: a target height is needed when the height is an observable")
    scale = [CURVATURE_SCALE, CURVATURE_SCALE] + ([HEIGHT_SCALE] if design.height else [])
    n = design.eq.params.size
    p = np.full(n, 0.5 * (LAMBDA_MIN + design.lambda_N)) if p0 is None else np.asarray(p0, float)
    t0 = time.perf_counter()
    result = None
    for _ in range(rounds if check else 1):
        try:
            current = solve_design(design.eq, target, p, LAMBDA_MIN, design.lambda_N, scale=scale,
                                   absolute=REACHED / CURVATURE_SCALE, max_evaluations=max_evaluations)
        except ConvergenceError:
            if result is None:
                raise
            # The design's Newton cannot start from the ramp's equilibrium (the dome's ramp ends
            # next to a fold): keep the last design, whose check shows the ramp's branch.
            break
        result = current
        if not check:
            break
        try:
            ramp = forward_check(design, result.p)
        except ConvergenceError as exc:
            # The ramp from as built meets a fold before the lambdas found: the design loop's
            # (warm-started) equilibrium stands unconfirmed.
            result.check = {"circle_x": float("nan"), "circle_y": float("nan"), "seconds": float("nan"),
                            "failed": str(exc)}
            break
        result.check = ramp
        loop = result.state.observables[:2]
        if max(abs(ramp["circle_x"] - loop[0]), abs(ramp["circle_y"] - loop[1])) <= BRANCH_TOLERANCE:
            break
        design.eq.reseed(ramp["x"], result.p)
        p = result.p
    result.seconds = time.perf_counter() - t0
    result.stats = dataclasses.replace(design.eq.stats)
    return result


#: Path of the forward check from as built: 20 equal increments of the load factor (0.05, halved on
#: failure and regrown to 0.05), the quasi-static route. The ramp of ``lcefem run gridshell``
#: (GRIDSHELL_PATH: increments growing to 0.5) can jump to another stable equilibrium: FE-calibrated
#: set, rollers, at the table design's lambdas (1.2208, 1.2208, 1.2291, 1.2291) it takes 7
#: increments and ends at circle 0.0018082 1/mm with energy 13.584282 N mm; 20 increments (0.05)
#: and 50 (0.02) both end at 0.0016564 1/mm, 13.577075 N mm (the design loop's equilibrium), and so
#: does GRIDSHELL_PATH at the design's 1e-8 N (10 increments). Cost: 2.3 s CPU instead of 2.7 s.
CHECK_PATH = PathOptions(initial_increment=0.05, max_increment=0.05, easy_iterations=8, growth=2.0)


def forward_check(design: GridshellDesign, p) -> dict:
    """Curvatures of a forward run from the as-built state at design variables p (the quasi-static
    ramp :data:`CHECK_PATH` with the Newton settings of ``lcefem run gridshell``)."""
    params = design.eq.params
    setup = problem_bh.setup_gridshell(params.rest_fractions(p), design.support, structure=design.structure,
                                       materials=design.materials)
    sol = problem_bh.solve_gridshell(setup, path=CHECK_PATH)
    return {"circle_x": float(sol.curvatures["circle_x"]), "circle_y": float(sol.curvatures["circle_y"]),
            "x": sol.final.x, "seconds": sol.path.seconds}


def lambdas_by_name(design: GridshellDesign, p) -> dict:
    return {str(k): float(v) for k, v in zip(design.names, p)}


def currents_for(design: GridshellDesign, p) -> dict[str, dict[str, float]]:
    """{route: {name: current [A]}} for every thermal model of the current route ('strip' with the
    grid exchange factor calibrated with the design's model set, :meth:`calibrate.ModelSet.current_route`)."""
    out = {}
    ms = calibrate.model_set(design.model_set)
    for model in lumped_heat.THERMAL_MODELS:
        route = ms.current_route(lumped_heat.CurrentRouteConfig(thermal_model=model))
        out[model] = {str(k): current_for_lambda(float(v), route, design.lambda_N)
                      for k, v in zip(design.names, p)}
    return out


def design_summary(design: GridshellDesign, result: DesignResult) -> dict:
    """A JSON-able record of one inverse solve."""
    st, check = result.state, result.check
    out = {"target": {"kappa_x [1/mm]": float(result.target[0]),
                      "kappa_y [1/mm]": float(result.target[1])},
           "lambdas [-]": lambdas_by_name(design, result.p),
           "currents [A]": currents_for(design, result.p),
           "achieved (design loop) [1/mm]": {"kappa_x": float(st.observables[0]),
                                             "kappa_y": float(st.observables[1])},
           "residual [1/mm]": [float(r) for r in result.residual[:2]],
           "residual norm [1/mm]": float(np.linalg.norm(result.residual[:2])),
           "optimizer": {"evaluations": result.iterations, "message": result.message,
                         "optimality": result.optimality},
           "forward solves": result.stats.solves, "newton iterations": result.stats.newton_iterations,
           "restarts from as built": result.stats.restarts,
           "design points without an equilibrium": result.stats.failures, "time [s]": result.seconds}
    if design.height:
        out["target"]["centre height [mm]"] = float(result.target[2])
        out["achieved (design loop) [1/mm]"]["centre height [mm]"] = float(st.observables[2])
    if check is not None and "failed" in check:
        out["forward run from as built"] = "did not converge: " + check["failed"]
    elif check is not None:
        ramp = {"kappa_x": check["circle_x"], "kappa_y": check["circle_y"]}
        out["achieved (forward run from as built) [1/mm]"] = ramp
        out["forward check time [s]"] = check["seconds"]
        out["same equilibrium as the ramp from as built"] = bool(
            max(abs(ramp["kappa_x"] - st.observables[0]), abs(ramp["kappa_y"] - st.observables[1]))
            <= BRANCH_TOLERANCE)
    return out


def reachable_set(design: GridshellDesign, levels: int = 4) -> np.ndarray:
    """Centre curvatures (circle kappa_x, kappa_y) [1/mm] over a grid of ``levels`` values per
    design variable in [1.05, lambda_N] (four channels: levels^4 equilibria), visited in a
    boustrophedon order so that each warm-started solve starts from a neighbour. Rows: the
    variables' lambdas, then kappa_x, kappa_y; points where neither the warm start nor a ramp from
    as built reaches the design tolerance are left out (seen once at |g| ~ 1e-8 N)."""
    if design.eq.params.size > 4:
        raise InputError("reachable_set: use the four channels (a grid over 42 strips is too large)")
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
