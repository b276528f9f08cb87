"""Fig. 5C of seed 001 in the bar-and-hinge model: the covered surface free on a table lifts a pad
and carries weights on it.

* The table: the rigid plane of :func:`lcefem.solvers.problems.gridshell_bh.add_table` (the bottom
  strips' ends on it), here with every Kapton ribbon node in frictionless unilateral contact with it
  too (any part of a surface lying free on a table can touch it; smallest distance t_p/2, the
  ribbon's underside), and the surface's own 33 g lumped on its nodes.
* The pad: a plate lying on the actuated surface's highest points, the crowns of the twelve buckled
  ribbon arches between the nine junctions (the "core sandwich" of seed 001: "the buckled ribbons
  increase the effective thickness of the robotic surface"), through the cover scales. Its weight is
  a dead load shared equally by the twelve crowns (the highest centreline node of each arch as
  actuated; a rigid pad on the symmetric surface loads symmetric crowns equally; that inner and
  outer arches carry the same share is the approximation), and its height is the crowns' mean height
  plus the clearance t_p/2 + t_a/sqrt(lambda_N) + 2 t_s (the ribbon's upper half, the top strip, two
  overlapping scales). As built (flat, ribbons at z = 0) the pad lies at the clearance.

The run (:func:`weights_path`): strips ramped to their targets (the pad is lifted), then the pad's
mass raised through the given loads; the pad's height and the surface's
deformation (scale centres) at each; the mass ramp is continued to the load at which the shape gives
way (the pad comes down to half its lifted height, or the path ends at a limit point).

Units: mm, N, t, s.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from lcefem.meshes.bar_hinge_structure import BarHingeStructure
from lcefem.meshes.composite_beam import CompositeBeamGeometry
from lcefem.models import units
from lcefem.models.bar_hinge_materials import PUBLISHED_LAMBDA_N, BarHingeMaterials
from lcefem.models.cover_scales import CoverScales
from lcefem.models.errors import ConvergenceError
from lcefem.solvers.analysis.curvature import junction_centre_points
from lcefem.solvers.bar_hinge import PathOptions, follow_path
from lcefem.solvers.problems import gridshell_bh as gs
from lcefem.solvers.problems.gridshell_bh_scales import cover_setup


def add_ribbon_table_contacts(
    structure: BarHingeStructure, geometry: CompositeBeamGeometry
) -> None:
    """Every ribbon node against the table's plane (after :func:`gs.add_table`), smallest distance
    t_p/2."""
    a, b, c = structure.node_sets["table_anchors"]
    nodes = np.setdiff1d(gs.ribbon_nodes(structure), structure.node_sets["bottom_strip_ends"])
    structure.add_contacts(
        "ribbon_table_contact",
        [(int(p), a, b, c) for p in nodes],
        rest=0.5 * geometry.ribbon_thickness,
    )
    structure.sections["ribbon_table_contact"] = dict(structure.sections["table_contact"])


def pad_clearance(
    geometry: CompositeBeamGeometry, scales: CoverScales, lambda_N: float = PUBLISHED_LAMBDA_N
) -> float:
    """[mm] between a ribbon's midplane and the pad above it (module docstring)."""
    return (
        0.5 * geometry.ribbon_thickness
        + geometry.strip_thickness / math.sqrt(lambda_N)
        + 2.0 * scales.thickness
    )


def arch_crowns(structure: BarHingeStructure, x) -> np.ndarray:
    """The highest ribbon-centreline node (panel centre) of each ribbon segment between two
    neighbouring junctions, at positions x: (2 n (n - 1),) node ids."""
    x = np.asarray(x).reshape(-1, 3)
    ref = structure.nodes
    c = ref[structure.node_sets["junction_corners"]].mean(axis=2)  # (n, n, 3)
    n = c.shape[0]
    centres = structure.node_sets["panel_centres"]
    half = 0.5 * float(np.ptp(ref[structure.node_sets["junction_corners"][0, 0], 0]))
    out = []
    for i in range(n):
        for j in range(n - 1):
            for along, across, lo, hi, line in (
                (0, 1, c[j, i, 0], c[j + 1, i, 0], c[j, i, 1]),
                (1, 0, c[i, j, 1], c[i, j + 1, 1], c[i, j, 0]),
            ):
                p = ref[centres]
                sel = centres[
                    (np.abs(p[:, across] - line) < 1.0)
                    & (p[:, along] > lo + half)
                    & (p[:, along] < hi - half)
                ]
                out.append(int(sel[np.argmax(x[sel, 2])]))
    return np.array(sorted(set(out)))


@dataclass
class WeightsSetup:
    setup: gs.GridshellSetup
    clearance: float  # [mm] between a ribbon's midplane and the pad
    base_force: np.ndarray = field(repr=False)  # the surface's weight [N] (3n,)
    crowns: np.ndarray | None = None  # the nodes carrying the pad (set once actuated)

    def pad_height(self, x) -> float:
        """[mm] above the ribbons' as-built midplane: the crowns' mean height + the clearance."""
        if self.crowns is None:
            return self.clearance
        return float(np.asarray(x).reshape(-1, 3)[self.crowns, 2].mean()) + self.clearance

    def set_pad_mass(self, mass: float, gravity: float = units.STANDARD_GRAVITY) -> None:
        f = self.base_force.copy().reshape(-1, 3)
        if self.crowns is not None:
            f[self.crowns, 2] -= mass * gravity / self.crowns.size
        self.setup.model.set_external_forces(f.reshape(-1))


def weights_setup(
    targets_lambdas: dict,
    *,
    scales: CoverScales | None = CoverScales(),
    geometry: CompositeBeamGeometry = CompositeBeamGeometry(),
    materials: BarHingeMaterials = BarHingeMaterials(),
    structure: BarHingeStructure | None = None,
) -> WeightsSetup:
    """Structure with the table and the ribbon-table contacts; the (covered) model; strips' targets
    from lambdas per selection."""
    from lcefem.meshes.gridshell import build_gridshell_bar_hinge

    s = structure or build_gridshell_bar_hinge(geometry)
    lam_n = materials.lce.lambda_N
    gs.prepare_structure(s, "table", geometry, lam_n)
    add_ribbon_table_contacts(s, geometry)
    setup = gs.setup_gridshell(
        gs.targets_from_lambdas(s, targets_lambdas, lam_n),
        "table",
        geometry=geometry,
        materials=materials,
        structure=s,
    )
    if scales is not None:
        setup = cover_setup(setup, scales, materials)
    return WeightsSetup(
        setup, pad_clearance(geometry, scales or CoverScales(), lam_n), setup.weight.copy()
    )


def scale_centres(structure: BarHingeStructure, x) -> np.ndarray:
    return junction_centre_points(structure, np.asarray(x).reshape(-1, 3)).reshape(-1, 3)


def weights_path(
    ws: WeightsSetup,
    loads: list[float],
    *,
    hold_lambdas: dict | None = None,
    give_way_mass: float = 2000.0 * units.GRAM,
    newton=gs.GRIDSHELL_NEWTON,
    path: PathOptions = gs.GRIDSHELL_PATH,
    log=None,
) -> dict:
    """Pad of ``loads[0]`` [t] on the flat surface; strips ramped to their targets (then to
    ``hold_lambdas``, e.g. the 0.1 A hold, if given); the pad's mass raised through ``loads``; then
    on to ``give_way_mass``. Returns the pad heights [mm], scale-centre positions [mm] and the
    give-way record."""
    setup, model = ws.setup, ws.setup.model
    log = log or (lambda text: None)
    s = setup.structure
    held = setup.held
    x = s.nodes.copy()
    out = {"loads [t]": list(loads), "states": {}}

    def ramp_mass(m0: float, m1: float, x0, on_step=None, path=path):
        def load(t):
            ws.set_pad_mass(m0 + t * (m1 - m0))
            return model.reference.reshape(-1)[held]

        def step(state):
            log(
                f"  pad mass {(m0 + state.t * (m1 - m0)) / units.GRAM:.1f} g, pad at "
                f"{ws.pad_height(state.x):.3f} "
                "mm"
            )
            if on_step is not None:
                on_step(state)

        return follow_path(
            model, x0, held, load, newton_options=newton, path_options=path, on_step=step
        )

    # 1. the strips contract (the pad lies at the clearance on the flat surface), 2. the pad rests
    # on the arches' crowns
    out["flat"] = {"pad height [mm]": ws.clearance}
    targets = setup.targets

    def ramp_strips(x0, start, end):
        def load(t):
            model.set_rest_fractions({g: start[g] + t * (end[g] - start[g]) for g in end})
            return model.reference.reshape(-1)[held]

        return (
            follow_path(model, x0, held, load, newton_options=newton, path_options=path)
            .states[-1]
            .x
        )

    ones = {g: np.ones_like(v) for g, v in targets.items()}
    ws.crowns = None
    ws.set_pad_mass(0.0)
    x = ramp_strips(x, ones, targets)
    log("strips actuated")
    ws.crowns = arch_crowns(s, x)
    x = ramp_mass(0.0, loads[0], x).states[-1].x
    out["actuated"] = {"pad height [mm]": ws.pad_height(x), "x": x}
    if hold_lambdas is not None:
        hold = gs.targets_from_lambdas(s, hold_lambdas, model.lce.lambda_N)
        x = ramp_strips(x, targets, hold)
    out["states"][loads[0]] = x
    # 3. the weights
    for m0, m1 in zip(loads[:-1], loads[1:]):
        x = ramp_mass(m0, m1, x).states[-1].x
        out["states"][m1] = x
        log(f"{m1 / units.GRAM:g} g")
    # 4. on to the give-way load
    lifted = ws.pad_height(out["states"][loads[0]]) - out["flat"]["pad height [mm]"]
    floor = out["flat"]["pad height [mm]"] + 0.5 * lifted
    record = []
    m_last = loads[-1]

    def on_step(state):
        record.append((m_last + state.t * (give_way_mass - m_last), ws.pad_height(state.x)))
        log(f"give-way ramp: {record[-1][0] / units.GRAM:.0f} g, pad at {record[-1][1]:.3f} mm")

    reason = "carried the largest mass tried"
    try:
        # coarser stepping: the path is declared lost (a limit point) when an increment below 0.2 %
        # of the ramp (a few g) fails, instead of 1e-5; bounds the search's time
        ramp_mass(
            m_last,
            give_way_mass,
            x,
            on_step,
            dataclasses.replace(path, min_increment=2.0e-3, snap_increment=5.0e-3),
        )
    except ConvergenceError as exc:
        reason = f"limit point (path ended: {str(exc)[:120]})"
    give = None
    for m, h in record:
        if h < floor:
            give = m
            reason = "pad down to half its lifted height"
            break
    if give is None:
        give = record[-1][0] if record else m_last
    out["give way"] = {"mass [t]": give, "reason": reason, "record": record}
    ws.set_pad_mass(0.0)
    out["crowns"] = ws.crowns
    return out
