"""The robotic surface of seed 001 (Fig. 4, 5) in the bar-and-hinge model: the gridshell problem in
the per-body shape (as :mod:`lcefem.solvers.problems.gridshell`, the FE gridshell).

:class:`GridshellBH` is built from a :class:`GridshellBHConfig` (material laws, support, solver and
path settings) and the mesh (:func:`lcefem.meshes.gridshell.build_gridshell_bar_hinge`); it is
driven per strip id, channel (Tx, Ty, Bx, By), group (XD1..YU3) or half plane through
:meth:`GridshellBH.set_drives`, advanced along the load factor t in [0, 1] (rest fractions ramped
linearly from the current ones to the targets: the paper's quasi-static route) by
:meth:`GridshellBH.advance`, and read through :meth:`GridshellBH.observables` (named, with units).

* Actuation: a target rest fraction f = lambda/lambda_N per strip bar (lambda relative to the
  isotropic length).
* Supports (:data:`SUPPORTS`):
  - "clamp": the published support of saddle, cone, twisted, wave and dustpan (Examples2D.m), the
    four corner nodes of the centre junction held in x, y, z (12 DOFs);
  - "rollers": the published support of dome, cylinder and table (Examples2D.m): the nodes at
    (30, 0), (30, 141), (111, 0), (111, 141), (141, 30), (141, 111), (0, 30), (0, 111), the outer
    edge node at each end of the four OUTER ribbons, held in z, plus (30, 0) in x and y, (30, 141)
    in x and (111, 0) in y (12 DOFs; shared/reference/gridshell_recipes.md);
  - "middle_rollers" (our former reading of "8 roller supports at the ribbon ends on the
    perimeter", kept as an option): both edge nodes at both ends of the middle x and y ribbons
    (8 nodes, z held), plus the three in-plane rigid-body motions removed at the centre junction
    (corner 0 in x and y, corner 1 in y), which carry no reaction in equilibrium;
  - "table": the experiment (seed 001, "lightweight (33 g) and not anchored to the table"): the
    surface's own weight (33 g lumped on the nodes), frictionless unilateral contact of the bottom
    strips' ends with a rigid table plane, and only the in-plane rigid-body motions removed as
    above (the vertical position and the tilts are set by the contacts).
* Observables: the centre curvatures by both of the paper's measures
  (:func:`lcefem.solvers.analysis.curvature.gridshell_curvatures`; dome negative), the z range, the
  centre junction's height.

The lower-level functions (:func:`setup_gridshell`, :func:`setup_from_model`,
:func:`solve_gridshell`, ...) are used by the study
(:mod:`lcefem.validation.studies.gridshell.gridshell_bh`: the paper's curvatures), which re-exports
them. One run of ``lcefem run gridshell`` (``GridshellBHRunConfig``, ``run_gridshell``)
is in :mod:`lcefem.solvers.problems.gridshell_bh_run`; the paper's Fig. 4 programs and the published
recipes are validation data (:mod:`lcefem.validation.cases.programs`); the current route (currents
-> lambdas) is
:class:`lcefem.models.lumped_heat.CurrentRouteConfig`.

Units: mm, N, t, s.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, replace

import numpy as np

from lcefem.meshes.bar_hinge_structure import BarHingeStructure, panel_dimensions
from lcefem.meshes.composite_beam import BeamBarHingeMesh, CompositeBeamGeometry
from lcefem.meshes.gridshell import (
    CHANNELS,
    FAMILIES,
    STRIP_GROUPS,
    GridshellLayout,
    build_gridshell_bar_hinge,
    resolve_bar_values,
)
from lcefem.models import bar_hinge_materials as law
from lcefem.models import units
from lcefem.models.bar_hinge_materials import PUBLISHED_LAMBDA_N
from lcefem.models.errors import InputError
from lcefem.models.loads import SurfaceWeight
from lcefem.solvers.analysis.curvature import (
    centre_junction_point,
    gridshell_curvatures,
    junction_centre_points,
)
from lcefem.solvers.bar_hinge import (
    BarHingeModel,
    NewtonOptions,
    PathOptions,
    PathResult,
    PathState,
    follow_path,
    held_dofs,
)
from lcefem.solvers.bar_hinge.strip_beams import bar_hinge_model
from lcefem.solvers.problems.protocol import LOAD, StepRecord, check_quasi_static_step, path_record
from lcefem.solvers.problems.stable_ramp import StabilityOptions, follow_stable_path

#: Default stepping of the actuation ramp: path-following increments (grow after easy increments).
GRIDSHELL_PATH = PathOptions(
    initial_increment=0.1, max_increment=0.5, easy_iterations=8, growth=2.0
)
#: Newton settings: |g| <= 1e-6 N (1e-5 of the ~0.1 N strip forces; displacement error ~1e-4 mm on
#: the softest ~0.01 N/mm mode, 1e-7 1/mm in curvature). The beam's 1e-8 N is not reachable here:
#: with ~1300 strip-ribbon contacts some sit at their kink (penalty switching on) and the residual
#: stalls between 1e-8 and 1e-7 N.
#: Progress budget and energy slack (NewtonOptions.progress_iterations, energy_slack; measured
#: on the 5 x 5 layout's Fig. 4 dome drive, rollers, 2026-12-07, docs/layouts/index.md "Speed"):
#: from flat its Newton descends for 110 iterations to t = 0.1 with the energy falling all along
#: (the strips pull stiff Kapton bars round soft hinges; no contact switches), so 50 iterations cut
#: the increment three times for nothing; near t = 0.6 (a double tangent eigenvalue 6e-8 N/mm: not
#: a bifurcation of the dome but the rigid motion of the centre junction's raised top square, whose
#: top strips are slack, 99.999 % of the mode on its 4 nodes; benchmarks/bh_soft_modes.py) a full
#: step that raises the 30 mJ energy by 2e-8 mJ (5e-10 of it) leads to
#: |g| = 1.5e-7 N in two steps, while the 1e-13 slack refused it and Newton cycled at |g| ~ 3e-4 N
#: for 600 iterations.
GRIDSHELL_NEWTON = NewtonOptions(
    force_tolerance=1.0e-6, progress_iterations=300, energy_slack=1.0e-9
)
#: Newton settings of the ramp from as built (solve_gridshell, lcefem run gridshell): stall damping
#: after 5 iterations without halving the residual. Near the dome's fold the slack top strips'
#: raised square floats (4 tangent eigenvalues ~1e-8 N/mm) and undamped steps there are cut by the
#: trust radius, so the ribbons hardly move (Fig. 4 dome: 53 increments, 24 failed, 678 Newton
#: iterations, 22.6 s CPU -> 15, 1 and 237, 2.3 s; the same equilibrium: ribbon nodes within 1e-5
#: mm, only the 4 floating nodes move, along those modes). Not the default of the other paths: the
#: Fig. 5B ball's flat -> bowl ramp (clamp, cover scales) then buckles into the bowl's mirror image
#: across the diagonal (quadratic fit 0.026033 / 0.006015 instead of 0.006015 / 0.026033 1/mm).
RAMP_NEWTON = replace(GRIDSHELL_NEWTON, stall_iterations=5)


SUPPORTS = ("clamp", "rollers", "middle_rollers", "table")


def check_lambda_values(values: dict[str, np.ndarray], lambda_N: float, name: str) -> None:
    for g, v in values.items():
        if np.any(~np.isfinite(v)) or np.any(v < 1.0) or np.any(v > lambda_N):
            bad = v[(~np.isfinite(v)) | (v < 1.0) | (v > lambda_N)][0]
            raise InputError(
                f"{name}: lambda = {bad}: must be between 1 (isotropic) and lambda_N = "
                f"{lambda_N} (as built)"
            )


def lumped_node_weights(
    structure: BarHingeStructure, model: BarHingeModel, weight: SurfaceWeight
) -> np.ndarray:
    """Nodal forces (3n,) [N] of the surface's weight: panel (Kapton) and strip (LCE) masses lumped
    equally on their nodes, scaled so that they add up to the measured total mass."""
    mass = np.zeros(structure.num_nodes)
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


def add_table(
    structure: BarHingeStructure, geometry: CompositeBeamGeometry, lambda_N: float
) -> None:
    """A rigid table below the bottom strips: three held anchor nodes span its plane at
    z_t = -(t_p/2 + t_a/sqrt(lambda_N)) (the as-built bottom strip's underside), and every node a
    bottom strip attaches to stays at least t_p/2 + t_a/sqrt(lambda_N) above it (frictionless
    unilateral point-plane contact; the strip is a chord, so its ends are its lowest points)."""
    depth = 0.5 * geometry.ribbon_thickness + geometry.strip_thickness / math.sqrt(lambda_N)
    span = float(np.ptp(structure.nodes[:, 0])) + 100.0
    lo = float(structure.nodes[:, 0].min()) - 50.0
    a, b, c = structure.add_nodes(
        [(lo, lo, -depth), (lo, lo + span, -depth), (lo + span, lo, -depth)]
    )
    pts = structure.node_sets["bottom_strip_ends"]
    structure.add_contacts("table_contact", [(int(p), a, b, c) for p in pts], rest=depth)
    structure.node_sets["table_anchors"] = np.array([a, b, c])
    structure.sections["table_contact"] = {
        "area": 0.25 * geometry.strip_width * geometry.junction_length,
        "depth": geometry.strip_thickness,
    }


def published_roller_dofs(structure: BarHingeStructure) -> np.ndarray:
    """The published 8 rollers (module docstring): the outer edge node at each end of the outer
    ribbons held in z, and the three in-plane holds of Examples2D.m, for any number of ribbons (the
    as-built coordinates of the 3 x 3 grid: (30, 0) x y z, (30, 141) x z, (111, 0) y z, and z at
    (111, 141), (141, 30), (141, 111), (0, 30), (0, 111))."""
    n = structure.info["ribbons"]
    ex, ey = structure.node_sets["ribbon_ends_x"], structure.node_sets["ribbon_ends_y"]
    # x ribbons: side 0 at the lower y; y ribbons: side 0 at the higher x (meshes.gridshell).
    # ends[r, end, side]: ribbon r, end 0 (low) / 1 (high).
    a, b, c, d = (
        ey[0, 0, 1],
        ey[0, 1, 1],
        ey[n - 1, 0, 0],
        ey[n - 1, 1, 0],
    )  # (30,0) (30,141) (111,0) (111,141)
    xs = [
        ex[0, 1, 0],
        ex[n - 1, 1, 1],
        ex[0, 0, 0],
        ex[n - 1, 0, 1],
    ]  # (141,30) (141,111) (0,30) (0,111)
    return np.unique(
        np.concatenate(
            [
                held_dofs([a, b, c, d, *xs], "z"),
                held_dofs([a], "xy"),
                held_dofs([b], "x"),
                held_dofs([c], "y"),
            ]
        )
    )


#: Supports of a triangular grid (lcefem.meshes.gridshell_tri): the rollers sit at the ends of an
#: orthogonal grid's outer and middle ribbons and have no counterpart on three families.
TRIANGULAR_SUPPORTS = ("clamp", "table")
#: Supports of a honeycomb (lcefem.meshes.gridshell_hex): the clamp of its centre junction's
#: hexagon, statically determinate (one rigid support of the 6 rigid-body modes).
HEXAGONAL_SUPPORTS = ("clamp",)


def support_dofs(structure: BarHingeStructure, support: str) -> np.ndarray:
    """Held DOFs of a support kind (module docstring)."""
    c = structure.node_sets["centre_junction"]
    inplane = np.concatenate([held_dofs([c[0]], "xy"), held_dofs([c[1]], "y")])
    if support == "clamp":
        # a triangular grid's clamp holds its centre hexagon whole (3-fold symmetric)
        return held_dofs(structure.node_sets.get("centre_clamp", c), "xyz")
    n = structure.info["ribbons"]
    if structure.info.get("kind") == "hexagonal" and support not in HEXAGONAL_SUPPORTS:
        raise InputError(
            f"support = {support!r}: a hexagonal grid is held by "
            f"{', '.join(HEXAGONAL_SUPPORTS)} (the clamp of its centre junction)"
        )
    if structure.info.get("kind") == "triangular" and support not in TRIANGULAR_SUPPORTS:
        raise InputError(
            f"support = {support!r}: a triangular grid is held by "
            f"{', '.join(TRIANGULAR_SUPPORTS)} (the rollers are an orthogonal grid's)"
        )
    if support == "rollers":
        return published_roller_dofs(structure)
    if support == "middle_rollers":
        ends = np.concatenate(
            [
                structure.node_sets["ribbon_ends_x"][n // 2].ravel(),
                structure.node_sets["ribbon_ends_y"][n // 2].ravel(),
            ]
        )
        return np.unique(np.concatenate([held_dofs(ends, "z"), inplane]))
    if support == "table":
        return np.unique(
            np.concatenate([held_dofs(structure.node_sets["table_anchors"], "xyz"), inplane])
        )
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


def targets_from_lambdas(
    structure: BarHingeStructure,
    lambdas: dict,
    lambda_N: float = PUBLISHED_LAMBDA_N,
    name: str = "lambda",
) -> dict[str, np.ndarray]:
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
    """Nodes of the Kapton ribbons (panel corners and centres; not the raised squares or
    anchors)."""
    return np.unique(np.concatenate([structure.panels.ravel(), structure.panel_centres]))


def shape_summary(structure: BarHingeStructure, x: np.ndarray) -> dict:
    """Centre curvatures (both measures), z range of the ribbons and the junction centres'
    heights."""
    x = np.asarray(x).reshape(-1, 3)
    k = gridshell_curvatures(structure, x)
    z = x[ribbon_nodes(structure), 2]
    out = {key: (float(v) if np.ndim(v) == 0 else np.asarray(v).tolist()) for key, v in k.items()}
    out["z_min [mm]"] = float(z.min())
    out["z_max [mm]"] = float(z.max())
    out["z_range [mm]"] = float(z.max() - z.min())
    out["junction_centres [mm]"] = junction_centre_points(structure, x).reshape(-1, 3).tolist()
    return out


#: Strip-ribbon penetration [mm] above which a run says that strips pass through the ribbon: twice
#: the deepest penalty penetration measured with the contact on (0.18 mm over the eight published
#: recipes, docs/gridshell_configuration.md); without the contact the published states reach 1-3.6
#: mm.
PENETRATION_LIMIT = 0.36


def strip_ribbon_penetration(
    x: np.ndarray,
    geometry: CompositeBeamGeometry = CompositeBeamGeometry(),
    layout: GridshellLayout = GridshellLayout(),
    mesh: BeamBarHingeMesh = BeamBarHingeMesh(),
) -> float:
    """Deepest strip-ribbon interpenetration [mm] of node positions x (n, 3) of the gridshell built
    from (geometry, layout, mesh): the largest g0 - g over the strip-ribbon contact rows
    (:func:`lcefem.models.bar_hinge.point_plane_gap`, g0 the as-built gap), measured whether or not
    the run had the contact (0 if every strip point stays on its side of the ribbon)."""
    return structure_penetration(
        build_gridshell_bar_hinge(geometry, layout, replace(mesh, contact=True)), x
    )


def structure_penetration(s: BarHingeStructure, x: np.ndarray) -> float:
    """Deepest strip-ribbon interpenetration [mm] of node positions x (n, 3) over the contact rows
    of structure ``s`` (:func:`strip_ribbon_penetration`; NaN when ``s`` has none: built without
    the contact, measure it with :func:`strip_ribbon_penetration`)."""
    from lcefem.models import bar_hinge as bh

    x = np.asarray(x).reshape(-1, 3)
    if x.shape[0] != s.num_nodes:
        raise ValueError(
            f"strip-ribbon penetration: {x.shape[0]} nodes, the structure has {s.num_nodes}"
        )
    if not s.contacts:
        return math.nan
    worst = 0.0
    for name, rows in s.contacts.items():
        gap = bh.point_plane_gap(*(x[rows[:, c]] for c in range(4)), derivatives=0)
        g0 = s.contact_rest.get(name)
        if g0 is None:
            g0 = bh.point_plane_gap(*(s.nodes[rows[:, c]] for c in range(4)), derivatives=0)
        worst = max(worst, float(np.max(np.asarray(g0) - gap)))
    return worst


def solve_gridshell(
    setup: GridshellSetup,
    *,
    newton_options: NewtonOptions = RAMP_NEWTON,
    path: PathOptions = GRIDSHELL_PATH,
    on_step: Callable[[PathState], None] | None = None,
    progress: Callable[[float], None] | None = None,
) -> GridshellSolution:
    """Ramp the rest fractions from the as-built state to their targets (see module docstring)."""
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
    return GridshellSolution(
        setup, result, gridshell_curvatures(setup.structure, result.states[-1].x)
    )


def payload_forces(
    structure: BarHingeStructure, mass: float, gravity: float = units.STANDARD_GRAVITY
) -> np.ndarray:
    """Weight of a payload of ``mass`` [t] on a central pad: -m g shared by the four corners of the
    raised square over the centre junction (the top of the surface at its centre) [N], (3n,)."""
    n = structure.info["ribbons"]
    sq = structure.node_sets["top_squares"]
    q = sq[structure.info["centre_junction_index"]] if sq.ndim == 2 else sq[n // 2, n // 2]
    f = np.zeros((structure.num_nodes, 3))
    f[q, 2] = -mass * gravity / len(q)
    return f.reshape(-1)


def solve_payload(
    solution: GridshellSolution,
    mass: float,
    *,
    newton_options: NewtonOptions = GRIDSHELL_NEWTON,
    path: PathOptions = GRIDSHELL_PATH,
) -> PathResult:
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
        return follow_path(
            setup.model,
            solution.final.x,
            setup.held,
            load,
            newton_options=newton_options,
            path_options=path,
        )
    finally:
        setup.model.set_external_forces(base)


def centre_height(structure: BarHingeStructure, x: np.ndarray) -> float:
    """z [mm] of the centre junction's centre."""
    return float(centre_junction_point(structure, x)[2])


def prepare_structure(
    structure: BarHingeStructure,
    support: str,
    geometry: CompositeBeamGeometry = CompositeBeamGeometry(),
    lambda_N: float = PUBLISHED_LAMBDA_N,
) -> None:
    """Check the support kind and add what it needs to the structure (the table's plane and
    contacts) before the model is built."""
    if support not in SUPPORTS:
        raise InputError(f"support = {support!r}: allowed {', '.join(SUPPORTS)}")
    if support == "table" and "table_anchors" not in structure.node_sets:
        add_table(structure, geometry, lambda_N)


def setup_from_model(
    structure: BarHingeStructure,
    model: BarHingeModel,
    support: str,
    rest_fractions: dict[str, np.ndarray] | None = None,
    weight: SurfaceWeight = SurfaceWeight(),
) -> GridshellSetup:
    """Supports, weight (table only) and ramp targets (default: as built) on a built model."""
    forces = np.zeros(model.ndof)
    if support == "table":
        forces = lumped_node_weights(structure, model, weight)
        model.set_external_forces(forces)
    targets = rest_fractions or {g: np.ones(structure.bars[g].shape[0]) for g in STRIP_GROUPS}
    return GridshellSetup(
        structure, model, support_dofs(structure, support), targets, support, forces
    )


# --------------------------------------------------------------------------- the problem
@dataclass(frozen=True)
class GridshellBHConfig:
    """Material laws (:class:`lcefem.models.bar_hinge_materials.BarHingeMaterials`, the published
    model's values), support, solver and path settings."""

    materials: law.BarHingeMaterials = field(default_factory=law.BarHingeMaterials)
    weight: SurfaceWeight = field(default_factory=SurfaceWeight)
    geometry: CompositeBeamGeometry = field(default_factory=CompositeBeamGeometry)
    support: str = "rollers"
    solver: NewtonOptions = GRIDSHELL_NEWTON
    path: PathOptions = GRIDSHELL_PATH
    #: None: the ramp of :func:`follow_path`; set: :func:`follow_stable_path` (watches the path's
    #: lowest structural eigenvalue and leaves a lost stability by a branch switch; issue 47,
    #: layout_5x5_fold). Off by default: it costs two eigensolves per increment.
    stability: StabilityOptions | None = None


class GridshellBH:
    """The bar-and-hinge gridshell: drive strips, advance along the load factor, read observables.

    Example::

        s = build_gridshell_bar_hinge()
        g = GridshellBH(s, GridshellBHConfig(support="rollers"))
        g.set_drives({"Tx": 1.33, "Ty": 1.33, "Bx": 1.05, "By": 1.05})
        g.advance()
        g.observables()["circle kappa_x [1/mm]"]
    """

    def __init__(
        self, structure: BarHingeStructure, config: GridshellBHConfig = GridshellBHConfig()
    ):
        self.structure, self.config = structure, config
        prepare_structure(structure, config.support, config.geometry, config.materials.lce.lambda_N)
        model = bar_hinge_model(structure, config.materials)
        self.setup = setup_from_model(structure, model, config.support, None, config.weight)
        self.x = structure.nodes.copy()
        self._current = model.rest_fractions()
        self._target = {g: v.copy() for g, v in self._current.items()}
        self.history: list[PathState] = []

    @property
    def model(self) -> BarHingeModel:
        return self.setup.model

    @property
    def lambda_N(self) -> float:
        return self.config.materials.lce.lambda_N

    def _set_lambda(self, drives: Mapping) -> None:
        """Target lambdas [-] by selection (strip id, channel, layer, group, half plane; applied in
        order); strips not named keep their current target."""
        lam = {g: v * self.lambda_N for g, v in self._target.items()}
        values = resolve_bar_values(self.structure, drives, 0.0, "lambda")
        named = {g: np.zeros(v.size, dtype=bool) for g, v in values.items()}
        for key in drives:
            for g, mask in _selection_masks(self.structure, key).items():
                named[g] |= mask
        for g in lam:
            lam[g] = np.where(named[g], values[g], lam[g])
        check_lambda_values(lam, self.lambda_N, "lambda")
        self._target = {g: v / self.lambda_N for g, v in lam.items()}

    def set_rest_fractions(self, fractions: Mapping[str, np.ndarray]) -> None:
        """Target rest fractions f = lambda/lambda_N [-] per bar by strip group (a recipe's P0, or
        :func:`targets_from_lambdas`), reached by :meth:`advance`; groups not named keep theirs."""
        for g, v in fractions.items():
            if g not in self._target:
                raise InputError(
                    f"rest fractions for {g!r}: no such strip group (have: "
                    f"{', '.join(self._target)})"
                )
            v = np.asarray(v, dtype=float)
            if v.shape != self._target[g].shape or np.any(v <= 0.0):
                raise InputError(
                    f"rest fractions of {g}: {self._target[g].size} values > 0 expected"
                )
            self._target[g] = v.copy()

    def lambda_of(self, group: str) -> np.ndarray:
        """Target lambda [-] of every bar of a strip group."""
        return self._target[group] * self.lambda_N

    def advance(
        self,
        dt: float = 1.0,
        *,
        on_step: Callable[[PathState], None] | None = None,
        progress: Callable[[float], None] | None = None,
    ) -> StepRecord:
        """Ramp the rest fractions from the current state to the targets (t: 0 -> 1; ``dt`` < 1
        stops at that fraction of the way) from the current positions; raises ConvergenceError when
        the increment falls below its minimum. The record's ``detail``: the :class:`PathResult`."""
        dt = check_quasi_static_step(dt)
        start = {g: v.copy() for g, v in self._current.items()}
        target = {
            g: v.copy() if dt == 1.0 else start[g] + dt * (v - start[g])
            for g, v in self._target.items()
        }
        model, held = self.model, self.setup.held

        def load(t: float) -> np.ndarray:
            model.set_rest_fractions({g: start[g] + t * (target[g] - start[g]) for g in target})
            return model.reference.reshape(-1)[held]

        self._fraction = dt
        extra = {} if self.config.stability is None else {"stability": self.config.stability}
        result = (follow_path if self.config.stability is None else follow_stable_path)(
            model,
            self.x,
            held,
            load,
            newton_options=self.config.solver,
            path_options=self.config.path,
            on_step=on_step,
            progress=progress,
            **extra,
        )
        self.x = result.states[-1].x.copy()
        self._current = target
        self.history.extend(result.states[1:])
        return path_record(dt, self.observables(), result)

    def increment_record(self, state: PathState) -> StepRecord:
        """The :class:`StepRecord` of one converged increment of :meth:`advance` (``at``: its
        fraction of the way; the one door, lcefem.solvers.runner.run, records every increment)."""
        return StepRecord(
            state.t * self._fraction,
            self._observe(state.x),
            state.iterations,
            clock=LOAD,
            detail=state,
        )

    def observables(self) -> dict[str, float]:
        """Centre curvatures by both measures [1/mm] (dome negative), z range of the ribbons and the
        centre junction's height [mm]."""
        return self._observe(self.x)

    def _observe(self, x) -> dict[str, float]:
        s = shape_summary(self.structure, x)
        out = {"circle kappa_x [1/mm]": s["circle_x"], "circle kappa_y [1/mm]": s["circle_y"]}
        if "quad_kx" in s:
            out.update(
                {
                    "quad kappa_x [1/mm]": s["quad_kx"],
                    "quad kappa_y [1/mm]": s["quad_ky"],
                    "quad kappa_1 [1/mm]": s["quad_k1"],
                    "quad kappa_2 [1/mm]": s["quad_k2"],
                }
            )
        out["z range [mm]"] = s["z_range [mm]"]
        out["centre height [mm]"] = centre_height(self.structure, x)
        return out

    # -- the Problem protocol (lcefem.solvers.problems.protocol) --------------------------------
    drive = "lambda [-]"

    def drive_tags(self) -> tuple[str, ...]:
        """Layers, channels, families and groups (strip ids and half planes also select:
        :func:`lcefem.meshes.gridshell.resolve_bar_values`)."""
        info = self.structure.info
        if "channels" in info:  # a triangular grid: its six channels are among its groups
            return ("T", "B", *sorted(info["groups"]))
        return ("T", "B", *CHANNELS, *FAMILIES, *sorted(info["groups"]))

    def set_drives(self, drives: Mapping[str, float]) -> None:
        self._set_lambda(drives)

    def fields(self) -> dict:
        return {"node positions [mm]": self.x}

    def save_state(self) -> dict:
        return {
            "x": self.x.copy(),
            "current": {g: v.copy() for g, v in self._current.items()},
            "target": {g: v.copy() for g, v in self._target.items()},
            "steps": len(self.history),
        }

    def restore_state(self, state: dict) -> None:
        self.x = state["x"].copy()
        self._current = {g: v.copy() for g, v in state["current"].items()}
        self._target = {g: v.copy() for g, v in state["target"].items()}
        del self.history[state["steps"] :]
        self.model.set_rest_fractions(self._current)


def _selection_masks(structure: BarHingeStructure, key) -> dict[str, np.ndarray]:
    """Bars (by strip group) a selection names: those that get a value from ``{key: 1}`` with
    default 0."""
    values = resolve_bar_values(structure, {key: 1.0}, 0.0, "lambda")
    return {g: v != 0.0 for g, v in values.items()}


def setup_gridshell(
    rest_fractions: dict[str, np.ndarray] | None = None,
    support: str = "rollers",
    geometry: CompositeBeamGeometry = CompositeBeamGeometry(),
    layout: GridshellLayout = GridshellLayout(),
    mesh: BeamBarHingeMesh = BeamBarHingeMesh(),
    materials: law.BarHingeMaterials = law.BarHingeMaterials(),
    weight: SurfaceWeight = SurfaceWeight(),
    structure: BarHingeStructure | None = None,
) -> GridshellSetup:
    """Structure, model, supports and ramp. ``rest_fractions`` per bar by group (default: as built);
    build them with :func:`targets_from_lambdas` / :func:`targets_from_recipe` on ``structure``
    (pass the same structure here)."""
    if support not in SUPPORTS:
        raise InputError(f"support = {support!r}: allowed {', '.join(SUPPORTS)}")
    structure = structure or build_gridshell_bar_hinge(geometry, layout, mesh)
    prepare_structure(structure, support, geometry, materials.lce.lambda_N)
    return setup_from_model(
        structure, bar_hinge_model(structure, materials), support, rest_fractions, weight
    )
