"""Inverse design of the robotic surface (issue 15), bar-and-hinge model.

- ``gridshell_design_strips_bh``: every strip its own design variable (``--channels all``): the
  shape (centre curvatures and centre height) of a random strip lambda set is found again by a
  forward run from as built at the lambdas found (judged; the lambdas need not return: 42 variables,
  3 targets). Full level: the 3 x 3 surface; quick: one cell.
- ``gridshell_design_bh``: round trips (a Fig. 4 lambda set -> forward run -> its centre curvatures
  -> inverse from the mid-range start -> a forward run at the lambdas found reproduces the
  curvatures within 1e-4 1/mm; judged), the time per inverse solve; at the default level the
  table, saddle and cylinder (:data:`ROUND_TRIP_SHAPES`), then the inverse runs from the paper's
  measured curvatures (table: the flat (0, 0)) with the currents found next to the paper's
  currents (informative), and the reachable set of (kappa_x, kappa_y) over a
  :data:`REACHABLE_LEVELS`^4 grid of channel lambdas (figure). The quick level runs the cylinder
  round trip (~25 s CPU with the default FE-calibrated model set).

  Cost of the default level (issue 13): the dome's round trip is not run. It cost 1020 s of the
  case's 2737 s, and the dome's inverse from the paper's measured (-0.016, -0.016) runs the same
  loop: the same :func:`~lcefem.validation.studies.design.gridshell_design.inverse` from the same
  mid-range start on the same rollers, warm-started solves past the dome's fold, the forward check
  from as built and its restarts from the ramp's branch. Only the target differs: the Fig. 4
  lambdas' own curvatures, -0.0236 1/mm, against -0.016 1/mm. By hand: ``lcefem design --target-kx
  -0.02359 --target-ky -0.02359``. The reachable set uses 2 lambdas per channel (the 16 corners 1.05
  / lambda_N) instead of 3 (81 points, 1298 s CPU); see :data:`REACHABLE_LEVELS` for the ranges of
  both.
"""

from __future__ import annotations

import numpy as np

from lcefem.meshes.gridshell import GridshellLayout
from lcefem.models import lumped_heat
from lcefem.solvers.problems.gridshell_bh import centre_height
from lcefem.validation.app.plots import caption
from lcefem.validation.cases import CaseContext, Metric, case, not_judged, write_csv
from lcefem.validation.studies.design import gridshell_design as gd
from lcefem.validation.studies.gridshell import gridshell_bh as gs
from lcefem.validation.studies.gridshell.gridshell_plots import reachable_set_figure

BH = "bar-and-hinge gridshell inverse design (lcefem.validation.studies.design.gridshell_design)"
#: Round-trip tolerance [1/mm] (issue 15): a tenth of the 0.001 1/mm the paper reports curvatures
#: to.
ROUND_TRIP = 1.0e-4
#: Random strip lambdas of the per-strip case: uniform in the paper's programmed range [1.05, 1.35]
#: (seed 001, Fig. 4: 1.05 contracted, 1.33 nearly as built), fixed seed so the target is one shape.
RANDOM_LAMBDAS = (1.05, 1.35)
RANDOM_SEED = 7
#: Shapes whose Fig. 4 lambda sets make the round trips of the default level (the dome's loop is
#: the one its paper-target inverse runs; module docstring).
ROUND_TRIP_SHAPES = ("table", "saddle", "cylinder")
#: Lambdas per channel of the default level's reachable set (rollers): 2, the corners of
#: [1.05, lambda_N]^4 (16 equilibria). The extremes of the centre curvatures sit at corners of the
#: lambda box (each channel's contraction bends the cells one way, monotonically), so the 3^4 grid
#: added only interior points; the report states the kappa ranges the grid reaches.
REACHABLE_LEVELS = 2


def _p(design, lambdas: dict) -> np.ndarray:
    return np.array([lambdas[k] for k in design.names])


@case(
    "gridshell_design_bh",
    "Robotic surface, inverse design: round trips of the Fig. 4 lambda sets, "
    "currents for the paper's measured curvatures, reachable set",
    fe=False,
)
def gridshell_design_bh(ctx: CaseContext) -> list[Metric]:
    name = ctx.case or "gridshell_design_bh"
    metrics: list[Metric] = []
    shapes = ["cylinder"] if ctx.quick else list(ROUND_TRIP_SHAPES)
    src = "seed 001, Results (Fig. 4 B-E): the lambda sets; " + BH
    for shape in shapes:
        spec = gs.SHAPES[shape]
        design = gd.setup_design("4", spec["support"])
        truth = gd.forward_check(design, _p(design, spec["lambdas"]))
        res = gd.inverse(design, truth["circle_x"], truth["circle_y"])
        check, seconds = res.check, res.seconds
        for axis in ("x", "y"):
            metrics.append(
                Metric.within(
                    name,
                    f"{shape}: round trip kappa_{axis} (forward run at the lambdas found)",
                    check[f"circle_{axis}"],
                    "1/mm",
                    truth[f"circle_{axis}"],
                    ROUND_TRIP,
                    src,
                )
            )
        metrics.append(
            Metric.info(
                name,
                f"{shape}: time per inverse solve",
                seconds,
                "s",
                f"{res.stats.solves} warm-started forward solves, "
                f"{res.stats.newton_iterations} Newton iterations, with the forward "
                "check from as built (machine load matters)",
            )
        )
    if ctx.quick:
        return metrics
    metrics += paper_targets(ctx, name)
    design = gd.setup_design("4", "rollers")
    grid = gd.reachable_set(design, levels=REACHABLE_LEVELS)
    write_csv(
        ctx.path("reachable_set.csv"),
        {
            **{f"lambda {k} [-]": grid[:, j] for j, k in enumerate(design.names)},
            "kappa_x [1/mm]": grid[:, -2],
            "kappa_y [1/mm]": grid[:, -1],
        },
    )
    points = {
        f"{s} (paper exp.)": spec["paper_exp"]
        for s, spec in gs.SHAPES.items()
        if spec["paper_exp"][0] is not None
    }
    for j, axis in ((-2, "x"), (-1, "y")):
        for label, value in (("smallest", grid[:, j].min()), ("largest", grid[:, j].max())):
            metrics.append(
                Metric.info(
                    name,
                    f"reachable set: {label} kappa_{axis}",
                    value,
                    "1/mm",
                    f"range over the {REACHABLE_LEVELS}^4 lambda grid, for "
                    "comparison with the paper's measured shapes (figure)",
                )
            )
    fig = reachable_set_figure(
        ctx.path("reachable_set.png"),
        grid[:, -2:],
        points,
        f"Reachable centre curvatures, four channels, rollers ({REACHABLE_LEVELS}^4 lambda grid)",
    )
    ctx.add_figure(
        fig,
        caption(
            f"Centre curvatures (circle measure) of the equilibria on a {REACHABLE_LEVELS}^4 grid "
            "of "
            "channel lambdas in [1.05, 1.4] (roller supports) and the paper's "
            "measured shapes.",
            ["seed 001, Fig. 4", BH],
        ),
    )
    return metrics


def paper_targets(ctx: CaseContext, name: str) -> list[Metric]:
    """Inverse runs from the paper's measured curvatures (table: flat), currents next to the
    paper's."""
    metrics: list[Metric] = []
    rows: dict[str, list] = {
        k: []
        for k in (
            "shape",
            "channel",
            "lambda [-]",
            "segment route [A]",
            "eq1 route [A]",
            "paper [A]",
        )
    }
    for shape, spec in gs.SHAPES.items():
        target = spec["paper_exp"] if spec["paper_exp"][0] is not None else spec["paper_sim"]
        kind = "measured" if spec["paper_exp"][0] is not None else "simulated (flat)"
        design = gd.setup_design("4", spec["support"])
        res = gd.inverse(design, *target)
        check, seconds = res.check, res.seconds
        summ = gd.design_summary(design, res)
        src = f"seed 001: the {kind} curvatures of the {shape}; " + BH
        how = ""
        if "failed" in check:  # the ramp from as built meets a fold: the design loop's equilibrium
            how = " (design-loop equilibrium; the ramp from as built did not converge)"
        for axis, k in (("x", 0), ("y", 1)):
            value = float(res.state.observables[k]) if how else check[f"circle_{axis}"]
            metrics.append(
                Metric.info(
                    name,
                    f"{shape}: kappa_{axis} for the paper's {kind} target",
                    value,
                    "1/mm",
                    src + how,
                    reference=target[k],
                )
            )
        metrics.append(
            Metric.info(
                name,
                f"{shape}: residual |kappa - target|",
                summ["residual norm [1/mm]"],
                "1/mm",
                src + " (0 when the target is reachable)",
            )
        )
        metrics.append(Metric.info(name, f"{shape}: time per inverse solve", seconds, "s", src))
        for ch in design.names:
            cur = summ["currents [A]"]
            for route in lumped_heat.THERMAL_MODELS:
                metrics.append(
                    Metric.info(
                        name,
                        f"{shape}: current {ch} ({route} route)",
                        cur[route][ch],
                        "A",
                        gs.SHAPE_SOURCES["currents"],
                        reference=spec["currents"][ch],
                    )
                )
            rows["shape"].append(shape)
            rows["channel"].append(ch)
            rows["lambda [-]"].append(summ["lambdas [-]"][ch])
            rows["segment route [A]"].append(cur["segment"][ch])
            rows["eq1 route [A]"].append(cur["eq1"][ch])
            rows["paper [A]"].append(spec["currents"][ch])
    numeric = {k: v for k, v in rows.items() if k not in ("shape", "channel")}
    numeric["shape index [-]"] = [list(gs.SHAPES).index(s) for s in rows["shape"]]
    numeric["channel index [-]"] = [["Tx", "Ty", "Bx", "By"].index(c) for c in rows["channel"]]
    write_csv(ctx.path("paper_targets.csv"), numeric)
    return not_judged(
        metrics,
        "the design reaches a target through its own model; the paper's "
        "currents come from its lambda-current chart, and several lambda sets give the "
        "same two curvatures (4 channels, 2 targets)",
    )


@case(
    "gridshell_design_strips_bh",
    "Robotic surface, inverse design per strip: the shape (centre "
    "curvatures and height) of a random strip lambda set found again",
    fe=False,
)
def gridshell_design_strips_bh(ctx: CaseContext) -> list[Metric]:
    name = ctx.case or "gridshell_design_strips_bh"
    layout = GridshellLayout(ribbons=1) if ctx.quick else GridshellLayout()
    design = gd.setup_design("all", "rollers", height=True, layout=layout)
    p_true = np.random.default_rng(RANDOM_SEED).uniform(*RANDOM_LAMBDAS, design.eq.params.size)
    truth = gd.forward_check(design, p_true)
    z_true = centre_height(design.structure, truth["x"])
    res = gd.inverse(design, truth["circle_x"], truth["circle_y"], height=z_true)
    check = res.check
    src = (
        f"a random lambda set (seed {RANDOM_SEED}, uniform "
        f"{RANDOM_LAMBDAS[0]}-{RANDOM_LAMBDAS[1]}) "
        f"on {design.eq.params.size} strips, rollers; " + BH
    )
    metrics = [
        Metric.within(
            name,
            f"kappa_{axis} found again (forward run at the lambdas found)",
            check[f"circle_{axis}"],
            "1/mm",
            truth[f"circle_{axis}"],
            ROUND_TRIP,
            src,
        )
        for axis in ("x", "y")
    ]
    # A caliper's 0.1 mm (the height's residual scale in the design) is the tolerance of a height.
    metrics.append(
        Metric.within(
            name,
            "centre height found again",
            centre_height(design.structure, check["x"]),
            "mm",
            z_true,
            gd.HEIGHT_SCALE,
            src,
        )
    )
    metrics.append(
        Metric.info(
            name,
            "largest |lambda found - lambda drawn|",
            float(np.max(np.abs(res.p - p_true))),
            "-",
            src + " (not judged: more variables than targets)",
        )
    )
    metrics.append(
        Metric.info(
            name,
            "time per inverse solve",
            res.seconds,
            "s",
            f"{res.stats.solves} warm-started forward solves, "
            f"{res.stats.newton_iterations} Newton iterations (machine load matters)",
        )
    )
    write_csv(
        ctx.path("strip_lambdas.csv"),
        {
            "strip index [-]": np.arange(design.eq.params.size),
            "lambda drawn [-]": p_true,
            "lambda found [-]": res.p,
        },
    )
    return metrics
