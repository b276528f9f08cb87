"""What refinement and more channels buy (issue 47, item 3): the RMS distance [mm] of the best surface
each grid and wiring reaches from a set of target surfaces (:mod:`lcefem.validation.gridshell_reach_study`:
targets, grids, wirings, the rigid fit). Informative rows (one per target, grid and wiring) and the
phenomenon the study shows (validation/data/phenomena.toml); figure: RMS against grid and wiring.

Quick level: :data:`QUICK` (the Gaussian bump on the 3 x 3 with 4 channels and per strip); full level:
every target, grid and wiring. The 3D FE confirmation of the best designs (issue 47) waits for the FE
mesh of the new layouts.
"""

from __future__ import annotations

from lcefem.validation import gridshell_reach_study as rs
from lcefem.validation.cases import CaseContext, Metric, case, write_csv
from lcefem.validation.plots import caption

STUDY = ("bar-and-hinge design loop, FE-calibrated set, rollers: the closest equilibrium found "
         "(lcefem.validation.gridshell_reach_study)")
#: (target, grid, wiring) of the quick level.
QUICK = (("gaussian bump", "3x3", "4 channels"), ("gaussian bump", "3x3", "per strip"))


def combinations(quick: bool):
    if quick:
        return QUICK
    return tuple((t, g, w) for t in rs.TARGETS for g in rs.GRIDS for w in rs.WIRINGS)


def metric_name(target: str, grid: str, wiring: str) -> str:
    return f"{target}: {grid}, {wiring}: RMS distance of the best surface"


@case("gridshell_reach_study_bh", "Robotic surface: what refinement and more channels buy (RMS distance "
      "of the best reachable surface from target surfaces, per grid and wiring)", fe=False)
def gridshell_reach_study_bh(ctx: CaseContext) -> list[Metric]:
    name = ctx.case or "gridshell_reach_study_bh"
    metrics, rows = [], []
    for target, grid, wiring in combinations(ctx.quick):
        r = rs.best_surface(target, grid, wiring, max_evaluations=30 if ctx.quick else 40)
        rows.append(r)
        metrics.append(Metric.info(name, metric_name(target, grid, wiring), r.rms, "mm",
                                   f"{rs.TARGETS[target][1]}; {STUDY}; {r.variables} drives, "
                                   f"{r.evaluations} evaluations, {r.cpu:.1f} s CPU"))
    targets = list(rs.TARGETS)
    grids, wirings = list(rs.GRIDS), list(rs.WIRINGS)
    write_csv(ctx.path("reach_study.csv"), {
        "target index [-]": [targets.index(r.target) for r in rows],
        "grid index [-]": [grids.index(r.grid) for r in rows],
        "wiring index [-]": [wirings.index(r.wiring) for r in rows],
        "drives [-]": [r.variables for r in rows], "RMS distance [mm]": [r.rms for r in rows],
        "evaluations [-]": [r.evaluations for r in rows], "CPU [s]": [r.cpu for r in rows]})
    fig = rs.reach_figure(ctx.path("reach_study.png"), rows)
    ctx.add_figure(fig, caption(
        "RMS distance of the best surface the design loop finds from each target (rigid fit removed), "
        "against grid and wiring; dashed: 1 mm. Targets: " + "; ".join(
            f"{t}: {rs.TARGETS[t][1]}" for t in targets if any(r.target == t for r in rows)) + ".",
        ["seed 001, Fig. 4 and its next steps (fig. S6, S7)", STUDY]))
    return metrics
