"""Bar-and-hinge simulations of the robotic surface (seed 001, Fig. 4 and 5), shared by
``lcefem run gridshell``, the validation cases, the benchmark and the tests.

* Actuation: a target rest fraction f = lambda/lambda_N per strip bar (lambda relative to the
  isotropic length, lambda_N = 1.4 as the published model), ramped linearly from the as-built f = 1
  along the load factor t in [0, 1] (the paper's quasi-static route). Targets come from lambdas per
  channel/group (:data:`SHAPES`, the paper's Fig. 4 settings), from the published recipes
  (:data:`RECIPES`, rest fractions P0 per group) or from currents per channel/group through the
  strip's thermal model (:func:`stretch_from_current`).
* Supports (:data:`SUPPORTS`):
  - "clamp": the published saddle support, the four corner nodes of the centre junction held (12
    DOFs);
  - "rollers": the published support of the other shapes, "8 roller supports at the ribbon ends on
    the perimeter": we take both edge nodes at both ends of the middle x and y ribbons (8 nodes, z
    held), plus the three in-plane rigid-body motions removed at the centre junction (corner 0 in x
    and y, corner 1 in y), which carry no reaction in equilibrium;
  - "table": the experiment (seed 001, "lightweight (33 g) and not anchored to the table"): the
    surface's own weight (33 g lumped on the nodes), frictionless unilateral contact of the bottom
    strips' ends with a rigid table plane, and only the in-plane rigid-body motions removed as
    above (the vertical position and the tilts are set by the contacts).
* Observables: the centre curvatures by both of the paper's measures
  (:func:`lcefem.solvers.analysis.curvature.gridshell_curvatures`; dome negative), the z range, the
  centre junction's height.

Units: mm, N, t, s, A.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from lcefem.meshes.bar_hinge_structure import BarHingeStructure
from lcefem.meshes.composite_beam import BeamBarHingeMesh, CompositeBeamGeometry
from lcefem.meshes.gridshell import (STRIP_GROUPS, GridshellLayout, build_gridshell_bar_hinge,
                                     resolve_bar_values)
from lcefem.models import units
from lcefem.models.bar_hinge import PUBLISHED_LAMBDA_N
from lcefem.models.empirical import Eq1, eq1_stretch
from lcefem.models.errors import InputError
from lcefem.models.heat import Coil
from lcefem.models.loads import SurfaceWeight
from lcefem.models.lumped_heat import HeatedStrip, LumpedThermal, steady_stretch
from lcefem.models.parameters import param
from lcefem.solvers.analysis.curvature import gridshell_curvatures, junction_centre_points
from lcefem.solvers.bar_hinge import (BarHingeModel, NewtonOptions, PathOptions, PathResult,
                                      PathState, follow_path, held_dofs)
from lcefem.validation.bar_hinge_studies import BarHingeMaterials
from lcefem.validation.reference_data import reference

#: Default stepping of the actuation ramp: path-following increments (grow after easy increments).
GRIDSHELL_PATH = PathOptions(initial_increment=0.1, max_increment=0.5, easy_iterations=8,
                             growth=2.0)
#: Newton settings: |g| <= 1e-6 N (1e-5 of the ~0.1 N strip forces; displacement error ~1e-4 mm on
#: the softest ~0.01 N/mm mode, 1e-7 1/mm in curvature). The beam's 1e-8 N is not reachable here:
#: with ~1300 strip-ribbon contacts some sit at their kink (penalty switching on) and the residual
#: stalls between 1e-8 and 1e-7 N.
GRIDSHELL_NEWTON = NewtonOptions(force_tolerance=1.0e-6)

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
SUPPORTS = ("clamp", "rollers", "table")
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


def check_lambda_values(values: dict[str, np.ndarray], lambda_N: float, name: str) -> None:
    for g, v in values.items():
        if np.any(~np.isfinite(v)) or np.any(v < 1.0) or np.any(v > lambda_N):
            bad = v[(~np.isfinite(v)) | (v < 1.0) | (v > lambda_N)][0]
            raise InputError(f"{name}: lambda = {bad}: must be between 1 (isotropic) and lambda_N = "
                             f"{lambda_N} (as built)")


def lumped_node_weights(structure: BarHingeStructure, model: BarHingeModel,
                        weight: SurfaceWeight) -> np.ndarray:
    """Nodal forces (3n,) [N] of the surface's weight: panel (Kapton) and strip (LCE) masses lumped
    equally on their nodes, scaled so that they add up to the measured total mass."""
    mass = np.zeros(structure.num_nodes)
    from lcefem.meshes.bar_hinge_structure import panel_dimensions
    w, h = panel_dimensions(structure)
    m_panel = weight.kapton_density * w * h * structure.thickness
    for k in range(4):
        np.add.at(mass, structure.panels[:, k], m_panel / 5.0)
    np.add.at(mass, structure.panel_centres, m_panel / 5.0)
    for b in model.strip_sets():
        np.add.at(mass, b.nodes[:, 0], 0.5 * weight.lce_density * b.volume)
        np.add.at(mass, b.nodes[:, 1], 0.5 * weight.lce_density * b.volume)
    mass *= weight.total_mass / mass.sum()
    forces = np.zeros((structure.num_nodes, 3))
    forces[:, 2] = -mass * weight.gravity
    return forces.reshape(-1)


def add_table(structure: BarHingeStructure, geometry: CompositeBeamGeometry, lambda_N: float) -> None:
    """A rigid table below the bottom strips: three held anchor nodes span its plane at
    z_t = -(t_p/2 + t_a/sqrt(lambda_N)) (the as-built bottom strip's underside), and every node a
    bottom strip attaches to stays at least t_p/2 + t_a/sqrt(lambda_N) above it (frictionless
    unilateral point-plane contact; the strip is a chord, so its ends are its lowest points)."""
    depth = 0.5 * geometry.ribbon_thickness + geometry.strip_thickness / math.sqrt(lambda_N)
    span = float(np.ptp(structure.nodes[:, 0])) + 100.0
    lo = float(structure.nodes[:, 0].min()) - 50.0
    a, b, c = structure.add_nodes([(lo, lo, -depth), (lo, lo + span, -depth), (lo + span, lo, -depth)])
    pts = structure.node_sets["bottom_strip_ends"]
    structure.add_contacts("table_contact", [(int(p), a, b, c) for p in pts], rest=depth)
    structure.node_sets["table_anchors"] = np.array([a, b, c])
    structure.sections["table_contact"] = {"area": 0.25 * geometry.strip_width * geometry.junction_length,
                                           "depth": geometry.strip_thickness}


def support_dofs(structure: BarHingeStructure, support: str) -> np.ndarray:
    """Held DOFs of a support kind (module docstring)."""
    c = structure.node_sets["centre_junction"]
    inplane = np.concatenate([held_dofs([c[0]], "xy"), held_dofs([c[1]], "y")])
    if support == "clamp":
        return held_dofs(c, "xyz")
    n = structure.info["ribbons"]
    if support == "rollers":
        ends = np.concatenate([structure.node_sets["ribbon_ends_x"][n // 2].ravel(),
                               structure.node_sets["ribbon_ends_y"][n // 2].ravel()])
        return np.unique(np.concatenate([held_dofs(ends, "z"), inplane]))
    if support == "table":
        return np.unique(np.concatenate([held_dofs(structure.node_sets["table_anchors"], "xyz"),
                                         inplane]))
    raise InputError(f"support = {support!r}: allowed {', '.join(SUPPORTS)}")


@dataclass
class GridshellSetup:
    structure: BarHingeStructure
    model: BarHingeModel
    held: np.ndarray
    targets: dict[str, np.ndarray]  # rest fractions per bar at t = 1
    support: str
    weight: np.ndarray  # nodal weight forces (3n,) [N] (zero unless "table")

    def load(self, t: float) -> np.ndarray:
        """Set the rest fractions f(t) = 1 + t (f_target - 1); return the held DOFs' positions."""
        self.model.set_rest_fractions({g: 1.0 + t * (v - 1.0) for g, v in self.targets.items()})
        return self.model.reference.reshape(-1)[self.held]


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
    if support == "table" and "table_anchors" not in structure.node_sets:
        add_table(structure, geometry, materials.lce.lambda_N)
    model = materials.model(structure)
    forces = np.zeros(model.ndof)
    if support == "table":
        forces = lumped_node_weights(structure, model, weight)
        model.set_external_forces(forces)
    targets = rest_fractions or {g: np.ones(structure.bars[g].shape[0]) for g in STRIP_GROUPS}
    return GridshellSetup(structure, model, support_dofs(structure, support), targets, support, forces)


def targets_from_lambdas(structure: BarHingeStructure, lambdas: dict, lambda_N: float = PUBLISHED_LAMBDA_N,
                         name: str = "lambda") -> dict[str, np.ndarray]:
    """Rest fractions f = lambda/lambda_N per bar from lambdas per selection (default lambda_N)."""
    values = resolve_bar_values(structure, lambdas, lambda_N, name)
    check_lambda_values(values, lambda_N, name)
    return {g: v / lambda_N for g, v in values.items()}


def targets_from_recipe(structure: BarHingeStructure, recipe: dict) -> dict[str, np.ndarray]:
    """Rest fractions per bar from a published recipe (P0 per selection, default 1)."""
    values = resolve_bar_values(structure, recipe, 1.0, "recipe")
    for g, v in values.items():
        if np.any(v <= 0.0) or np.any(v > 1.0):
            raise InputError(f"recipe: rest fraction {v[(v <= 0) | (v > 1)][0]}: must be in (0, 1]")
    return values


@dataclass
class GridshellSolution:
    setup: GridshellSetup
    path: PathResult
    curvatures: dict

    @property
    def final(self) -> PathState:
        return self.path.states[-1]

    @property
    def structure(self) -> BarHingeStructure:
        return self.setup.structure


def ribbon_nodes(structure: BarHingeStructure) -> np.ndarray:
    """Nodes of the Kapton ribbons (panel corners and centres; not the raised squares or anchors)."""
    return np.unique(np.concatenate([structure.panels.ravel(), structure.panel_centres]))


def shape_summary(structure: BarHingeStructure, x: np.ndarray) -> dict:
    """Centre curvatures (both measures), z range of the ribbons and the junction centres' heights."""
    x = np.asarray(x).reshape(-1, 3)
    k = gridshell_curvatures(structure, x)
    z = x[ribbon_nodes(structure), 2]
    out = {key: (float(v) if np.ndim(v) == 0 else np.asarray(v).tolist()) for key, v in k.items()}
    out["z_min [mm]"] = float(z.min())
    out["z_max [mm]"] = float(z.max())
    out["z_range [mm]"] = float(z.max() - z.min())
    out["junction_centres [mm]"] = junction_centre_points(structure, x).reshape(-1, 3).tolist()
    return out


def solve_gridshell(setup: GridshellSetup, *, newton_options: NewtonOptions = GRIDSHELL_NEWTON,
                    path: PathOptions = GRIDSHELL_PATH,
                    on_step: Callable[[PathState], None] | None = None,
                    progress: Callable[[float], None] | None = None) -> GridshellSolution:
    """Ramp the rest fractions from the as-built state to their targets (see module docstring)."""
    result = follow_path(setup.model, setup.structure.nodes, setup.held, setup.load,
                         newton_options=newton_options, path_options=path, on_step=on_step,
                         progress=progress)
    return GridshellSolution(setup, result, gridshell_curvatures(setup.structure, result.states[-1].x))


def payload_forces(structure: BarHingeStructure, mass: float, gravity: float = units.STANDARD_GRAVITY
                   ) -> np.ndarray:
    """Weight of a payload of ``mass`` [t] on a central pad: -m g shared by the four corners of the
    raised square over the centre junction (the top of the surface at its centre) [N], (3n,)."""
    n = structure.info["ribbons"]
    q = structure.node_sets["top_squares"][n // 2, n // 2]
    f = np.zeros((structure.num_nodes, 3))
    f[q, 2] = -mass * gravity / 4.0
    return f.reshape(-1)


def solve_payload(solution: GridshellSolution, mass: float, *,
                  newton_options: NewtonOptions = GRIDSHELL_NEWTON,
                  path: PathOptions = GRIDSHELL_PATH) -> PathResult:
    """Add a payload of ``mass`` [t] on the central pad of an actuated surface, ramped from 0 to its
    weight (the strips held at their targets); returns the path (states' positions)."""
    setup = solution.setup
    base = setup.weight.copy()
    extra = payload_forces(setup.structure, mass)
    setup.load(1.0)

    def load(t: float) -> np.ndarray:
        setup.model.set_external_forces(base + t * extra)
        return setup.model.reference.reshape(-1)[setup.held]

    try:
        return follow_path(setup.model, solution.final.x, setup.held, load,
                           newton_options=newton_options, path_options=path)
    finally:
        setup.model.set_external_forces(base)


def centre_height(structure: BarHingeStructure, x: np.ndarray) -> float:
    """z [mm] of the centre junction's centre."""
    n = structure.info["ribbons"]
    return float(junction_centre_points(structure, x)[n // 2, n // 2, 2])
