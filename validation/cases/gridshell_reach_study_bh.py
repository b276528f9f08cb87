"""What refinement and more channels buy (issue 47, item 3): the RMS distance [mm] of the best
surface each grid and wiring reaches from a set of target surfaces
(:mod:`lcefem.validation.studies.design.gridshell_reach_study`: targets, grids, wirings, the rigid
fit). Informative rows (one per target, grid and wiring) and the phenomenon the study shows
(validation/data/phenomena.toml); figure: RMS against grid and wiring.

Per target, one more row: the RMS of the paper's surface (3 x 3, 4 channels) minus the smallest RMS
of the other grids and wirings run [mm] (> 0: refinement or more drives come closer). Measured on
the Gaussian bump (2026-12-07, FE-calibrated set, rollers; CPU s on the shared machine): 3 x 3 with
4 channels 1.882 mm (14 s), 3 x 3 per strip 1.156 mm (24 s, 42 drives), refined 5 x 5 with 4
channels 1.855 mm (49 s), refined 5 x 5 per strip 0.761 mm (91 s, 110 drives): the bump the paper's
surface misses by 1.9 mm comes within 1 mm on the refined grid with a drive per strip, and neither
the refinement alone nor the drives alone bring it there. The two-wave surface likewise (3 x 3 with
4 channels 2.338 mm, refined 5 x 5 per strip 0.518 mm); the twisted one does not (4 channels 2.145
mm: they leave the surface flat; per strip 1.520 mm on the 3 x 3, 1.615 mm on the refined 5 x 5 at
the loop's 40-evaluation cap). Table and sources: docs/design.md.

The triangular grid (3 ribbons per family, clamp; 6 channels, 18 per ribbon, 51 per strip),
measured alone at the full level's settings (2026-12-07): 234 s CPU for its 21 rows; the 6
channels twist it (0.688 mm from the twisted target, 1.711 mm flat), which the 3 x 3's 4 channels
cannot; on the bump 1.787 mm with 6 channels, 1.290 mm per ribbon (docs/design.md). The honeycomb
(3 cells round a clamped junction) is not among the grids: its patch spans about 84 mm, so its
distances would not compare (gridshell_reach_study's docstring).

Quick level: :data:`QUICK` (the Gaussian bump on the 3 x 3 with 4 channels and per strip, 40 s CPU:
it shows that more drives come closer; the refined grid's 91 s is beyond the quick level's 60 s);
full level: every target, grid and wiring. The 3D FE confirmation of the best designs (issue 47):
informative rows from validation/data/gridshell_fe_reach_designs_level0.json when it is present
(benchmarks/gridshell_reach_fe.py: the design's lambdas per strip mapped to the FE strip tags,
meshes.gridshell_fe.fe_lambdas_of_strips; measured 2026-12-07: the FE of the bump's and the
two-wave's designs 1.224 and 1.026 mm from their targets, against the BH's 0.739 and 0.518 mm:
the FE does not confirm "within 1 mm", docs/design.md). The FE-corrected designs (output space
mapping on the FE's gap, benchmarks/gridshell_reach_fe.py --space-map; stored in
validation/data/gridshell_fe_reach_space_map_level0.json): judged rows against issue 47's 1 mm
(measured 2026-12-07: 0.683 and 0.618 mm after 3 FE runs each; level 0, which is 15 % off the
mesh-converged dome's curvature).
"""

from __future__ import annotations

import json

from lcefem.validation.app.plots import caption
from lcefem.validation.cases import NOT_JUDGED, CaseContext, Metric, case, write_csv
from lcefem.validation.cases.reference_data import DATA_DIR
from lcefem.validation.studies.design import gridshell_reach_study as rs

STUDY = (
    "bar-and-hinge design loop, FE-calibrated set, rollers: the closest equilibrium found "
    "(lcefem.validation.studies.design.gridshell_reach_study)"
)
#: (target, grid, wiring) of the quick level.
QUICK = (("gaussian bump", "3x3", "4 channels"), ("gaussian bump", "3x3", "per strip"))


def combinations(quick: bool):
    if quick:
        return QUICK
    return tuple((t, g, w) for t in rs.TARGETS for g in rs.GRIDS for w in rs.grid_wirings(g))


def metric_name(target: str, grid: str, wiring: str) -> str:
    return f"{target}: {grid}, {wiring}: RMS distance of the best surface"


def gain_name(target: str) -> str:
    return f"{target}: RMS of the 3x3 with 4 channels minus the best other grid and wiring"


@case(
    "gridshell_reach_study_bh",
    "Robotic surface: what refinement and more channels buy (RMS distance "
    "of the best reachable surface from target surfaces, per grid and wiring)",
    fe=False,
)
def gridshell_reach_study_bh(ctx: CaseContext) -> list[Metric]:
    name = ctx.case or "gridshell_reach_study_bh"
    metrics, rows = [], []
    for target, grid, wiring in combinations(ctx.quick):
        r = rs.best_surface(target, grid, wiring, max_evaluations=30 if ctx.quick else 40)
        rows.append(r)
        metrics.append(
            Metric.info(
                name,
                metric_name(target, grid, wiring),
                r.rms,
                "mm",
                f"{rs.TARGETS[target][1]}; {STUDY}; {r.variables} drives, "
                f"{r.evaluations} evaluations, {r.cpu:.1f} s CPU",
            )
        )
    for target in rs.TARGETS:
        paper = [
            r.rms for r in rows if (r.target, r.grid, r.wiring) == (target, "3x3", "4 channels")
        ]
        others = [
            r.rms
            for r in rows
            if r.target == target and (r.grid, r.wiring) != ("3x3", "4 channels")
        ]
        if paper and others:
            metrics.append(
                Metric.info(
                    name,
                    gain_name(target),
                    paper[0] - min(others),
                    "mm",
                    f"{rs.TARGETS[target][1]}; {STUDY}; the 3 x 3 with 4 channels "
                    f"{paper[0]:.3f} mm, the best other {min(others):.3f} mm",
                )
            )
    metrics += fe_confirmation(name)
    metrics += fe_corrected(name)
    targets = list(rs.TARGETS)
    grids, wirings = list(rs.GRIDS), list(rs.WIRINGS)
    write_csv(
        ctx.path("reach_study.csv"),
        {
            "target index [-]": [targets.index(r.target) for r in rows],
            "grid index [-]": [grids.index(r.grid) for r in rows],
            "wiring index [-]": [wirings.index(r.wiring) for r in rows],
            "drives [-]": [r.variables for r in rows],
            "RMS distance [mm]": [r.rms for r in rows],
            "evaluations [-]": [r.evaluations for r in rows],
            "CPU [s]": [r.cpu for r in rows],
        },
    )
    fig = rs.reach_figure(ctx.path("reach_study.png"), rows)
    ctx.add_figure(
        fig,
        caption(
            "RMS distance of the best surface the design loop finds from each target (rigid fit "
            "removed), "
            "against grid and wiring; dashed: 1 mm. Targets: "
            + "; ".join(
                f"{t}: {rs.TARGETS[t][1]}" for t in targets if any(r.target == t for r in rows)
            )
            + ".",
            ["seed 001, Fig. 4 and its next steps (fig. S6, S7)", STUDY],
        ),
    )
    return metrics


#: The 3D FE of the best designs on the refined 5 x 5 with a drive per strip
#: (benchmarks/gridshell_reach_fe.py).
FE_DESIGNS = DATA_DIR / "gridshell_fe_reach_designs_level0.json"


def fe_confirmation(name: str) -> list[Metric]:
    """Informative rows "<target>: 5x5, per strip: RMS distance of the design's 3D FE surface"
    (reference: the design's bar-and-hinge RMS) from the stored FE runs of :data:`FE_DESIGNS`,
    both levels (no solve: stored values)."""
    if not FE_DESIGNS.exists():
        return []
    ref = json.loads(FE_DESIGNS.read_text())
    out = []
    for row in ref["rows"]:
        out.append(
            Metric.info(
                name,
                f"{row['target']}: {row['grid']}, {row['wiring']}: RMS distance of the design's "
                "3D FE surface",
                row["FE RMS [mm]"],
                "mm",
                NOT_JUDGED
                + "the FE check of a design (reference: its bar-and-hinge RMS); "
                + ref["source"],
                reference=row["BH RMS [mm]"],
            )
        )
    return out


#: The FE-corrected designs (output space mapping, benchmarks/gridshell_reach_fe.py --space-map).
FE_CORRECTED = DATA_DIR / "gridshell_fe_reach_space_map_level0.json"
#: Distance [mm] within which a design's surface counts as reaching its target: issue 47's
#: threshold ("come within 1 mm RMS on a refined grid with more channels"). Not a measured error:
#: the level-0 FE the rows use is itself 15 % off the mesh-converged dome's circle curvature
#: (docs/notes/fe_bodies_log.md, "The full-ramp GCI, measured").
REACH_MM = 1.0


def fe_corrected(name: str) -> list[Metric]:
    """Per target of :data:`FE_CORRECTED`: the 3D FE RMS distance [mm] of the FE-corrected design
    (the space mapping's best iteration), judged against :data:`REACH_MM` (|value - 0| <= 1
    mm), pass or fail (no solve: stored values)."""
    if not FE_CORRECTED.exists():
        return []
    ref = json.loads(FE_CORRECTED.read_text())
    out = []
    for row in ref["rows"]:
        metric = (
            f"{row['target']}: {row['grid']}, {row['wiring']}: RMS distance of the FE-corrected "
            "design's 3D FE surface"
        )
        its = len(row["iterations"])
        source = (
            f"{its} FE runs, best iteration {row['best iteration']} (uncorrected design "
            f"{row['start FE RMS [mm]']:.3f} mm); threshold {REACH_MM:g} mm: issue 47's "
            "'within 1 mm RMS'; the level-0 FE is 15 % off the mesh-converged dome's circle "
            "curvature (docs/notes/fe_bodies_log.md, 'The full-ramp GCI, measured'); "
            + ref["source"]
        )
        # Judged whatever the stored value: a row that is judged only when it passes cannot fail.
        out.append(Metric.within(name, metric, row["FE RMS [mm]"], "mm", 0.0, REACH_MM, source))
    return out
