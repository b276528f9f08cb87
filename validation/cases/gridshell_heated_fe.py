"""3D FE case of the robotic surface driven by its currents (seed 001, Fig. 4; issues 14 and 31),
heated route.

``gridshell_heated_fe``: the heated route on the paper's dome protocol (0.1 A top / 0.2 A bottom
for 20 s, then 0.04 / 0.07 A held;
:class:`lcefem.solvers.problems.gridshell_heated.HeatedGridshellFE`, quarter, level 0, the published
rollers): the first second's heating against the adiabatic closed form (judged), the centre
curvature against time (CSV, figure), the peak and the held dome next to the bar-and-hinge current
route and the paper. Full level: the 20 s of heating at 1 s steps, then the hold in 9 doubling
backward-Euler steps to 2555 s (the steady held state). The coils run on through the junctions
(``junction_heating = "added"``, seed 001's coils lie in the grid-shaped mould channels), so the
held dome is judged against the paper's. Quick level: the first 3 s at 1 s steps (9 Newton
iterations, ~10 s CPU): the surface domes (kappa_x = kappa_y < 0) and the dome grows each step. Then
the four Fig. 4 shapes held at their currents (validation/data/programs.toml, gridshell_shapes
"currents"; the protocol is published for the dome only), straight to the steady state
(HeatedGridshellFE.steady_hold: steady heat -> temperature -> lambda -> mechanics) on their
published supports: the steady lambda per channel next to the bar-and-hinge current route's (both
levels; quick: the heat alone), the held curvatures against the paper and the bar-and-hinge current
route, and the dome's steady route against the transient hold (judged: within the hold's last-step
change) (full level; CSV gridshell_held_fe.csv, figure). Full level also: the stored FE current
route at level 1 (validation/data/gridshell_fe_current_route_level1.json) against the experiment,
and the bar-and-hinge current route in the FE-calibrated model set against it at the same currents
and at the FE's own channel lambdas (judged; the published set informative).

Units: mm, 1/mm, N, MPa, s, C, A.
"""

from __future__ import annotations

import json
import math
import time

import numpy as np

from lcefem.validation.app import plots
from lcefem.validation.cases import NOT_JUDGED, CaseContext, Metric, case, not_judged, write_csv
from lcefem.validation.cases.gridshell_fe import BH, KAPPA_KEYS, SIM_TOLERANCE, run_bh_shape

# --------------------------------------------------------------------------- heated route
#: Quick level of gridshell_heated_fe: the first seconds of the dome protocol's heating [s] and
#: its time step [s]: the centre already domes in x and y and the dome grows each step (the 1 s
#: run to 120 s, validation/data/gridshell_fe_heated_dome_quarter_level0.csv: kappa_x circle
#: -2.8e-5, -7.4e-5, -1.45e-4 1/mm at 1, 2, 3 s).
HEATED_QUICK = (3.0, 1.0)
#: Full level: the heating phase's time step [s] (the 1 s run's: peak -0.025142 1/mm at 20 s, 244
#: Newton iterations; a coarser step is untested) and the hold: first step [s], growth [-] and
#: end [s]. The 1 s run relaxes with a time constant tau of
#: ~90 s between 60 and 120 s; a backward-Euler step dt leaves 1/(1 + dt/tau) of the distance to
#: the steady state, so 9 doubling steps (5 ... 640 s, then 1260 s to 2555 s) leave ~1e-3 of it.
HEATED_FULL_DT = 1.0
HEATED_HOLD = (5.0, 2.0, 2555.0)
#: Band of the early heating [-]: over the first second the heat stored in the model is nearly the
#: coils' Joule energy, never more (no other source) and within 15 % of it (the losses to the air;
#: tests/solvers/test_gridshell_problem.py::test_heated_route_first_second).
ADIABATIC_BAND = (0.85, 1.0)
HEATED_SOURCE = (
    "seed 001, Results: 'we first apply 0.1 A to each of the top LCE strips and 0.2 A "
    "to the bottom ... After about 20 s, the currents are switched to I_Bx = I_By = "
    "0.07 A and I_Tx = I_Ty = 0.04 A ... to keep the robotic surface at a stable dome'"
)
FE_STEADY = (
    "3D FE gridshell, heated route held to the steady state directly "
    "(HeatedGridshellFE.steady_hold), quarter, level 0, published supports"
)
FE_HEATED = (
    "3D FE gridshell, heated route (lcefem.solvers.problems.gridshell_heated.HeatedGridshellFE), "
    "quarter, level 0"
)


def _heated_rows(quick: bool, on_step=None) -> tuple[object, list[dict], list[dict]]:
    """The dome protocol on the heated FE gridshell (quarter, level 0): (model, heating rows from
    t = 0, hold rows) at the case's level (HEATED_QUICK / HEATED_FULL_DT, HEATED_HOLD)."""
    from lcefem.meshes.gridshell_fe import GridshellFEMesh
    from lcefem.solvers.problems.gridshell import GridshellConfig
    from lcefem.solvers.problems.gridshell_heated import HeatedGridshellFE
    from lcefem.validation.cases.programs import DOME_PROTOCOL

    duration, dt = HEATED_QUICK if quick else (DOME_PROTOCOL[1][0], HEATED_FULL_DT)
    model = HeatedGridshellFE(
        GridshellConfig(mesh=GridshellFEMesh(level=0), symmetry="quarter"), dt=dt
    )

    def energy(
        row: dict,
    ) -> None:  # the energy balance of the heating (heat stored vs Joule energy)
        row["heat content [mJ]"], row["Joule power [mW]"] = (
            model.heat_content(),
            model.joule_power(),
        )
        if on_step is not None:
            on_step(row)

    heating = model.run_protocol(DOME_PROTOCOL[:1], duration=duration, dt=dt, on_step=energy)
    hold = []
    if not quick:
        first, growth, until = HEATED_HOLD
        hold = model.hold(DOME_PROTOCOL[1][1], until, first, growth, on_step=on_step)
    return model, heating, hold


def _held_shapes(quick: bool, model=None, on_shape=None) -> dict[str, dict]:
    """Each Fig. 4 shape held at its currents (lcefem.validation.cases.programs.SHAPE_DRIVES
    "currents"), straight to the steady state (quarter, level 0): the steady heat equation at those
    currents -> temperature -> lambda per strip -> the mechanics at that temperature
    (HeatedGridshellFE.steady_hold, on the shape's published supports). Quick level: the steady
    heat alone (temperatures and lambdas per channel) on one model for all four (``model``, e.g.
    the protocol's after its 3 s, whose deformation barely moves the exchange area; the supports
    do not enter the heat). Full level: the dome continues from ``model`` (the protocol's, held
    at the dome's currents to 2555 s: its steady route is the check of the hold), the other three
    from the as-built state. {shape: observables of the held state}."""
    from lcefem.meshes.gridshell_fe import GridshellFEMesh
    from lcefem.solvers.problems.gridshell import GridshellConfig, GridshellSupports
    from lcefem.solvers.problems.gridshell_heated import STEADY_PICARD_ITERATIONS, HeatedGridshellFE
    from lcefem.validation.cases.programs import PUBLISHED_SUPPORTS
    from lcefem.validation.studies.gridshell import gridshell_bh as gs

    out = {}
    for shape, spec in gs.SHAPES.items():
        c0 = time.process_time()
        if quick:
            model = model or HeatedGridshellFE(GridshellConfig(mesh=GridshellFEMesh(level=0)))
            model.set_drives(spec["currents"])
            model.heat.steady(max_iterations=STEADY_PICARD_ITERATIONS)
            obs = {**model.observables(), "newton iterations [-]": 0}
        else:
            held = (
                model
                if shape == "dome" and model is not None
                else HeatedGridshellFE(
                    GridshellConfig(
                        mesh=GridshellFEMesh(level=0),
                        supports=GridshellSupports(kind=PUBLISHED_SUPPORTS[shape]),
                    )
                )
            )
            rows = held.steady_hold(spec["currents"])
            obs = {
                **rows[-1],
                "newton iterations [-]": sum(r["newton iterations [-]"] for r in rows),
            }
        out[shape] = {k: v for k, v in obs.items() if not k.startswith("junction_")}
        out[shape]["cpu [s]"] = time.process_time() - c0
        if on_shape is not None:
            on_shape(shape, out[shape])
    return out


def _held_metrics(
    name: str, held: dict, mechanics: bool, transient: tuple | None
) -> tuple[list[Metric], dict]:
    """Rows of the held shapes (:func:`_held_shapes`) next to the bar-and-hinge current route and
    the paper; ``transient``: the dome protocol's last two hold rows (the steady route's check).
    Returns (metrics, bar-chart series)."""
    from lcefem.models import lumped_heat
    from lcefem.validation.studies.gridshell import gridshell_bh as gs

    route = lumped_heat.CurrentRouteConfig()  # the grid strip (issue 31), as the FE heat source
    src = gs.SHAPE_SOURCES["curvatures"]
    metrics: list[Metric] = []
    chart = {
        "3D FE, held (steady)": {},
        "bar-and-hinge current route": {},
        "paper simulation": {},
        "paper experiment": {},
    }
    for shape, obs in held.items():
        spec = gs.SHAPES[shape]
        currents = " / ".join(f"{ch} {spec['currents'][ch]:g}" for ch in ("Tx", "Ty", "Bx", "By"))
        label = f"held {shape} ({currents} A)"
        bh_lambdas = lumped_heat.lambda_assignments_from_currents(spec["currents"], route)
        for ch in ("Tx", "Ty", "Bx", "By"):
            metrics.append(
                Metric.info(
                    name,
                    f"{label}: steady lambda, {ch}",
                    obs[f"lambda {ch} [-]"],
                    "-",
                    f"{FE_STEADY}; model vs model: FE heat equation vs the "
                    "lumped steady balance of one grid strip "
                    "(models.lumped_heat.stretch_from_current)",
                    bh_lambdas[ch],
                )
            )
        if not mechanics:
            continue  # quick level: the heat alone
        bh = run_bh_shape(bh_lambdas, spec["support"])
        kappa = (obs["kappa_circle_x [1/mm]"], obs["kappa_circle_y [1/mm]"])
        chart["3D FE, held (steady)"][shape] = kappa
        chart["bar-and-hinge current route"][shape] = (bh[KAPPA_KEYS[0]], bh[KAPPA_KEYS[1]])
        chart["paper simulation"][shape] = spec["paper_sim"]
        chart["paper experiment"][shape] = spec["paper_exp"]
        for i, axis in enumerate("xy"):
            for against, ref in (
                ("simulation", spec["paper_sim"]),
                ("experiment", spec["paper_exp"]),
            ):
                if ref[i] is None:
                    continue
                metrics.append(
                    Metric.within(
                        name,
                        f"{label}: kappa_{axis} circle vs paper {against}",
                        kappa[i],
                        "1/mm",
                        ref[i],
                        SIM_TOLERANCE,
                        f"{src}; currents: {gs.SHAPE_SOURCES['currents']}; "
                        "tolerance: as gridshell_shapes_fe (sim-exp spread 0.002 "
                        "+ precision 0.001)",
                    )
                )
            metrics.append(
                Metric.info(
                    name,
                    f"{label}: kappa_{axis} circle vs bar-and-hinge current route",
                    kappa[i],
                    "1/mm",
                    f"model vs model; {FE_STEADY}; {BH}, current route 'strip'",
                    bh[KAPPA_KEYS[i]],
                )
            )
        metrics.append(
            Metric.info(
                name, f"{label}: Newton iterations", obs["newton iterations [-]"], "-", FE_STEADY
            )
        )
    if mechanics and transient is not None and "dome" in held:
        last, before = transient
        key = "kappa_circle_x [1/mm]"
        metrics.append(
            Metric.within(
                name,
                f"held dome: steady route vs the transient hold at t = {last['time [s]']:g} s, "
                "kappa_x circle",
                held["dome"][key],
                "1/mm",
                last[key],
                abs(last[key] - before[key]),
                "the steady state is the hold's limit (backward Euler tends to it); tolerance: the "
                "hold's own last-step change of kappa_x (its distance to the limit is smaller)",
            )
        )
    return metrics, chart


#: Stored runs of the FE current route (issue 31): the rule's currents at mesh level 1 (``lcefem run
#: gridshell --model fe --shape NAME --route current --mesh-level 1``, one summary per shape,
#: gathered by ``python -m lcefem.validation.studies.gridshell.gridshell_fe_current_store DIR ...``)
#: and the dome protocol's junction-heating change (``python -m
#: lcefem.validation.studies.gridshell.gridshell_junction_heating``). Each takes 10-60 min of one
#: core, so the case reads them instead of running them.
CURRENT_ROUTE_LEVEL1 = "gridshell_fe_current_route_level1.json"
JUNCTION_HEATING_DOME = "gridshell_junction_heating_dome_protocol_l0.json"


def _stored_current_route_rows(name: str) -> list[Metric]:
    """Judged rows of the stored FE current-route runs (:data:`CURRENT_ROUTE_LEVEL1`, written by
    ``python -m lcefem.validation.studies.gridshell.gridshell_fe_current_store``): each shape's
    circle curvatures from the rule's currents at level >= 1 against the experiment (within
    :data:`SIM_TOLERANCE`) and against the bar-and-hinge current route at the same currents (within
    10 % of the FE or 0.002 1/mm, the larger: the issue's point 3, validation.calibrate's
    tolerance); a failing row per required shape (dome, saddle) whose run is not stored, or was run
    with a junction heating other than the default (never silence); and info rows of the dome
    protocol's junction-heating change (:data:`JUNCTION_HEATING_DOME`)."""
    from lcefem.models import lumped_heat
    from lcefem.solvers.problems.gridshell_heated import JUNCTION_HEATING_DEFAULT
    from lcefem.validation.cases.reference_data import DATA_DIR
    from lcefem.validation.studies.gridshell import gridshell_bh as gs
    from lcefem.validation.studies.gridshell.calibrate import ABS_TOL, REL_TOL
    from lcefem.validation.studies.gridshell.gridshell_fe_current_store import REQUIRED

    metrics: list[Metric] = []
    path = DATA_DIR / CURRENT_ROUTE_LEVEL1
    runs = json.loads(path.read_text())["runs"] if path.exists() else {}
    for shape in REQUIRED:
        run = runs.get(shape)
        why = (
            "not stored"
            if run is None
            else "run with junction_heating "
            f"'{run.get('junction_heating', 'off (before the field)')}', "
            f"not the default '{JUNCTION_HEATING_DEFAULT}'"
            if run.get("junction_heating") != JUNCTION_HEATING_DEFAULT
            else None
        )
        if why is None:
            continue
        runs.pop(shape, None)
        exp = gs.SHAPES[shape]["paper_exp"]
        metrics.append(
            Metric.within(
                name,
                f"{shape} from the rule's currents, level >= 1: kappa_x circle vs paper experiment "
                f"({why})",
                math.nan,
                "1/mm",
                exp[0],
                SIM_TOLERANCE,
                f"validation/data/{CURRENT_ROUTE_LEVEL1}: the FE current route of this shape is "
                f"{why}; "
                f"run lcefem run gridshell --model fe --shape {shape} --route current --mesh-level "
                "1 "
                "--out "
                "DIR, then python -m "
                "lcefem.validation.studies.gridshell.gridshell_fe_current_store "
                "DIR",
            )
        )
    from lcefem.validation.studies.gridshell import gridshell_current_route as bh_routes

    tol_src = (
        "the issue's 10 % of the FE or 0.002 1/mm, the larger "
        "(validation.calibrate.REL_TOL, ABS_TOL)"
    )
    for shape, run in runs.items():
        held, exp = run["held"], gs.SHAPES[shape]["paper_exp"]
        currents = " / ".join(
            f"{ch} {run['current [A]'][ch]:.4f}" for ch in ("Tx", "Ty", "Bx", "By")
        )
        label = f"{shape} from the rule's currents ({currents} A), level {run['mesh level']}"
        src = (
            f"3D FE heated gridshell, quarter, mesh level {run['mesh level']}, {run['support']}, "
            f"junction_heating '{run.get('junction_heating', 'off')}' "
            f"(validation/data/{CURRENT_ROUTE_LEVEL1}); currents: {run['current rule']}; "
            f"{gs.SHAPE_SOURCES['curvatures']}"
        )
        # each model set's lambdas through the exchange factor calibrated with it
        # (bh_routes.set_route)
        lumped = lumped_heat.lambda_assignments_from_currents(
            run["current [A]"], bh_routes.set_route("fe-calibrated")
        )
        lumped_pub = lumped_heat.lambda_assignments_from_currents(
            run["current [A]"], bh_routes.set_route("published")
        )
        # the point 3 in the FE-calibrated model set (strip element, plate torsion, fitted
        # factors, validation.calibrate: within 10 % of the FE at the Fig. 4 lambdas), judged; the
        # published set informative; and the mechanics alone: the FE-calibrated BH at the FE's own
        # channel lambdas (the FE's heat, the BH's surface), judged
        bh_cal = bh_routes.bh_curvatures(shape, lumped, "fe-calibrated")
        bh_pub = bh_routes.bh_curvatures(shape, lumped_pub, "published")
        bh_mech = bh_routes.bh_curvatures(shape, bh_routes.fe_lambdas(held), "fe-calibrated")
        cal_src = (
            "bar-and-hinge, FE-calibrated model set (validation.calibrate.model_set: strip element "
            "'beam', plate torsion, validation/data/bar_hinge_calibration.json; published supports "
            "and glue squares + contact + volume law), lambdas of "
        )
        for i, axis in enumerate("xy"):
            fe = held[f"kappa_circle_{axis} [1/mm]"]
            key = f"circle_{axis}"
            if exp[i] is not None:
                metrics.append(
                    Metric.within(
                        name,
                        f"{label}: kappa_{axis} circle vs paper experiment",
                        fe,
                        "1/mm",
                        exp[i],
                        SIM_TOLERANCE,
                        src + "; tolerance: as gridshell_shapes_fe",
                    )
                )
            metrics.append(
                Metric.within(
                    name,
                    f"{label}: bar-and-hinge current route (FE-calibrated set) kappa_{axis} circle "
                    "vs "
                    "the FE",
                    bh_cal[key],
                    "1/mm",
                    fe,
                    max(REL_TOL * abs(fe), ABS_TOL),
                    f"model vs model at the same currents: {cal_src}the current route 'strip' "
                    "(lumped "
                    "grid "
                    f"strip, models.lumped_heat) vs {src}; tolerance: {tol_src}",
                )
            )
            metrics.append(
                Metric.within(
                    name,
                    f"{label}: bar-and-hinge (FE-calibrated set) at the FE's channel lambdas, "
                    f"kappa_{axis} "
                    "circle vs the FE",
                    bh_mech[key],
                    "1/mm",
                    fe,
                    max(REL_TOL * abs(fe), ABS_TOL),
                    f"the mechanics alone: {cal_src}the FE's channel means (lambda_s at each "
                    "channel's "
                    "mean "
                    f"T of the held FE) vs {src}; tolerance: {tol_src}",
                )
            )
            metrics.append(
                Metric.info(
                    name,
                    f"{label}: bar-and-hinge current route (published set) kappa_{axis} circle",
                    bh_pub[key],
                    "1/mm",
                    f"informative: {BH}, published model set, current route 'strip'; FE {fe:.4f}",
                    fe,
                )
            )
    path = DATA_DIR / JUNCTION_HEATING_DOME
    if path.exists():
        doc = json.loads(path.read_text())
        for key, run in doc["runs"].items():
            held = run["held"]
            src = (
                f"3D FE heated gridshell, quarter, level {doc['mesh level']}, dome protocol hold "
                f"0.04 / 0.07 A, junction_heating '{run['junction_heating']}' "
                f"(validation/data/{JUNCTION_HEATING_DOME})"
            )
            metrics.append(
                Metric.info(
                    name,
                    f"held dome, {key}: kappa_x circle",
                    held["kappa_circle_x [1/mm]"],
                    "1/mm",
                    f"{NOT_JUDGED}a controlled change of the model; {src}",
                    doc["measured circle x/y [1/mm] (seed 001)"][0],
                )
            )
            metrics.append(
                Metric.info(
                    name,
                    f"held dome, {key}: bottom strips' mean temperature",
                    held["T_mean Bx [C]"],
                    "C",
                    f"model vs model: the lumped grid strip's steady temperature at 0.07 A; {src}",
                    doc["lumped grid strip (steady)"]["Bx"]["T [C]"],
                )
            )
    return metrics


@case(
    "gridshell_heated_fe",
    "Robotic surface in 3D FE, heated route: the paper's dome protocol (0.1 / "
    "0.2 A for 20 s, then 0.04 / 0.07 A held), quarter, level 0: early heating rate vs adiabatic, "
    "centre curvature against time, peak and held dome vs bar-and-hinge and the paper",
    fe=True,
)
def gridshell_heated_fe(ctx: CaseContext) -> list[Metric]:
    from lcefem.models import lumped_heat
    from lcefem.validation.studies.gridshell import gridshell_bh as gs

    name = ctx.case or "gridshell_heated_fe"
    ctx.mesh_size = 3.0  # [mm] level 0 (meshes.gridshell_fe.GridshellFEMesh.size)
    t0, c0 = time.perf_counter(), time.process_time()
    model, heating, hold = _heated_rows(ctx.quick)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    # ParaView: the held dome (quick: the end of its first seconds) before the held shapes move on
    model.write_fields(ctx.path("fields_heated_dome"))
    rows = heating + hold
    keys = [k for k in rows[0] if k.endswith("]") and not k.startswith("junction_")]
    write_csv(
        ctx.path("gridshell_heated_fe.csv"),
        {k: [r.get(k, math.nan) for r in rows] for k in keys + ["newton iterations [-]"]},
    )
    metrics: list[Metric] = []
    # early heating: the whole model's heat stored over the first step vs the Joule energy (no
    # other source; the losses to the air make it smaller); each channel's strips vs q/(rho c)
    first = next(r for r in heating if r["time [s]"] > 0)
    stored = first["heat content [mJ]"] - heating[0]["heat content [mJ]"]
    metrics.append(
        Metric.between(
            name,
            f"first {first['time [s]']:g} s: heat stored in the model / Joule energy",
            stored / (first["Joule power [mW]"] * first["time [s]"]),
            "-",
            *ADIABATIC_BAND,
            "closed form: the energy balance of the heat equation (rho c integral of T over the "
            "model, "
            "HeatedGridshellFE.heat_content, vs the coils' power, joule_power, times the step); "
            "band: never "
            "above (no other source), losses to the air within 15 %",
        )
    )
    for ch in ("Tx", "Bx"):
        current = first[f"current {ch} [A]"]
        adiabatic = model.adiabatic_rate(current) * first["time [s]"]  # [K]
        rise = first[f"T_mean {ch} [C]"] - heating[0][f"T_mean {ch} [C]"]
        metrics.append(
            Metric.info(
                name,
                f"first {first['time [s]']:g} s at {current:g} A, {ch} strips: temperature rise / "
                "adiabatic q/(rho c) t",
                rise / adiabatic,
                "-",
                "closed form: q = I^2 R/(L W_s H) of the grid strip coil's 34.8 ohm per 30 mm "
                "segment "
                "(models.lumped_heat.grid_segment_resistance), rho c of "
                "models.heat.ThermalProperties; not a "
                "bound with the junctions heated (the default): where two coils cross (the "
                "junction "
                "centres, the glue squares) the source is twice the strips', and heat flows into "
                "them",
                1.0,
            )
        )
    # the dome while heated: both curvatures negative and still growing at the end of the heating
    end, before = heating[-1], heating[-2]
    for axis in ("x", "y"):
        key = f"kappa_circle_{axis} [1/mm]"
        metrics.append(
            Metric.info(
                name,
                f"heating (0.1 / 0.2 A), t = {end['time [s]']:g} s: kappa_{axis} circle",
                end[key],
                "1/mm",
                FE_HEATED,
            )
        )
        metrics.append(
            Metric.info(
                name,
                f"heating: change of kappa_{axis} circle over the last step "
                f"({before['time [s]']:g} -> {end['time [s]']:g} s)",
                end[key] - before[key],
                "1/mm",
                FE_HEATED,
            )
        )
    times = [r["time [s]"] for r in rows]
    kx = [r["kappa_circle_x [1/mm]"] for r in rows]
    sim, exp = gs.SHAPES["dome"]["paper_sim"], gs.SHAPES["dome"]["paper_exp"]
    src = gs.SHAPE_SOURCES["curvatures"]
    if hold:
        peak = int(np.argmin(kx))
        metrics.append(
            Metric.info(
                name,
                "peak dome: kappa_x circle",
                kx[peak],
                "1/mm",
                f"{NOT_JUDGED}the paper publishes the held dome only; {FE_HEATED}",
                sim[0],
            )
        )
        metrics.append(Metric.info(name, "peak dome: time", times[peak], "s", FE_HEATED))
        held, prev = hold[-1], hold[-2]
        label = f"held (0.04 / 0.07 A), t = {held['time [s]']:g} s"
        for i, axis in enumerate(("x", "y")):
            value = held[f"kappa_circle_{axis} [1/mm]"]
            for against, ref in (("simulation", sim), ("experiment", exp)):
                metrics.append(
                    Metric.within(
                        name,
                        f"{label}: kappa_{axis} circle vs paper {against}",
                        value,
                        "1/mm",
                        ref[i],
                        SIM_TOLERANCE,
                        f"{src}; {HEATED_SOURCE}; tolerance: as gridshell_shapes_fe "
                        "(sim-exp spread 0.002 + precision 0.001)",
                    )
                )
        metrics.append(
            Metric.info(
                name,
                f"{label}: relative change of kappa_x circle over the last "
                f"hold step ({prev['time [s]']:g} -> {held['time [s]']:g} s)",
                held["kappa_circle_x [1/mm]"] / prev["kappa_circle_x [1/mm]"] - 1.0,
                "-",
                f"{FE_HEATED}: the held state is steady when this is small",
            )
        )
        # the bar-and-hinge current route: the hold currents' steady lambdas on the dome's rollers
        route = lumped_heat.CurrentRouteConfig()  # the grid strip (issue 31), as the FE heat source
        bh_lambdas = lumped_heat.lambda_assignments_from_currents(
            gs.SHAPES["dome"]["currents"], route
        )
        bh = run_bh_shape(bh_lambdas, gs.SHAPES["dome"]["support"])
        metrics.append(
            Metric.info(
                name,
                f"{label}: kappa_x circle vs bar-and-hinge current route",
                held["kappa_circle_x [1/mm]"],
                "1/mm",
                f"model vs model; {FE_HEATED}; {BH}, current route 'strip'",
                bh[KAPPA_KEYS[0]],
            )
        )
        for ch, layer in (("Bx", "bottom"), ("Tx", "top")):
            metrics.append(
                Metric.info(
                    name,
                    f"{label}: {layer} strips' mean temperature",
                    held[f"T_mean {ch} [C]"],
                    "C",
                    FE_HEATED,
                )
            )
            metrics.append(
                Metric.info(
                    name,
                    f"{label}: {layer} strips' lambda vs the bar-and-hinge "
                    "current route's steady lambda",
                    held[f"lambda {ch} [-]"],
                    "-",
                    "model vs model: FE heat equation vs the lumped steady balance "
                    "of one grid strip (models.lumped_heat.stretch_from_current)",
                    bh_lambdas[ch],
                )
            )
    # the four Fig. 4 shapes held at their currents, straight to the steady state
    held = _held_shapes(ctx.quick, model)
    held_rows, chart = _held_metrics(
        name, held, not ctx.quick, (hold[-1], hold[-2]) if hold else None
    )
    metrics += held_rows
    write_csv(
        ctx.path("gridshell_held_fe.csv"),
        {
            "shape index [-]": list(range(len(held))),
            **{
                k: [held[s].get(k, math.nan) for s in held]
                for k in next(iter(held.values()))
                if k.endswith("]")
            },
        },
    )
    if chart["3D FE, held (steady)"]:
        from lcefem.validation.studies.gridshell.gridshell_plots import curvature_bar_chart

        shapes = list(chart["3D FE, held (steady)"])
        sources = [gs.SHAPE_SOURCES["currents"], gs.SHAPE_SOURCES["curvatures"], FE_STEADY, BH]
        ctx.add_figure(
            curvature_bar_chart(ctx.path("gridshell_held_fe.png"), shapes, chart, sources),
            plots.caption(
                "Centre curvatures (circle measure, dome negative) of the four "
                "Fig. 4 shapes held at their currents: 3D FE steady state vs "
                "bar-and-hinge current route vs the paper; CSV: "
                "gridshell_held_fe.csv (row order " + ", ".join(shapes) + ")",
                sources,
            ),
        )
    if not ctx.quick:
        metrics += _stored_current_route_rows(name)
    its = sum(r.get("newton iterations [-]", 0) for r in rows)
    metrics += [
        Metric.info(name, "Newton iterations", its, "-", FE_HEATED),
        Metric.info(name, "time steps", len(rows) - 1, "-", FE_HEATED),
        Metric.info(name, "wall time (shared machine)", wall, "s", FE_HEATED),
        Metric.info(name, "CPU time", cpu, "s", FE_HEATED),
    ]
    series = [
        plots.Series(
            [t for t in times if t > 0],
            [k for t, k in zip(times, kx) if t > 0],
            "3D FE, kappa_x = kappa_y (circle)",
            marker="o",
        )
    ]
    lines = [
        plots.Line(sim[0], "paper simulation (held dome)", "published model"),
        plots.Line(exp[0], "paper experiment (held dome)", "experiment"),
    ]
    png = plots.comparison_plot(
        ctx.path("gridshell_heated_fe.png"),
        series,
        xlabel="time [s]",
        ylabel="centre kappa_x, dome < 0 [1/mm]",
        sources=[HEATED_SOURCE, src, FE_HEATED],
        hlines=lines,
        logx=True,
        vlines=[plots.Line(20.0, "currents switched (20 s)", "reference")] if hold else (),
    )
    ctx.add_figure(
        png,
        plots.caption(
            "Centre curvature of the heated FE gridshell against time on the "
            "paper's dome protocol (log time axis); CSV: gridshell_heated_fe.csv "
            "(temperatures, lambdas, both curvature measures); ParaView fields "
            "of the last state in fields_heated_dome/ (displacement, "
            "temperature and lambda_s(T), cell lambda, stress).",
            [HEATED_SOURCE, src, FE_HEATED],
        ),
    )
    return not_judged(
        metrics,
        "model vs model (FE vs bar-and-hinge current route) or a value the paper does not publish",
    )
