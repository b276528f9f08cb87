"""What refinement and more channels buy (issue 47, item 3): the RMS distance [mm] of the best
surface a gridshell layout and wiring reaches from a target surface z(x, y) [mm].

Seed 001 ends with its next steps: "To achieve higher geometric complexity, it is necessary to add
control channels (fig. S6), refine the grid mesh (fig. S7), and explore non-orthogonal meshes." This
study asks how close each (grid, wiring) comes to a set of targets:

* Targets (:data:`TARGETS`), height fields z(x, y) [mm] over the surface's footprint, x and y from
  the centroid of the observed points: the four Fig. 4 shapes as the quadrics
  z = (kappa_x x^2 + kappa_y y^2) / 2 of the paper's centre curvatures (seed 001 Fig. 4: measured
  dome, saddle, cylinder; the table's simulated value, as
  :data:`lcefem.validation.studies.gridshell.gridshell_bh.SHAPES`); a Gaussian bump, a two-wave
  surface and a twisted surface (assumed amplitudes, stated per target).
* Grids (:data:`GRIDS`): the published 3 x 3, the refined 5 x 5, the rhombic 60 deg grid and the
  triangular grid of 3 ribbons per family (7 hexagonal junctions, lcefem.meshes.gridshell_tri;
  pitch 42.12 mm, so that its segments are the published 30 mm composite beams: footprint 156 x
  139 mm against the 3 x 3's 141 x 141 mm). Not the honeycomb (lcefem.meshes.gridshell_hex): its
  3 cells round the centre junction span about 84 mm, so its RMS distances would not compare with
  the others' (a smaller patch is closer to any smooth target); a design on it (twisted target)
  costs 10.7 s CPU with 6 channels (1.583 mm) and 18.4 s per strip (0.509 mm), and
  :func:`grid_wirings` and :func:`grid_support` take its layout.
* Wirings (:data:`WIRINGS`, per grid :func:`grid_wirings`): the paper's 4 channels (Tx, Ty, Bx, By:
  one current per layer and direction; on the triangular grid their extension, 6 channels: one per
  layer and family), one per ribbon and layer (layout wiring 'ribbons': 4 n drives, 6 n on the
  triangular grid) and one per strip.
* Support (:func:`grid_support`): the published rollers (Fig. 4 dome and cylinder) on the
  two-family grids; the clamp of the centre hexagon on the triangular grid (the rollers sit at the
  ends of an orthogonal grid's ribbons and have no counterpart there). The rollers hold z at 8
  points, the clamp only the centre junction: the triangular rows are not the same support.
* Distance: the observed points are the panel centres of the Kapton ribbons; the residual per point
  is z_i - z_target(x_i, y_i) with the plane a + b x + c y of least squares removed (the rigid fit:
  a vertical translation and the two small tilts, linearised); RMS over the points [mm].
* Best surface: the design loop (:func:`lcefem.solvers.bar_hinge.design.solve_design`: warm-started
  equilibria, exact sensitivities, bounded least squares on lambda in [1.05, lambda_N]) minimising
  that residual from the mid-range lambdas. It is the best equilibrium the loop finds on the branch
  it follows, not checked from flat (``lcefem design`` does that for curvature targets).

Units: mm, 1/mm; lambdas [-].
"""

from __future__ import annotations

import dataclasses
import math
import time

import numpy as np

from lcefem.meshes.gridshell_layout import NAMED_LAYOUTS, Layout
from lcefem.models.errors import ConvergenceError, InputError
from lcefem.solvers.bar_hinge.design import EquilibriumMap, solve_design, strip_parameters
from lcefem.solvers.problems import gridshell_bh as problem_bh
from lcefem.validation.studies.design import gridshell_design as gd
from lcefem.validation.studies.gridshell import calibrate
from lcefem.validation.studies.gridshell import gridshell_bh as gs


def _quadric(shape: str):
    spec = gs.SHAPES[shape]
    kx, ky = spec["paper_exp"] if spec["paper_exp"][0] is not None else spec["paper_sim"]
    return lambda x, y: 0.5 * (kx * x * x + ky * y * y)


#: Bump height [mm] and width [mm] (assumed: a bump a third of the published surface's 141 mm side
#: wide, as high as the measured dome's rise over that width).
BUMP = (12.0, 25.0)
#: Two-wave surface: amplitude [mm] and wavelength [mm] (assumed: two waves across the published
#: 141 mm side, 4 mm amplitude).
WAVE = (4.0, 70.5)
#: Twisted surface z = tau x y: tau [1/mm] (assumed: corners of the published surface +-8 mm).
TWIST = 1.0 / 600.0

#: Targets: name -> (z(x, y) [mm], source).
TARGETS = {
    "dome": (
        _quadric("dome"),
        "seed 001 Fig. 4: the measured dome's centre curvatures as a quadric",
    ),
    "saddle": (
        _quadric("saddle"),
        "seed 001 Fig. 4: the measured saddle's centre curvatures as a quadric",
    ),
    "cylinder": (
        _quadric("cylinder"),
        "seed 001 Fig. 4: the measured cylinder's centre curvatures as a quadric",
    ),
    "table": (
        _quadric("table"),
        "seed 001 Fig. 4: the table, flat (0, 0 1/mm by symmetry; no number published)",
    ),
    "gaussian bump": (
        lambda x, y: BUMP[0] * np.exp(-(x * x + y * y) / (2.0 * BUMP[1] ** 2)),
        f"assumed: {BUMP[0]:g} mm high, sigma {BUMP[1]:g} mm",
    ),
    "two-wave": (
        lambda x, y: 0.5
        * WAVE[0]
        * (np.cos(2 * math.pi * x / WAVE[1]) + np.cos(2 * math.pi * y / WAVE[1])),
        f"assumed: amplitude {WAVE[0]:g} mm, wavelength {WAVE[1]:g} mm in x and y",
    ),
    "twisted": (lambda x, y: TWIST * x * y, f"assumed: z = x y / {1 / TWIST:g} mm"),
}
#: Side of the published surface [mm]: 4 segments of 30 mm and 3 junctions of 7 mm (seed 001; the
#: published reduced-order model).
SIDE = 141.0
#: Grids: study name -> layout. The refined grid keeps the published side (fig. S7 refines the grid
#: of the same surface): 5 ribbons, pitch p with 6 (p - 7 mm) + 5 x 7 mm = 141 mm. The rhombic grid
#: is the named 60 deg one (the published pitch).
GRIDS = {
    "3x3": NAMED_LAYOUTS["published"],
    "5x5": dataclasses.replace(NAMED_LAYOUTS["5x5"], pitch=(SIDE - 5 * 7.0) / 6 + 7.0),
    "rhombic": NAMED_LAYOUTS["rhombic60"],
    "triangular": Layout(kind="triangular", ribbons=3),
}
#: Wirings: study name -> (design mode of gridshell_design, the layout's wiring).
WIRINGS = {
    "4 channels": ("4", "channels"),
    "6 channels": ("wiring", "channels"),
    "per ribbon and layer": ("wiring", "ribbons"),
    "per strip": ("all", "channels"),
}
#: Support of every two-family design (the Fig. 4 dome's and cylinder's published rollers).
SUPPORT = "rollers"
#: Support of the triangular grid's and the honeycomb's designs (the clamp of the centre junction's
#: hexagon: module docstring).
TRIANGULAR_SUPPORT = "clamp"
#: Grid kinds with three piece directions (6 channels, the clamp).
THREE_DIRECTION_KINDS = ("triangular", "hexagonal")


def _grid_layout(grid: str | Layout) -> Layout:
    return grid if isinstance(grid, Layout) else GRIDS[grid]


def grid_wirings(grid: str | Layout) -> tuple[str, ...]:
    """The wirings that apply to ``grid``: the paper's 4 channels on a two-family grid, their
    extension to 6 (one per layer and family) on the triangular one; per ribbon and per strip on
    every grid."""
    channels = "6 channels" if _grid_layout(grid).kind in THREE_DIRECTION_KINDS else "4 channels"
    return (channels, "per ribbon and layer", "per strip")


def grid_support(grid: str | Layout) -> str:
    """The support of ``grid``'s designs (module docstring)."""
    return TRIANGULAR_SUPPORT if _grid_layout(grid).kind in THREE_DIRECTION_KINDS else SUPPORT


def rigid_residual(points: np.ndarray, target, offset=None) -> np.ndarray:
    """z - z_target(x, y) [mm] at ``points`` (m, 3) (x, y from their centroid) with the
    least-squares plane a + b x + c y removed (the linearised rigid fit). ``offset`` (m,) [mm],
    per point: the target is z_target - offset there (the space mapping's corrected target,
    :func:`lcefem.validation.studies.design.space_mapping.output_space_map`)."""
    xy = points[:, :2] - points[:, :2].mean(axis=0)
    r = points[:, 2] - target(xy[:, 0], xy[:, 1])
    if offset is not None:
        r = r + np.asarray(offset, dtype=float)
    basis = np.column_stack([np.ones(len(r)), xy])
    coef, *_ = np.linalg.lstsq(basis, r, rcond=None)
    return r - basis @ coef


@dataclasses.dataclass
class ReachResult:
    target: str
    grid: str
    wiring: str
    rms: float  # mm
    variables: int
    lambdas: np.ndarray
    evaluations: int
    cpu: float  # s
    x: np.ndarray | None = None  # (n, 3) [mm]


def _design_problem(target: str, grid: str, wiring: str, model_set: str, offset=None):
    """(structure, EquilibriumMap, design variables, lambda_N) of a design of ``target`` on
    ``grid`` with ``wiring``; the observables are the rigid residuals at the panel centres with
    the target corrected by ``offset`` (rigid_residual)."""
    if wiring not in grid_wirings(grid):
        raise InputError(
            f"wiring = {wiring!r} on grid {grid!r}: allowed {', '.join(grid_wirings(grid))}"
        )
    mode, wires = WIRINGS[wiring]
    layout = dataclasses.replace(GRIDS[grid], wiring=wires)
    ms = calibrate.model_set(model_set)
    structure, materials = ms.structure(layout), ms.materials_for(layout)
    setup = problem_bh.setup_gridshell(
        None, grid_support(grid), structure=structure, materials=materials
    )
    lambda_N = materials.lce.lambda_N
    params = strip_parameters(structure, gd.channel_selections(structure, mode), lambda_N)
    points = structure.panel_centres
    z = TARGETS[target][0]
    eq = EquilibriumMap(
        setup.model,
        setup.held,
        params,
        lambda x: rigid_residual(np.asarray(x).reshape(-1, 3)[points], z, offset),
        newton_options=gd.DESIGN_NEWTON,
        path_options=problem_bh.GRIDSHELL_PATH,
    )
    return structure, eq, params, lambda_N


def surface_at(
    target: str,
    grid: str,
    wiring: str,
    lambdas,
    model_set: str = calibrate.DEFAULT_MODEL_SET,
) -> np.ndarray:
    """The bar-and-hinge equilibrium (n, 3) [mm] of the design variables ``lambdas`` (the order of
    :func:`best_surface`'s), reached from the as-built state as the design loop's first
    evaluation reaches it (EquilibriumMap.equilibrium)."""
    _, eq, _, _ = _design_problem(target, grid, wiring, model_set)
    return eq.equilibrium(np.asarray(lambdas, dtype=float))[0]


def best_surface(
    target: str,
    grid: str,
    wiring: str,
    model_set: str = calibrate.DEFAULT_MODEL_SET,
    max_evaluations: int = 40,
    p0=None,
    offset=None,
) -> ReachResult:
    """The design loop's closest surface to ``target`` on ``grid`` with ``wiring`` (module
    docstring). ``p0``: the start (default the mid-range lambdas); ``offset`` (per panel centre
    [mm]): the target is z_target - offset there (rigid_residual), and ``rms`` is the distance
    from that corrected target."""
    t0 = time.process_time()
    structure, eq, params, lambda_N = _design_problem(target, grid, wiring, model_set, offset)
    points = structure.panel_centres
    z = TARGETS[target][0]
    if p0 is None:
        p0 = np.full(params.size, 0.5 * (gd.LAMBDA_MIN + lambda_N))
    elif len(p0) != params.size:
        raise InputError(f"p0: {len(p0)} lambdas, allowed {params.size} (one per design variable)")
    try:
        res = solve_design(
            eq,
            np.zeros(len(points)),
            p0,
            gd.LAMBDA_MIN,
            lambda_N,
            scale=1.0,
            absolute=1e-3,
            tolerance=1e-6,
            max_evaluations=max_evaluations,
        )
        r, p, x, n = res.residual, res.p, res.state.x, res.iterations
    except ConvergenceError:  # not even the start: the flat surface is the answer
        r, p, x, n = rigid_residual(structure.nodes[points], z, offset), p0, None, 0
    rms = float(np.sqrt(np.mean(np.square(r))))
    return ReachResult(
        target, grid, wiring, rms, params.size, np.asarray(p), n, time.process_time() - t0, x
    )


def reach_figure(path, rows: list[ReachResult], tolerance: float = 1.0):
    """RMS distance [mm] against grid and wiring, one line per target; the 1 mm line dashed."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from lcefem.validation.app.plots import save_figure

    combos = [
        (g, w) for g in GRIDS for w in WIRINGS if any(r.grid == g and r.wiring == w for r in rows)
    ]
    fig, ax = plt.subplots(figsize=(9, 4.5))
    for k, target in enumerate(t for t in TARGETS if any(r.target == t for r in rows)):
        pts = [
            (j, r.rms)
            for j, c in enumerate(combos)
            for r in rows
            if (r.grid, r.wiring) == c and r.target == target
        ]
        ax.plot(*zip(*pts), "o-", color=f"C{k}", label=target)
    ax.axhline(tolerance, color="k", ls="--", lw=0.8)
    ax.set_xticks(
        range(len(combos)),
        [
            f"{g}\n{w} ({n})"
            for (g, w), n in zip(
                combos, [next(r.variables for r in rows if (r.grid, r.wiring) == c) for c in combos]
            )
        ],
        fontsize=7,
    )
    ax.set_ylim(bottom=0.0)
    ax.set_ylabel("RMS distance from the target [mm]")
    ax.set_xlabel("grid, wiring (number of drives)")
    ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    out = save_figure(fig, path, 120)
    plt.close(fig)
    return out
