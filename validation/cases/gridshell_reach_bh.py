"""Designs the robot reaches from flat (issue 50), bar-and-hinge model, FE-calibrated set.

``gridshell_reach_bh``: for each Fig. 4 target (seed 001: the measured dome, saddle and cylinder,
the table's flat) on its published support and two off-grid targets on rollers, ``lcefem design``'s
default: the design loop, then :func:`lcefem.validation.studies.design.gridshell_design.reach`.
Judged: the run's own path from flat (``lcefem run gridshell`` at the printed lambdas) ends within
the design tolerance (1e-4 1/mm, both curvatures) of the target, or, where no constant set does, the
program found ends there and its schedule, replayed as ``lcefem run gridshell --schedule`` does,
too. Reported: the design loop's lambdas and where the run from flat takes them (the branch it lands
on), the kind of design, its CPU time. Figure: per target, the design loop's equilibrium, the run
from flat at its lambdas and the final design's run, in the (kappa_x, kappa_y) plane. The quick
level runs the table and the cylinder (measured: 12 s and 39 s CPU, both constant designs; the
cylinder's loop lambdas land 4e-4 1/mm off from flat, one Gauss-Newton step along the run's path
closes it to 3.9e-5).
"""

from __future__ import annotations

import time

import numpy as np

from lcefem.validation.app.plots import caption
from lcefem.validation.cases import CaseContext, Metric, case, write_csv
from lcefem.validation.studies.design import gridshell_design as gd
from lcefem.validation.studies.gridshell import gridshell_bh as gs

BH = (
    "bar-and-hinge gridshell design reached from flat "
    "(lcefem.validation.studies.design.gridshell_design.reach)"
)
#: Off-grid targets [1/mm] on rollers (not Fig. 4 shapes): an elongated dome and a shallow
#: cylinder-like bend, inside the channels' reachable set (case gridshell_design_bh's figure).
OFF_GRID = {"elongated dome": (-0.010, -0.006), "shallow bend": (0.008, 0.003)}
QUICK = ("table", "cylinder")


def targets(quick: bool) -> dict[str, tuple[tuple[float, float], str, str]]:
    """{name: ((kappa_x, kappa_y) [1/mm], support, source)}."""
    out = {}
    for shape, spec in gs.SHAPES.items():
        if quick and shape not in QUICK:
            continue
        kind = "measured" if spec["paper_exp"][0] is not None else "simulated (flat)"
        k = spec["paper_exp"] if spec["paper_exp"][0] is not None else spec["paper_sim"]
        out[shape] = (tuple(k), spec["support"], f"seed 001, Fig. 4: the {kind} {shape}")
    if not quick:
        for name, k in OFF_GRID.items():
            out[name] = (k, "rollers", "off-grid target (assumed), not a Fig. 4 shape")
    return out


@case(
    "gridshell_reach_bh",
    "Robotic surface: designs the run from flat reaches (constant lambdas or a "
    "program of channel drives) for the Fig. 4 targets and two off-grid ones",
    fe=False,
)
def gridshell_reach_bh(ctx: CaseContext) -> list[Metric]:
    name = ctx.case or "gridshell_reach_bh"
    metrics: list[Metric] = []
    rows = {
        k: []
        for k in (
            "target index [-]",
            "target kappa_x [1/mm]",
            "target kappa_y [1/mm]",
            "loop kappa_x [1/mm]",
            "loop kappa_y [1/mm]",
            "flat run at loop lambdas kappa_x [1/mm]",
            "flat run at loop lambdas kappa_y [1/mm]",
            "design kappa_x [1/mm]",
            "design kappa_y [1/mm]",
            "kind (0 constant, 1 program, 2 none) [-]",
            "distance [1/mm]",
            "CPU [s]",
        )
    }
    plotted = {}
    for j, (label, (k, support, src)) in enumerate(targets(ctx.quick).items()):
        t0 = time.process_time()
        design = gd.setup_design("4", support)
        res = gd.inverse(design, *k)
        found = res.check["reach"]
        summ = gd.design_summary(design, res)
        first = found.attempts[0].get("achieved", (float("nan"), float("nan")))
        judged = f"{src}; {BH}; support {support}"
        metrics.append(
            Metric.within(
                name,
                f"{label}: distance of the run from flat to the target",
                found.distance,
                "1/mm",
                0.0,
                gd.DESIGN_TOLERANCE,
                f"{judged}; design kind: {found.kind}",
            )
        )
        if found.kind == "program":
            replayed = gd.replay(design, gd.program_schedule(design, found.stages))
            d = max(abs(replayed["circle_x"] - k[0]), abs(replayed["circle_y"] - k[1]))
            metrics.append(
                Metric.within(
                    name,
                    f"{label}: the program's schedule replayed (lcefem run gridshell --schedule)",
                    d,
                    "1/mm",
                    0.0,
                    gd.DESIGN_TOLERANCE,
                    judged,
                )
            )
        for axis, v, ref in zip("xy", first, k):
            metrics.append(
                Metric.info(
                    name,
                    f"{label}: run from flat at the design loop's lambdas, kappa_{axis}",
                    v,
                    "1/mm",
                    f"the branch the run lands on without the reach search (target {ref:g} 1/mm)",
                )
            )
        cpu = time.process_time() - t0
        metrics.append(
            Metric.info(
                name,
                f"{label}: CPU time of the design",
                cpu,
                "s",
                f"{len(found.attempts)} runs from flat; design kind {found.kind}; "
                "lambdas " + ", ".join(f"{n}={v:.4f}" for n, v in summ["lambdas [-]"].items()),
            )
        )
        loop = res.state.observables[:2]
        for key, v in zip(
            rows,
            (
                j,
                *k,
                *loop,
                *first,
                *found.achieved,
                {"constant": 0, "program": 1}.get(found.kind, 2),
                found.distance,
                cpu,
            ),
        ):
            rows[key].append(float(v))
        over = None
        if found.kind == "program":  # where the overshoot alone lands from flat
            over = next(
                (
                    a["achieved"]
                    for a in found.attempts
                    if len(a["stages"]) == 1
                    and "achieved" in a
                    and np.array_equal(a["stages"][0], found.stages[0])
                ),
                None,
            )
        plotted[label] = {
            "target": k,
            "loop": tuple(loop),
            "flat": tuple(first),
            "design": found.achieved,
            "kind": found.kind,
            "overshoot": over,
            "runs": [
                a["achieved"] for a in found.attempts if len(a["stages"]) == 1 and "achieved" in a
            ],
        }
    write_csv(ctx.path("reach.csv"), rows)
    from lcefem.validation.studies.gridshell.gridshell_plots import reach_figure

    fig = reach_figure(ctx.path("reach_branches.png"), plotted)
    ctx.add_figure(
        fig,
        caption(
            "Where each design lands. Per target (x): the design loop's equilibrium "
            "(o: it holds the target on the branch the loop followed), the run from "
            "flat at those lambdas (square: the branch the robot reaches), and the "
            "final design's run from flat (filled star: constant lambdas; open star: "
            "a program of drives).",
            ["seed 001, Fig. 4", BH],
        ),
    )
    return metrics
