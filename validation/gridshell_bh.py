"""Bar-and-hinge study of the robotic surface (seed 001, Fig. 4 and 5), shared by
``lcefem run gridshell``, the validation cases, the benchmark and the tests: the paper's Fig. 4
settings (:data:`SHAPES`), the published recipes (:data:`RECIPES`), the current route (currents per
channel/group -> lambdas through the strip's thermal model, :func:`stretch_from_current`) and
:func:`setup_gridshell` (structure + the materials of
:class:`~lcefem.models.bar_hinge.BarHingeMaterials` + supports).

The problem itself (supports "clamp", "rollers", "table"; the linear ramp of the rest fractions
f = lambda/lambda_N along the load factor; observables) is
:mod:`lcefem.solvers.problems.gridshell_bh`, whose functions are re-exported here.

Units: mm, N, t, s, A.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from lcefem.meshes.bar_hinge_structure import BarHingeStructure
from lcefem.meshes.composite_beam import BeamBarHingeMesh, CompositeBeamGeometry
from lcefem.meshes.gridshell import GridshellLayout, build_gridshell_bar_hinge
from lcefem.models.bar_hinge import PUBLISHED_LAMBDA_N, BarHingeMaterials
from lcefem.models.empirical import Eq1, eq1_stretch
from lcefem.models.errors import InputError
from lcefem.models.heat import Coil
from lcefem.models.loads import SurfaceWeight
from lcefem.models.lumped_heat import HeatedStrip, LumpedThermal, steady_stretch
from lcefem.models.parameters import param
from lcefem.solvers.bar_hinge import BarHingeModel
# The problem (supports, ramp, observables) lives in solvers/problems/gridshell_bh.py; its functions
# are re-exported here for the studies, cases and benchmarks that import them from this module.
from lcefem.solvers.problems.gridshell_bh import (  # noqa: F401
    GRIDSHELL_NEWTON, GRIDSHELL_PATH, SUPPORTS, GridshellBH, GridshellBHConfig, GridshellSetup,
    GridshellSolution, add_table, centre_height, check_lambda_values, lumped_node_weights,
    payload_forces, prepare_structure, ribbon_nodes, setup_from_model, shape_summary, solve_gridshell,
    solve_payload, support_dofs, targets_from_lambdas, targets_from_recipe)
from lcefem.validation.reference_data import reference

SEED = "seed 001"


def _paper_curvatures(shape: str, kind: str) -> tuple[float, float]:
    """(kappa_x, kappa_y) [1/mm] the paper reports at the centre joint, ``kind`` "sim" or "exp"
    (validation/data/seed001.toml, each with its quote)."""
    ref = reference(f"surface.{shape}.curvature_{kind}")
    return (ref["kx"], ref["ky"])


#: The paper's Fig. 4 settings (lambda per channel) and the curvatures it reports at the centre
#: joint [1/mm] (simulation, experiment), sign: dome negative (seed 001, Results and Methods). The
#: table is the flat shape (0, 0) of the paper's classification; no measured value is given.
SHAPES = {
    "table": {"lambdas": {"Tx": 1.05, "Ty": 1.05, "Bx": 1.05, "By": 1.05},
              "currents": {"Tx": 0.2, "Ty": 0.2, "Bx": 0.2, "By": 0.2},
              "support": "rollers", "paper_sim": (0.0, 0.0), "paper_exp": (None, None)},
    "dome": {"lambdas": {"Tx": 1.33, "Ty": 1.33, "Bx": 1.05, "By": 1.05},
             "currents": {"Tx": 0.04, "Ty": 0.04, "Bx": 0.07, "By": 0.07},
             "support": "rollers", "paper_sim": _paper_curvatures("dome", "sim"),
             "paper_exp": _paper_curvatures("dome", "exp")},
    "saddle": {"lambdas": {"Tx": 1.33, "Ty": 1.05, "Bx": 1.05, "By": 1.33},
               "currents": {"Tx": 0.04, "Ty": 0.07, "Bx": 0.07, "By": 0.04},
               "support": "clamp", "paper_sim": _paper_curvatures("saddle", "sim"),
               "paper_exp": _paper_curvatures("saddle", "exp")},
    "cylinder": {"lambdas": {"Tx": 1.05, "Ty": 1.33, "Bx": 1.33, "By": 1.33},
                 "currents": {"Tx": 0.07, "Ty": 0.04, "Bx": 0.04, "By": 0.04},
                 "support": "rollers", "paper_sim": _paper_curvatures("cylinder", "sim"),
                 "paper_exp": _paper_curvatures("cylinder", "exp")},
}
SHAPE_SOURCES = {
    "lambdas": "seed 001, Results (Fig. 4 B-E): dome lambda_T = 1.33, lambda_B = 1.05; saddle Tx = By = "
               "1.33, Ty = Bx = 1.05; cylinder Ty = Bx = By = 1.33, Tx = 1.05; table all 1.05",
    "currents": "dome: seed 001, Results: 'I_Bx = I_By = 0.07 A and I_Tx = I_Ty = 0.04 A, according to "
                "Fig. 2C' (after ~20 s at 0.1 A top / 0.2 A bottom); saddle and cylinder: the same "
                "Fig. 2C pair (0.07 A for lambda = 1.05, 0.04 A for 1.33) channel by channel, as the "
                "text says 'the other geometries are programmed similarly'; table: 0.2 A on all "
                "strips (Fig. 5C: 'we applied 0.2 A to all LCE strips', then 0.1 A), i.e. fully "
                "contracted (lambda = 1, Eq. 1)",
    "curvatures": "seed 001, Results (dome) and Materials and Methods (saddle, cylinder): principal "
                  "curvatures at the centre joint, simulation / experiment; table: flat (0, 0) by "
                  "symmetry, no number published",
}

#: The published model's recipes: target rest fraction P0 per group (lambda = 1.4 P0), and support
#: (shared/reference/gridshell_recipes.md).
RECIPES = {
    "saddle": ({"XD": 0.75, "YD": 0.95, "XU": 0.95, "YU": 0.75}, "clamp"),
    "dome": ({"XD": 0.75, "YD": 0.75, "XU": 0.95, "YU": 0.95}, "rollers"),
    "cylinder": ({"XD": 0.95, "YD": 0.95, "XU": 0.95, "YU": 0.75}, "rollers"),
    "table": ({"XD": 0.75, "YD": 0.75, "XU": 0.72, "YU": 0.72}, "rollers"),
    "cone": ({"XD1": 0.75, "XD2": 0.85, "XD3": 0.95, "YD": 0.90, "XU": 0.95, "YU": 0.90}, "rollers"),
    "twisted": ({"XD1": 0.85, "XD2": 0.80, "XD3": 0.95, "YD": 0.90, "XU1": 0.95, "XU2": 0.80,
                 "XU3": 0.85, "YU": 0.90}, "rollers"),
    "wave": ({"XD:x<70.5": 0.95, "XD:x>70.5": 0.75, "YD": 0.90, "XU:x<70.5": 0.75, "XU:x>70.5": 0.95,
              "YU": 0.90}, "rollers"),
    "dustpan": ({"XD:x<70.5": 0.95, "XD:x>70.5": 0.85, "YD": 0.95, "XU:x<70.5": 0.80,
                 "XU:x>70.5": 0.95, "YU": 0.80}, "rollers"),
}
RECIPE_SOURCE = ("published reduced-order model (Daraio-lab/RoboticSurface_SciRob_LiuK), restated in "
                 "shared/reference/gridshell_recipes.md")
THERMAL_MODELS = ("segment", "eq1")


@dataclass(frozen=True)
class CurrentRoute:
    """How a channel current becomes a strip's lambda."""

    thermal_model: str = param("segment", "-", "'segment': our lumped steady heat balance of one 25 ohm, "
                               "30 mm grid segment with the calibrated exchange and transition "
                               "(models.lumped_heat); 'eq1': the paper's own estimate, Eq. 1 at the "
                               "power I^2 R of a 146.6 ohm strip coil (seed 001: 'We can estimate the "
                               "required current for each LCE strip by the imposed stretch, using Eq. 1')")
    segment: HeatedStrip = field(default_factory=HeatedStrip)

    def checked(self) -> "CurrentRoute":
        if self.thermal_model not in THERMAL_MODELS:
            raise InputError(f"current.thermal_model = {self.thermal_model!r}: allowed "
                             f"{', '.join(THERMAL_MODELS)}")
        return self


def stretch_from_current(current: float, route: CurrentRoute = CurrentRoute(),
                         lambda_N: float = PUBLISHED_LAMBDA_N) -> float:
    """Steady lambda [-] of a grid strip at ``current`` [A], capped at the as-built lambda_N (a strip
    whose free length would exceed its glued length is slack: rest fraction 1)."""
    if route.checked().thermal_model == "eq1":
        lam = float(eq1_stretch(Coil().power(current), Eq1()))
    else:
        lam = steady_stretch(current, route.segment, LumpedThermal())
    return min(lam, lambda_N)


def lambda_assignments_from_currents(currents: dict, route: CurrentRoute = CurrentRoute(),
                                     lambda_N: float = PUBLISHED_LAMBDA_N) -> dict:
    """{selection: current [A]} -> {selection: lambda [-]} through :func:`stretch_from_current`."""
    return {k: stretch_from_current(float(v), route, lambda_N) for k, v in currents.items()}


def setup_gridshell(rest_fractions: dict[str, np.ndarray] | None = None, support: str = "rollers",
                    geometry: CompositeBeamGeometry = CompositeBeamGeometry(),
                    layout: GridshellLayout = GridshellLayout(),
                    mesh: BeamBarHingeMesh = BeamBarHingeMesh(),
                    materials: BarHingeMaterials = BarHingeMaterials(),
                    weight: SurfaceWeight = SurfaceWeight(),
                    structure: BarHingeStructure | None = None) -> GridshellSetup:
    """Structure, model, supports and ramp. ``rest_fractions`` per bar by group (default: as built);
    build them with :func:`targets_from_lambdas` / :func:`targets_from_recipe` on ``structure``
    (pass the same structure here)."""
    if support not in SUPPORTS:
        raise InputError(f"support = {support!r}: allowed {', '.join(SUPPORTS)}")
    structure = structure or build_gridshell_bar_hinge(geometry, layout, mesh)
    prepare_structure(structure, support, geometry, materials.lce.lambda_N)
    return setup_from_model(structure, BarHingeModel.from_materials(structure, materials), support,
                            rest_fractions, weight)
