"""Closed-loop shape control of the robotic surface (issue 37; beyond seed 001, whose Discussion
names feedback as the next step), bar-and-hinge model: ``gridshell_control_bh``.

For each Fig. 4 target and each drawn plant (strip resistances, current factors and lambda_N from
the measured spreads, ambient 3 K below the model's; :mod:`lcefem.solvers.control`), open loop and
closed loop from flat on the same plant and sensor noise. Judged per target and draw (full
equilibria at the end of the phase from flat):

* closed loop within 0.002 1/mm of the target (issue 37);
* closed loop no worse than open loop, up to the sensor's resolution (1 SD of the measured circle
  curvature from one scan at 0.1 mm noise per marker coordinate): a closed loop cannot beat an open
  loop that lands by chance closer than its sensor resolves.

Informative: open-loop errors, time to target, the 100 g centre load step (tangent map) and the
strip failure, the largest current and longest boost (the paper's rule: 0.2 A, at most 30 s).

Quick level: the cylinder, one draw, no load or failure phase (~20-60 s). Default: the four shapes,
:data:`DRAWS` draws each, with the load and failure phases.
"""

from __future__ import annotations

from lcefem.meshes.gridshell import GridshellLayout
from lcefem.models.shape_control import HeightSensor, PlantSpread
from lcefem.solvers import control as ctl
from lcefem.validation.app.plots import caption
from lcefem.validation.cases import CaseContext, Metric, case, write_csv
from lcefem.validation.cases.programs import SHAPE_DRIVES
from lcefem.validation.studies.design.control import ControlRequest, control_figures, run_pair

SRC = (
    "issue 37; lcefem.solvers.control (plant: bar-and-hinge gridshell with lumped strip heat "
    "and the measured spreads of seed 001)"
)
DRAWS = (1, 2, 3)
QUICK_SHAPE = "cylinder"


@case(
    "gridshell_control_bh",
    "Robotic surface, closed-loop shape control: open vs closed loop from flat "
    "to the Fig. 4 targets under drawn strip spreads, a 100 g load step and a failed strip",
    fe=False,
)
def gridshell_control_bh(ctx: CaseContext) -> list[Metric]:
    name = ctx.case or "gridshell_control_bh"
    metrics: list[Metric] = []
    shapes = [QUICK_SHAPE] if ctx.quick else list(SHAPE_DRIVES)
    draws = DRAWS[:1] if ctx.quick else DRAWS
    scenario = ctl.Scenario(load_phase=0.0, failure_phase=0.0) if ctx.quick else ctl.Scenario()
    rows = {
        k: []
        for k in (
            "shape index [-]",
            "seed [-]",
            "open loop error [1/mm]",
            "closed loop error [1/mm]",
            "closed loop time to target [s]",
            "resolution [1/mm]",
        )
    }
    for shape in shapes:
        surface = ctl.build_surface(shape, SHAPE_DRIVES[shape], GridshellLayout())
        resolution = ctl.sensor_resolution(surface, ctl.ControllerSettings(), HeightSensor().noise)
        for seed in draws:
            req = ControlRequest(
                shape,
                "channels",
                seed,
                PlantSpread(),
                HeightSensor(),
                scenario=scenario,
                movie=False,
            )
            pair = run_pair(req, surface)
            o, c = pair["open"], pair["closed"]
            eo, ec = o.phase_errors["target"], c.phase_errors["target"]
            tag = f"{shape}, draw {seed}"
            metrics.append(
                Metric.between(
                    name, f"{tag}: closed-loop error from flat", ec, "1/mm", 0.0, ctl.TOLERANCE, SRC
                )
            )
            metrics.append(
                Metric.between(
                    name,
                    f"{tag}: closed minus open loop error",
                    ec - eo,
                    "1/mm",
                    -1.0,
                    resolution,
                    SRC + f"; upper bound: the sensor's "
                    f"curvature resolution {resolution:.2e} 1/mm (0.1 mm noise, one scan)",
                )
            )
            metrics.append(Metric.info(name, f"{tag}: open-loop error from flat", eo, "1/mm", SRC))
            metrics.append(
                Metric.info(
                    name,
                    f"{tag}: closed-loop time to target",
                    c.time_to_target["target"],
                    "s",
                    SRC + " (error stays below 0.002 1/mm)",
                )
            )
            metrics.append(
                Metric.info(
                    name,
                    f"{tag}: closed-loop largest current",
                    c.max_current,
                    "A",
                    "seed 001: limit 0.2 A",
                )
            )
            metrics.append(
                Metric.info(
                    name,
                    f"{tag}: closed-loop longest boost above 0.1 A",
                    c.longest_boost,
                    "s",
                    "seed 001: at most 30 s at 0.2 A",
                )
            )
            for ph, what in (
                ("load", "100 g centre load (tangent map)"),
                ("failure", "one strip failed"),
            ):
                if ph in c.phase_errors:
                    for loop, r in (("open", o), ("closed", c)):
                        metrics.append(
                            Metric.info(
                                name,
                                f"{tag}: {loop}-loop error after {what}",
                                r.phase_errors[ph],
                                "1/mm",
                                SRC,
                            )
                        )
            rows["shape index [-]"].append(list(SHAPE_DRIVES).index(shape))
            rows["seed [-]"].append(seed)
            rows["open loop error [1/mm]"].append(eo)
            rows["closed loop error [1/mm]"].append(ec)
            rows["closed loop time to target [s]"].append(c.time_to_target["target"])
            rows["resolution [1/mm]"].append(resolution)
            if seed == draws[0]:
                out = ctx.path(f"control_{shape}")
                out.mkdir(parents=True, exist_ok=True)
                fig = control_figures(out, req, pair)[0]
                ctx.add_figure(
                    fig,
                    caption(
                        f"{shape}: curvature error of open and closed loop from flat "
                        f"(draw {seed}; markers: full equilibria at phase ends).",
                        ["seed 001, Fig. 4", SRC],
                    ),
                )
    write_csv(ctx.path("control_errors.csv"), rows)
    return metrics
