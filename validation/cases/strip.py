"""Validation cases of the 3D FE strip model against seed 001 (Fig. 2), closed forms, manufactured
solutions.

Cases: the transients at 0.2, 0.15 and 0.1 A; the steady stretch at the six hold currents against
Eq. 1; the blocked force at 0.2 A; uniform heating (closed form); the isotropic-phase tension test
against the published Ogden fit; the manufactured-solution checks of the heat and mechanics solvers.

Resolution: ``ctx.level`` when given (``lcefem converge``), else QUICK_LEVEL with ``--quick`` and
DEFAULT_LEVEL otherwise; the default level is the one the convergence study (README, 'Mesh
convergence') shows to have a small mesh error.

Time steps (FULL_DT, QUICK_DT): backward Euler, error proportional to dt. Halving the full level's
steps (0.2 A and held 0.5 s, 0.15 A and 0.1 A 1 s, before) moved the judged times by at most 0.5 %
(level 0: 0.2 A t95 20.62 -> 20.64 s, surface 70 C 14.18 s unchanged; 0.1 A t95 93.66 -> 94.17 s;
0.15 A t95 34.31 -> 34.48 s; held: force at 30 s 1.20935 -> 1.20934 N, t95 19.50 -> 19.59 s),
against acceptance windows of 10 s and more, for half the CPU time.
"""

from __future__ import annotations

import numpy as np

from lcefem.meshes.strip import StripMesh
from lcefem.models.empirical import eq1_stretch
from lcefem.models.hyperelastic import (
    PUBLISHED_MODEL,
    lce_uniaxial_nominal_stress,
    ogden_uniaxial_nominal_stress,
)
from lcefem.validation.app import plots
from lcefem.validation.cases import NOT_JUDGED, CaseContext, Metric, case, write_csv
from lcefem.validation.cases.reference_data import reference

QUICK_LEVEL = 0
DEFAULT_LEVEL = 1  # h = 1 mm: within 1 % of the extrapolated values of the 0.2 A study (README)
#: Time steps [s] of the transients and the held strip (module docstring), full and --quick.
FULL_DT = {"0p2A": 1.0, "0p15A": 2.0, "0p1A": 2.0, "held": 1.0}
#: --quick (level 0, CI): 0.2 A t95 20.64 -> 20.73 s and surface 70 C 14.182 -> 14.179 s with 1 -> 2
#: s steps, 0.1 A t95 94.74 -> 96.23 s with 3 -> 6 s steps, 0.15 A 34.48 -> 34.95 s with 2 -> 4 s,
#: held t95 19.59 -> 19.72 s and force at 30 s 1.20934 -> 1.20931 N with 1 -> 2 s.
QUICK_DT = {"0p2A": 2.0, "0p15A": 4.0, "0p1A": 6.0, "held": 2.0}

# Acceptance windows (issue 2, 'What it must show'), each around the seed 001 measurement it cites.
WINDOWS = {
    "t70_0p2A": (
        5.0,
        15.0,
        "window of issue 2 around the measured 'within 10 s' (1 Hz camera, T_NI only '~70 C')",
    ),
    "t95_0p2A": (12.0, 30.0, "window of issue 2 around 'about 20 s until full contraction'"),
    "t95_0p1A": (80.0, 180.0, "window of issue 2 around 'almost 120 s for full contraction'"),
    "eq1": (
        0.03,
        "tolerance of issue 2 on the steady stretch: Eq. 1 is a fit to samples whose nematic "
        "lengths scatter by +-6 % (seed 001: 130.22 +- 8.01 mm)",
    ),
    "isotropic_length": (0.005, "tolerance of issue 2: 0.5 % on the length ratio"),
    "tension": (0.05, "tolerance of issue 2: 5 % in nominal stress for stretch 1.0-1.5"),
    "blocked_rise": (
        15.0,
        45.0,
        "'about 30 s' (seed 001): +-50 %, as the measured curves end in "
        "rupture rather than a plateau",
    ),
    "blocked_force": (
        0.20,
        "+-20 %: the blocked force scales with the Ogden stress at lambda_N, and the "
        "measured nematic lengths (lambda_N = 1.63 +- 0.10) against Eq. 1's 1.426 move it "
        "by more than that",
    ),
    "mms_heat": (0.15, "tolerance of issue 2 on the observed L2 order of the heat solver"),
    "mms_mechanics": (
        0.3,
        "pre-asymptotic coarse meshes (n = 2, 4, 8): finest pair within 0.3 of 3",
    ),
}
#: Q2 hexahedra on uniform meshes reach order 3 from above: measured 3.86, 3.43 and 3.33 for the
#: pairs n = 2 -> 4, 4 -> 8 and 8 -> 16 (the last takes 7 min, so it is not part of the case); the
#: check is order in [3 - 0.3, 3.5].
HEX_MMS_UPPER = 3.5
HEX_MMS_WHY = (
    "Q2 hexahedra approach 3 from above on uniform meshes (measured 3.86, 3.43, 3.33 for "
    "n = 2->4, 4->8, 8->16): range [2.7, 3.5]"
)


def strip_mesh(ctx: CaseContext, **kw) -> StripMesh:
    level = ctx.level if ctx.level is not None else (QUICK_LEVEL if ctx.quick else DEFAULT_LEVEL)
    return StripMesh(level=level, **kw)


def _dt(ctx: CaseContext, key: str) -> float:
    return (QUICK_DT if ctx.quick else FULL_DT)[key]


def _run_config(ctx: CaseContext, **run):
    from lcefem.solvers.problems.strip import StripConfig, StripRun

    return StripConfig(run=StripRun(**run), mesh=strip_mesh(ctx))


def render_strip_end(path, result, title: str):
    """PNG of the last 20 mm of a strip run's deformed body coloured by temperature, mirrored from
    the quarter model to the whole section; returns the path."""
    from lcefem.validation.app import render

    model, dims = result.model, result.summary["as_built"]
    L, W, H = dims["length"], dims["width"], dims["thickness"]
    mirror = ((1, 0.5 * W), (2, 0.5 * H)) if result.summary["mesh"]["symmetry"] == "quarter" else ()
    return render.render_deformed(
        path,
        model.u,
        model.heat.T,
        scalar_label="temperature [C]",
        title=title,
        mirror=mirror,
        crop=(0, L - 20.0, L),
        zoom=1.3,
    )


def _render(ctx: CaseContext, result, name: str, title: str, sources) -> None:
    """The last 20 mm of the strip, mirrored from the quarter model to the whole section."""
    png = render_strip_end(ctx.path(f"{name}.png"), result, title)
    ctx.add_figure(
        png,
        plots.caption(
            f"{title}: the free end of the deformed strip (last 20 mm of the as-built length, "
            "whole "
            "section drawn from the quarter model) coloured by temperature; grey lines: as built. "
            "Full fields for ParaView in run/*.bp.",
            sources,
        ),
    )


def _transient(ctx: CaseContext, index: int, duration: float, dt: float) -> list[Metric]:
    """Free strip heated at the index-th transient current of seed 001 (0.1, 0.15, 0.2 A)."""
    from lcefem.solvers.problems.strip import run_strip
    from lcefem.validation.cases.programs import SEED_T_NI

    currents = reference("strip.transient_currents")
    powers = reference("strip.transient_powers")
    current = currents.value[index]
    cfg = _run_config(ctx, current=current, duration=duration, dt=dt)
    res = run_strip(cfg, ctx.out / "run", progress=ctx.progress, crossing_temperature=SEED_T_NI)
    ctx.mesh_size = res.summary["mesh"]["element_size [mm]"]
    m = res.summary["metrics"]
    h = res.history
    tag = f"{current:g} A"
    metrics = [
        Metric.within(
            "",
            f"electric power I^2 R at {tag}",
            cfg.coil.power(current),
            "mW",
            powers.value[index],
            powers.spread[index],
            powers.source,
        )
    ]
    t_NI = reference("strip.transient_0p2A.time_to_T_NI")
    t_full = {
        0.2: reference("strip.transient_0p2A.time_to_full_contraction"),
        0.1: reference("strip.transient_0p1A.time_to_full_contraction"),
    }
    if current == 0.2:
        lo, hi, why = WINDOWS["t70_0p2A"]
        metrics.append(
            Metric.between(
                "",
                "time for the surface to reach 70 C",
                m["time_to_70C_surface [s]"],
                "s",
                lo,
                hi,
                f"{t_NI.source}; {why}",
            )
        )
        metrics.append(
            Metric.info(
                "",
                "time for the volume mean to reach 70 C",
                m["time_to_70C_mean [s]"],
                "s",
                f"{NOT_JUDGED}the camera sees the surface (judged above); the volume "
                f"mean is shown for scale; {t_NI.source}",
                reference=t_NI.value,
            )
        )
    key = {0.2: "t95_0p2A", 0.1: "t95_0p1A"}.get(current)
    if key:
        lo, hi, why = WINDOWS[key]
        metrics.append(
            Metric.between(
                "",
                "time to 95 % of the full contraction",
                m["time_to_95pct_contraction [s]"],
                "s",
                lo,
                hi,
                f"{t_full[current].source}; {why}",
            )
        )
    else:
        metrics.append(
            Metric.info(
                "",
                "time to 95 % of the full contraction",
                m["time_to_95pct_contraction [s]"],
                "s",
                "no time is given in seed 001 for 0.15 A (Fig. 2B only)",
            )
        )
    # Tolerance 0.03 in stretch, as the steady states of strip_steady_eq1 against Eq. 1.
    metrics.append(
        Metric.within(
            "",
            f"stretch at {duration:g} s",
            m["final_stretch [-]"],
            "-",
            1.0,
            0.03,
            "full contraction is the isotropic length, stretch 1 (seed 001); tolerance "
            "0.03 as the steady states against Eq. 1 (strip_steady_eq1)",
        )
    )
    src = [currents.cite, t_NI.cite]
    spans = [plots.Span(*WINDOWS[key][:2], "acceptance window (95 %)")] if key else []
    lam_N = cfg.transition.lambda_N
    png = plots.comparison_plot(
        ctx.path("stretch.png"),
        [plots.Series(h["time [s]"], h["stretch [-]"], f"model, {tag}", "model")],
        xlabel="time [s]",
        ylabel="relative length lambda [-]",
        sources=src,
        vspans=spans,
        hlines=[
            plots.Line(lam_N - 0.95 * (lam_N - 1.0), "95 % of full contraction", "reference"),
            plots.Line(1.0, "isotropic length", "reference"),
        ],
        title=f"Free strip at {tag}: relative length",
    )
    ctx.add_figure(
        png,
        plots.caption(
            f"Relative length of the free strip at {tag} (model) with the "
            "acceptance window for 95 % of the full contraction.",
            src,
        ),
    )
    temp_spans = (
        [plots.Span(*WINDOWS["t70_0p2A"][:2], "acceptance window (70 C)")] if current == 0.2 else []
    )
    png = plots.comparison_plot(
        ctx.path("temperature.png"),
        [
            plots.Series(h["time [s]"], h["T_mean [C]"], "model, volume mean", "model"),
            plots.Series(
                h["time [s]"], h["T_surface [C]"], "model, surface mean", "model", color="C1"
            ),
            plots.Series(
                h["time [s]"], h["T_max [C]"], "model, maximum (coil)", "model", color="C3"
            ),
        ],
        xlabel="time [s]",
        ylabel="temperature [C]",
        sources=src,
        vspans=temp_spans,
        hlines=[plots.Line(reference("strip.T_NI").value, "T_NI ~ 70 C (seed 001)")],
        title=f"Free strip at {tag}: temperature",
    )
    ctx.add_figure(
        png,
        plots.caption(
            f"Strip temperatures at {tag}: the infrared camera of seed 001 saw the surface.", src
        ),
    )
    _render(ctx, res, "strip_3d", f"{tag}, t = {duration:g} s", src)
    return metrics


@case(
    "strip_transient_0p2A",
    "Free strip heated at 0.2 A for 30 s: time to 70 C and to 95 % "
    "contraction (seed 001 Fig. 2A-B)",
    fe=True,
    convergence=True,
)
def strip_transient_0p2A(ctx: CaseContext) -> list[Metric]:
    return _transient(
        ctx, 2, reference("strip.transient_0p2A.max_duration").value, _dt(ctx, "0p2A")
    )


@case("strip_transient_0p15A", "Free strip heated at 0.15 A for 60 s (seed 001 Fig. 2B)", fe=True)
def strip_transient_0p15A(ctx: CaseContext) -> list[Metric]:
    return _transient(ctx, 1, 60.0, _dt(ctx, "0p15A"))


@case(
    "strip_transient_0p1A",
    "Free strip heated at 0.1 A for 180 s: time to 95 % contraction (seed 001 Fig. 2B)",
    fe=True,
)
def strip_transient_0p1A(ctx: CaseContext) -> list[Metric]:
    return _transient(ctx, 0, 180.0, _dt(ctx, "0p1A"))


@case(
    "strip_steady_eq1",
    "Steady stretch at the six hold currents against Eq. 1 (seed 001 Fig. 2C)",
    fe=True,
)
def strip_steady_eq1(ctx: CaseContext) -> list[Metric]:
    from lcefem.solvers.problems.strip import StripSimulation

    currents = sorted(reference("strip.hold_currents").value)
    g1 = reference("eq1.gamma_1")
    tol, why = WINDOWS["eq1"]
    rows = {
        "current [A]": [],
        "power [mW]": [],
        "stretch model [-]": [],
        "stretch Eq. 1 [-]": [],
        "T_mean [C]": [],
        "T_surface [C]": [],
    }
    metrics = []
    # One model for all currents (mesh and forms built once), each steady state continued from
    # the last one (currents in increasing order): the same fixed point to its tolerance (1e-8).
    cfg = _run_config(ctx, current=currents[0], steady=True)
    sim = StripSimulation(cfg)
    ctx.mesh_size = sim.dims["element_size"]
    for current in currents:
        sim.set_drives({"coil": current})
        obs = sim.steady().observables
        power = cfg.coil.power(current)
        target = float(eq1_stretch(power))
        for k, v in (
            ("current [A]", current),
            ("power [mW]", power),
            ("stretch model [-]", obs["stretch [-]"]),
            ("stretch Eq. 1 [-]", target),
            ("T_mean [C]", obs["T_mean [C]"]),
            ("T_surface [C]", obs["T_surface [C]"]),
        ):
            rows[k].append(v)
        metrics.append(
            Metric.within(
                "",
                f"steady stretch at {current:g} A",
                obs["stretch [-]"],
                "-",
                target,
                tol,
                f"{g1.source}; {why}",
            )
        )
    write_csv(ctx.path("steady.csv"), rows)
    p = np.linspace(0.0, 1400.0, 200)
    src = [g1.cite]
    png = plots.comparison_plot(
        ctx.path("steady.png"),
        [
            plots.Series(p / 1e3, eq1_stretch(p), "Eq. 1 (seed 001 fit)", "closed form"),
            plots.Series(
                np.array(rows["power [mW]"]) / 1e3,
                rows["stretch model [-]"],
                "model (3D FE)",
                "model",
                marker="s",
            ),
        ],
        xlabel="electric power P [W]",
        ylabel="steady relative length lambda [-]",
        sources=src,
        title="Steady stretch at the hold currents 0.04-0.09 A",
    )
    ctx.add_figure(
        png, plots.caption("Steady relative length vs electric power: model against Eq. 1.", src)
    )
    return metrics


@case(
    "strip_blocked_force",
    "Strip held at its nematic length at 0.2 A: force rise and plateau "
    "against the 1.36 N rupture force (seed 001 Fig. 2D)",
    fe=True,
    convergence=True,
)
def strip_blocked_force(ctx: CaseContext) -> list[Metric]:
    from lcefem.solvers.problems.strip import run_strip
    from lcefem.validation.cases.programs import SEED_T_NI

    duration = reference("blocked.rise_time").value
    cfg = _run_config(
        ctx,
        current=reference("blocked.current").value,
        duration=duration,
        dt=_dt(ctx, "held"),
        bc="held",
    )
    res = run_strip(cfg, ctx.out / "run", progress=ctx.progress, crossing_temperature=SEED_T_NI)
    ctx.mesh_size = res.summary["mesh"]["element_size [mm]"]
    h, m = res.history, res.summary["metrics"]
    rupture, rise = reference("blocked.rupture_force"), reference("blocked.rise_time")
    tol, why_f = WINDOWS["blocked_force"]
    lo, hi, why_t = WINDOWS["blocked_rise"]
    metrics = [
        Metric.relative(
            "",
            f"force at {duration:g} s",
            float(h["force [N]"][-1]),
            "N",
            rupture.value,
            tol,
            f"{rupture.source}; {why_f}",
        ),
        Metric.between(
            "",
            "time to 95 % of the largest force",
            m["time_to_95pct_force [s]"],
            "s",
            lo,
            hi,
            f"{rise.source}; {why_t}",
        ),
        Metric.info(
            "",
            "Ogden force at lambda_N on the 10 mm^2 isotropic section",
            10.0 * float(ogden_uniaxial_nominal_stress(cfg.transition.lambda_N)),
            "N",
            PUBLISHED_MODEL,
        ),
    ]
    src = [rupture.cite]
    png = plots.comparison_plot(
        ctx.path("force.png"),
        [plots.Series(h["time [s]"], h["force [N]"], "model (3D FE)", "model")],
        xlabel="time [s]",
        ylabel="force [N]",
        sources=src,
        hlines=[plots.Line(rupture.value, "rupture force F_ult (4 samples)")],
        vlines=[plots.Line(rise.value, "'about 30 s' to the maximum")],
        title="Blocked force at 0.2 A",
    )
    ctx.add_figure(
        png, plots.caption("Axial force of the strip held at its nematic length at 0.2 A.", src)
    )
    _render(ctx, res, "strip_held_3d", f"held strip, 0.2 A, t = {duration:g} s", src)
    return metrics


@case(
    "strip_uniform_heating",
    "Free strip heated uniformly far above T_NI: isotropic length and "
    "incompressible cross-section (closed form)",
    fe=True,
)
def strip_uniform_heating(ctx: CaseContext) -> list[Metric]:
    from lcefem.solvers.problems.strip import StripConfig, StripSimulation

    cfg = StripConfig(mesh=strip_mesh(ctx))
    sim = StripSimulation(cfg)
    ctx.mesh_size = sim.dims["element_size"]
    T = 200.0
    sim.model.heat.T.x.array[:] = T
    sim.model.equilibrate(where="uniform heating")
    lam_N = cfg.transition.lambda_N
    ratio = sim.stretch() * cfg.geometry.length_isotropic / sim.dims["length"]
    tol, why = WINDOWS["isotropic_length"]
    src = (
        "closed form: F = F_s(T), length ratio a = lambda_s(T)/lambda_N, area ratio 1/a "
        "(models/lce.py)"
    )
    return [
        Metric.relative(
            "", "length ratio vs 1/lambda_ref", ratio, "-", 1.0 / lam_N, tol, f"{src}; {why}"
        ),
        Metric.relative(
            "",
            "cross-section area ratio vs lambda_ref",
            sim.end_area_ratio(),
            "-",
            lam_N,
            tol,
            f"{src}; {why}",
        ),
    ]


@case(
    "strip_isotropic_tension",
    "3D FE tension test in the isotropic phase against the published Ogden fit (seed 001 Fig. 2E)",
    fe=True,
)
def strip_isotropic_tension(ctx: CaseContext) -> list[Metric]:
    from lcefem.solvers.problems.tension_specimen import isotropic_tension

    lam = np.linspace(1.05, 1.5, 4 if ctx.quick else 10)
    fe = isotropic_tension(lam)
    og = ogden_uniaxial_nominal_stress(lam)
    law = lce_uniaxial_nominal_stress(lam)
    write_csv(
        ctx.path("tension.csv"),
        {
            "stretch [-]": lam,
            "FE nominal stress [MPa]": fe,
            "Ogden nominal stress [MPa]": og,
            "law closed form [MPa]": law,
        },
    )
    tol, why = WINDOWS["tension"]
    src = [PUBLISHED_MODEL]
    fine = np.linspace(1.0, 1.6, 61)
    png = plots.comparison_plot(
        ctx.path("tension.png"),
        [
            plots.Series(
                fine, ogden_uniaxial_nominal_stress(fine), "published Ogden fit", "published model"
            ),
            plots.Series(
                fine,
                lce_uniaxial_nominal_stress(fine),
                "our law, incompressible closed form",
                "closed form",
            ),
            plots.Series(lam, fe, "3D FE block (Q2)", "model", marker="o"),
        ],
        xlabel="stretch from the isotropic length [-]",
        ylabel="nominal stress [MPa]",
        sources=src,
        secondary_y=(10.0, "force on the 10 mm^2 cast section [N]"),
        title="Isotropic-phase tension",
    )
    ctx.add_figure(
        png,
        plots.caption(
            "Uniaxial tension of the isotropic LCE: 3D FE against the published "
            "Ogden fit of Fig. 2E.",
            src,
        ),
    )
    return [
        Metric.within(
            "",
            "max |relative deviation| of FE from Ogden, stretch 1.05-1.5",
            float(np.max(np.abs(fe / og - 1.0))),
            "-",
            0.0,
            tol,
            f"{PUBLISHED_MODEL}; {why}",
        )
    ]


@case(
    "verification_heat_mms",
    "Manufactured solution of the pulled-back heat equation: observed L2 "
    "orders of P1 tetrahedra and Q2 hexahedra",
    fe=True,
)
def verification_heat_mms(ctx: CaseContext) -> list[Metric]:
    from lcefem.validation.studies.verification.manufactured import heat_error, observed_orders

    tol, why = WINDOWS["mms_heat"]
    metrics, data = [], {}
    for degree, cell, ns in ((1, "tet", (4, 8, 16)), (2, "hex", (2, 4, 8))):
        sizes = [1.0 / n for n in ns]
        errors = [heat_error(n, degree, cell) for n in ns]
        orders = observed_orders(sizes, errors)
        data[f"{cell} P{degree} h [mm]"] = sizes
        data[f"{cell} P{degree} L2 error [C mm^1.5]"] = errors
        for i, p in enumerate(orders):
            metrics.append(
                Metric.within(
                    "",
                    f"L2 order, {cell} degree {degree}, n = {ns[i]} -> {ns[i + 1]}",
                    p,
                    "-",
                    degree + 1.0,
                    tol,
                    f"theory O(h^(p+1)) (e.g. Brenner & Scott 2008); {why}",
                )
            )
    write_csv(ctx.path("errors.csv"), data)
    return metrics


@case(
    "verification_mechanics_mms",
    "Manufactured solution of the finite-strain LCE solver (spatially "
    "varying F_s): observed L2 order",
    fe=True,
)
def verification_mechanics_mms(ctx: CaseContext) -> list[Metric]:
    from lcefem.validation.studies.verification.manufactured import mechanics_error, observed_orders

    tol, why = WINDOWS["mms_mechanics"]
    metrics, data = [], {}
    for cell in ("tet",) if ctx.quick else ("tet", "hex"):
        ns = (2, 4, 8)
        sizes = [1.0 / n for n in ns]
        errors = [mechanics_error(n, cell) for n in ns]
        orders = observed_orders(sizes, errors)
        data[f"{cell} h [mm]"] = sizes
        data[f"{cell} L2 error [mm^2.5]"] = errors
        if cell == "hex":  # approaches 3 from above on uniform hexahedra
            metrics.append(
                Metric.between(
                    "",
                    f"L2 order, {cell} P2/Q2, n = 4 -> 8",
                    orders[-1],
                    "-",
                    3.0 - tol,
                    HEX_MMS_UPPER,
                    f"theory O(h^3) for quadratic elements; {why}; {HEX_MMS_WHY}",
                )
            )
        else:
            metrics.append(
                Metric.within(
                    "",
                    f"L2 order, {cell} P2/Q2, n = 4 -> 8",
                    orders[-1],
                    "-",
                    3.0,
                    tol,
                    f"theory O(h^3) for quadratic elements; {why}",
                )
            )
        metrics.append(
            Metric.info(
                "",
                f"L2 order, {cell} P2/Q2, n = 2 -> 4",
                orders[0],
                "-",
                f"{NOT_JUDGED}pre-asymptotic pair (the n = 4 -> 8 pair is judged)",
                reference=3.0,
            )
        )
    write_csv(ctx.path("errors.csv"), data)
    return metrics
