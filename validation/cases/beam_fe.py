"""3D finite-element cases of seed 001's passive ribbon and composite beam (FEniCSx).

- ``ribbon_buckling_fe``: the 36 x 7 x 0.127 mm fixed-fixed Kapton specimen (Fig. 2G) as a
  neo-Hookean solid with datasheet E and nu: critical load of the perfect specimen (linearised
  buckling, SLEPc) against the Euler loads of the beam (E I) and of the plate strip (E I/(1 - nu^2))
  that bound it, against the measured 0.18 N and the bar-and-hinge model; its change under mesh
  refinement; the post-buckling force (first-mode imperfection) against the elastica.
- ``beam_curvature_map_fe``: kappa(lambda_T, lambda_B) of the 4-segment beam over [1.05, 1.33]^2
  (5 x 5; the 2 x 2 corners with --quick), FE against Eq. 2 and the bar-and-hinge model: table of
  differences, a figure like seed 001 Fig. 3B, the three curvatures at (1.33, 1.05), and the
  strip-ribbon contact force over the grid.
- ``beam_curvature_fe`` (convergence): the curvature at (1.33, 1.05) ramped from the as-built state
  at one mesh level (``lcefem converge beam_curvature_fe``); when beam_curvature_map_fe has swept
  that point at the same level earlier in the process, its equilibrium is reused (confirmed by
  Newton) instead of ramping again.

Resolution: ``ctx.level`` when given, else QUICK_LEVEL with --quick and DEFAULT_LEVEL otherwise
(in-plane element size 3 mm/(level + 1); the convergence study gives the error of each level).
The map runs at MAP_LEVEL (0) at both levels, 5 x 5 points at the full level: the convergence study
of beam_curvature_fe (README, 'Mesh convergence') puts level 0 within 1.1 % of the extrapolated
curvature at (1.33, 1.05) (0.025643 against 0.025361 1/mm), against tolerances of 14 % and more on
the map's judged rows, and the 5 x 5 map at level 1 (about 1000 Newton iterations at 0.5 s each)
never finished within the time of the whole validation. The map's full level samples the grid
more densely than --quick (2 x 2) and checks one swept point against a ramp from the as-built state.
"""

from __future__ import annotations

import math
import time

import numpy as np

from lcefem.meshes.kapton_ribbon import KaptonBarHingeMesh, KaptonSpecimenGeometry
from lcefem.models import buckling
from lcefem.models.empirical import Eq2, eq2_curvature
from lcefem.solvers.problems import composite_beam_bh as beam_bh
from lcefem.solvers.problems import kapton_specimen_bh as kapton_bh
from lcefem.validation.app import plots
from lcefem.validation.cases import NOT_JUDGED, CaseContext, Metric, case, reference_data, write_csv
from lcefem.validation.cases.beam_bar_hinge import (
    EQ2_POINT_TOLERANCE,
    MAP_TOLERANCE,
    MEASURED_TOLERANCE,
)
from lcefem.validation.cases.reference_data import reference

QUICK_LEVEL = 0
DEFAULT_LEVEL = 1
MAP_LEVEL = 0  #: mesh level of the curvature map at both levels (module docstring)
#: Post-buckling path of ribbon_buckling_fe at both levels: compression steps of 0.05 after 6
#: geometric onset steps (16 states) instead of the run's default 0.02 after 12 (35 states). The
#: force-compression curve is a smooth plateau; at level 1 the rows it feeds moved by < 3e-5
#: relative (force at 10 % 0.1058988 -> 0.105896 N, at 50 % 0.1380659 -> 0.138066 N, ratio 1.44996
#: unchanged) while the path's CPU time fell from about 110 s to 77 s.
CASE_PATH_STEP, CASE_PATH_ONSET_STEPS = 0.05, 6
QUICK_PATH_STEP, QUICK_PATH_ONSET_STEPS = 0.1, 4  #: --quick: 10 states (CI)
FE = (
    "3D FE model (lcefem.solvers.problems.composite_beam: Q2 hexahedra, neo-Hookean Kapton, "
    "LCE W(F U(a)^-1))"
)
BH = "bar-and-hinge model (lcefem.solvers.bar_hinge)"
#: The FE critical load must change by less than this under one refinement of its mesh (the
#: element choice converges; issue 4 asks to show it).
RIBBON_MESH_TOLERANCE = 0.01
#: The FE beam's top and bottom strips are attached differently (lap pads on the crowns above,
#: under the junctions below), so equal strips need not give exactly zero curvature; like the
#: bar-and-hinge case, allow 5 % of max |kappa_Eq2| on the grid.
EQUAL_STRIPS_TOLERANCE = 0.05
#: Sanity bound on |kappa_FE/kappa_Eq2 - 1| off the diagonal: Eq. 2 is an estimate (circular strips,
#: inextensible ribbon, eta fitted to experiments), the FE a first-principles model with datasheet
#: Kapton; they should agree in magnitude, not to a few per cent (the bar-and-hinge model, fitted to
#: the buckling test, differs from Eq. 2 by about 20 %).
RATIO_BOUND = 0.5


def _level(ctx: CaseContext) -> int:
    return ctx.level if ctx.level is not None else (QUICK_LEVEL if ctx.quick else DEFAULT_LEVEL)


@case(
    "ribbon_buckling_fe",
    "Passive Kapton ribbon, fixed-fixed buckling (seed 001 Fig. 2G) in 3D FE: "
    "critical load vs the Euler loads, 0.18 N measured and bar-and-hinge; post-buckling force",
    fe=True,
)
def ribbon_buckling_fe(ctx: CaseContext) -> list[Metric]:
    from lcefem.meshes.kapton_ribbon import KaptonFEMesh
    from lcefem.solvers.problems import composite_beam as beam_fe
    from lcefem.solvers.problems import kapton_specimen

    name = ctx.case or "ribbon_buckling_fe"
    measured = reference("ribbon.buckling_load")
    plateau_to = reference("ribbon.plateau_compression")
    spec = KaptonSpecimenGeometry()
    materials = beam_fe.FEMaterials()
    kapton = materials.kapton
    level = 0 if ctx.quick else (ctx.level if ctx.level is not None else 1)
    mesh = KaptonFEMesh(level=level)
    ctx.mesh_size = mesh.element_size()
    model = kapton_specimen.KaptonSpecimenFE(spec, mesh, kapton)
    path = (
        kapton_specimen.KaptonSpecimenFEPath(
            step=QUICK_PATH_STEP, onset_steps=QUICK_PATH_ONSET_STEPS
        )
        if ctx.quick
        else kapton_specimen.KaptonSpecimenFEPath(
            step=CASE_PATH_STEP, onset_steps=CASE_PATH_ONSET_STEPS
        )
    )
    critical = model.critical_load()
    # The finer mesh linearises at this mesh's critical shortening: one secant step instead of two
    # from the Euler estimate, the same load to 3e-7 (levels 1 and 2 from level 0), 35-40 % cheaper.
    finer = kapton_specimen.KaptonSpecimenFE(
        spec, KaptonFEMesh(level=level + 1), kapton
    ).critical_load(secant_steps=1, start=critical.shortening)
    model.add_imperfection(critical.mode, path.imperfection * spec.length)
    rows: list[tuple[float, float, float]] = [(0.0, 0.0, 0.0)]
    model.follow(
        model.compression_schedule(critical.shortening / spec.length, plateau_to.value, path),
        on_step=lambda c, its: rows.append((c, model.force(), model.mid_deflection())),
    )
    c, f, w = (np.array(v) for v in zip(*rows))
    closed = buckling.specimen_closed_forms(
        spec, kapton.youngs_modulus, kapton.poisson_ratio, measured.value
    )
    euler = closed["Euler, E I (datasheet E) [N]"]
    plate = closed["Euler, plate strip E I/(1 - nu^2) [N]"]
    bh_cr, _ = kapton_bh.critical_load(spec, KaptonBarHingeMesh())
    bh = kapton_bh.solve_specimen_buckling(plateau_to.value, spec, KaptonBarHingeMesh())
    elastica = np.array([buckling.elastica_force_ratio(x) for x in c])
    write_csv(
        ctx.path("ribbon_buckling_fe.csv"),
        {
            "compression [-]": c,
            "end shortening [mm]": c * spec.length,
            "force [N]": f,
            "mid-span deflection [mm]": w,
            "elastica force [N]": critical.force * elastica,
        },
    )
    sources = [
        measured.cite,
        "DuPont Kapton HN datasheet (E = 2.5 GPa, nu = 0.34)",
        "Euler: 4 pi^2 EI/L^2, fixed-fixed",
        "elastica: Timoshenko & Gere 1961, Sec. 2.7",
    ]
    png = plots.comparison_plot(
        ctx.path("ribbon_buckling_fe.png"),
        [
            plots.Series(100 * c, f, f"3D FE (Q2, {model.ndofs} DOFs, half model)", "model"),
            plots.Series(
                100 * bh.compression,
                bh.force,
                "bar-and-hinge (11 panels, published k)",
                "published model",
            ),
            plots.Series(100 * c, critical.force * elastica, "elastica x P_cr (FE)", "closed form"),
        ],
        xlabel="compression (end shortening / length) [%]",
        ylabel="compressive force [N]",
        hlines=[
            plots.Line(
                measured.value,
                f"measured critical load {measured.value:g} N (9 samples)",
                "experiment",
            ),
            plots.Line(euler, f"Euler E I = {euler:.4f} N", "closed form"),
            plots.Line(plate, f"Euler E I/(1-nu^2) = {plate:.4f} N", "reference"),
        ],
        title="Fixed-fixed Kapton ribbon 36 x 7 x 0.127 mm: 3D FE",
        sources=sources,
    )
    ctx.add_figure(
        png,
        plots.caption(
            "Compressive force vs end shortening of the fixed-fixed Kapton ribbon: 3D FE "
            "(datasheet "
            "modulus, first buckling mode as imperfection, amplitude 1e-3 L), the bar-and-hinge "
            "model "
            "with the published hinge stiffness (fitted to the test), the elastica scaled by the "
            "FE "
            "critical load, the measured critical load and the Euler loads of the beam and plate "
            "strip.",
            sources,
        ),
    )
    ratio_end = float(f[-1] / critical.force)
    src_fe = f"{FE}; half model, in-plane element {ctx.mesh_size:g} mm"
    WI_SRC = NOT_JUDGED + "what-if that sizes the gap to the measured 0.18 N, not a prediction; "
    # The post-buckling force follows the critical load, which is judged (and fails) above; judging
    # the plateau again would count one disagreement three times.
    PLATEAU = NOT_JUDGED + "the plateau follows the critical load judged above; "
    return [
        Metric.between(
            name,
            "FE critical load within the Euler loads of beam and plate strip",
            critical.force,
            "N",
            euler,
            plate,
            "clamped ends suppress the anticlastic curvature near them: the critical load "
            "lies between 4 pi^2 E I/L^2 (free anticlastic bending) and 4 pi^2 E I/((1 - "
            "nu^2) L^2) (none); datasheet E, nu",
        ),
        Metric.relative(
            name,
            "FE critical load, one mesh refinement apart",
            critical.force,
            "N",
            finer.force,
            RIBBON_MESH_TOLERANCE,
            f"{FE}; levels {level} and {level + 1}; tolerance RIBBON_MESH_TOLERANCE",
        ),
        Metric.relative(
            name,
            "FE critical load vs measured",
            critical.force,
            "N",
            measured.value,
            MEASURED_TOLERANCE,
            f"{measured.source}; {src_fe}; tolerance MEASURED_TOLERANCE "
            "(10 %, as the bar-and-hinge case: the seed states no scatter of its nine specimens)",
        ),
        Metric.info(
            name,
            "bar-and-hinge critical load (11 panels, published k)",
            bh_cr,
            "N",
            f"{NOT_JUDGED}judged in ribbon_buckling_bh; {BH}",
            reference=measured.value,
        ),
        Metric.info(
            name,
            "Euler load 4 pi^2 E I/L^2 (datasheet E, L = 36 mm)",
            euler,
            "N",
            NOT_JUDGED
            + "what-if that sizes the gap to the measured 0.18 N, not a prediction; "
            + "DuPont Kapton HN datasheet E = 2.5 GPa",
            reference=measured.value,
        ),
        Metric.info(
            name,
            "free length for which 4 pi^2 E I/L^2 = 0.18 N",
            closed["free length giving the measured load [mm]"],
            "mm",
            NOT_JUDGED
            + "what-if that sizes the gap to the measured 0.18 N, not a prediction; "
            + "datasheet E; seed 001 measured 0.18 N",
            reference=spec.length,
        ),
        Metric.info(
            name,
            "modulus for which 4 pi^2 E I/L^2 = 0.18 N at L = 36 mm",
            closed["modulus giving the measured load [MPa]"],
            "MPa",
            WI_SRC + "seed 001 measured 0.18 N",
            reference=kapton.youngs_modulus,
        ),
        Metric.info(
            name,
            "modulus for which the FE critical load is 0.18 N",
            kapton.youngs_modulus * measured.value / critical.force,
            "MPa",
            WI_SRC + f"{src_fe}; the linearised buckling load is proportional to E",
            reference=kapton.youngs_modulus,
        ),
        Metric.info(
            name,
            "free length for which the FE critical load is 0.18 N (scaling 1/L^2)",
            spec.length * math.sqrt(critical.force / measured.value),
            "mm",
            WI_SRC + src_fe,
            reference=spec.length,
        ),
        Metric.info(
            name,
            "FE force at 10 % compression",
            float(np.interp(0.1, c, f)),
            "N",
            PLATEAU + src_fe,
            reference=measured.value,
        ),
        Metric.info(
            name,
            "FE force at 50 % compression",
            float(f[-1]),
            "N",
            PLATEAU + src_fe,
            reference=measured.value,
        ),
        Metric.info(
            name,
            "FE force at 50 % compression / critical load",
            ratio_end,
            "-",
            f"{NOT_JUDGED}model vs closed form with no agreed band; {src_fe}; reference: "
            "inextensible elastica (Timoshenko & Gere 1961); the "
            "plate "
            f"strip stiffens towards 1/(1 - nu^2) as its curvature grows; seed 001: "
            f"'{plateau_to.quote}'",
            reference=buckling.elastica_force_ratio(float(c[-1])),
        ),
    ]


def _direct(level: int, lambda_top: float, lambda_bottom: float):
    """The FE beam ramped from the as-built state to (lambda_T, lambda_B) at a mesh level."""
    from lcefem.meshes.composite_beam_fe import BeamFEMesh
    from lcefem.solvers.problems import composite_beam as beam_fe

    model = beam_fe.BeamFE(mesh=BeamFEMesh(level=level))
    started = time.perf_counter()
    model.ramp(lambda_top, lambda_bottom)
    return model, time.perf_counter() - started


#: Equilibria of the default FE beam solved by beam_curvature_map_fe in this process, keyed by
#: (mesh level, lambda_T, lambda_B): displacement arrays [mm]. beam_curvature_fe at the same level
#: and point starts from one instead of ramping (a shared run between cases: the equilibrium does
#: not depend on the path, which the map's full level checks; Newton confirms it in 0-1 iterations).
_EQUILIBRIA: dict[tuple[int, float, float], np.ndarray] = {}


def _key(level: int, lambda_top: float, lambda_bottom: float) -> tuple[int, float, float]:
    return level, round(float(lambda_top), 12), round(float(lambda_bottom), 12)


def _keep_equilibrium(level: int):
    def keep(lambda_top: float, lambda_bottom: float, model) -> None:
        _EQUILIBRIA[_key(level, lambda_top, lambda_bottom)] = model.problem.save()

    return keep


def _equilibrium(level: int, lambda_top: float, lambda_bottom: float):
    """(model, wall time [s], Newton iterations, reused): the beam at (lambda_T, lambda_B), from a
    kept equilibrium confirmed by Newton when there is one, else :func:`_direct`."""
    from lcefem.meshes.composite_beam_fe import BeamFEMesh
    from lcefem.solvers.problems import composite_beam as beam_fe

    kept = _EQUILIBRIA.get(_key(level, lambda_top, lambda_bottom))
    if kept is not None:
        started = time.perf_counter()
        model = beam_fe.BeamFE(mesh=BeamFEMesh(level=level))
        model.set_drives({"top_strips": lambda_top, "bottom_strips": lambda_bottom})
        model.set_lambdas(lambda_top, lambda_bottom)
        model.problem.restore(kept)
        ok, its, _ = model.problem.solve()
        if ok:
            return model, time.perf_counter() - started, its, True
    model, wall = _direct(level, lambda_top, lambda_bottom)
    return model, wall, model.last_follower.iterations, False


def _render(ctx: CaseContext, model, name: str, title: str, sources) -> None:
    from lcefem.validation.studies.beam.beam_plots import render_fe_beam

    png = render_fe_beam(ctx.path(f"{name}.png"), model, title)
    ctx.add_figure(
        png,
        plots.caption(
            f"{title}: the deformed 3D FE beam (whole beam drawn from the quarter model), side "
            "view, "
            "coloured by the as-built height.",
            sources,
        ),
    )


@case(
    "beam_curvature_map_fe",
    "Composite beam curvature kappa(lambda_T, lambda_B) over [1.05, 1.33]^2: "
    "3D FE vs Eq. 2 vs bar-and-hinge (seed 001, Fig. 3B)",
    fe=True,
)
def beam_curvature_map_fe(ctx: CaseContext) -> list[Metric]:
    from lcefem.meshes.composite_beam_fe import BeamFEMesh
    from lcefem.solvers.problems import composite_beam as beam_fe

    name = ctx.case or "beam_curvature_map_fe"
    eta = reference("eq2.eta")
    law2 = Eq2()
    level = ctx.level if ctx.level is not None else MAP_LEVEL
    mesh = BeamFEMesh(level=level)
    ctx.mesh_size = mesh.element_size()
    lam = np.linspace(1.05, 1.33, 2 if ctx.quick else 5)
    n = lam.size
    kappa, stats, last = beam_fe.curvature_map_fe(lam, mesh=mesh, on_state=_keep_equilibrium(level))
    bh = np.array([[beam_bh.solve_beam(float(a), float(b)).curvature for b in lam] for a in lam])
    lt, lb = np.meshgrid(lam, lam, indexing="ij")
    k_eq2 = eq2_curvature(lt, lb, law2)
    d_eq2, d_bh = kappa - k_eq2, kappa - bh
    scale = float(np.max(np.abs(k_eq2)))
    off = ~np.isclose(lt, lb)
    write_csv(
        ctx.path("beam_curvature_map_fe.csv"),
        {
            "lambda_top [-]": lt.ravel(),
            "lambda_bottom [-]": lb.ravel(),
            "FE curvature [1/mm]": kappa.ravel(),
            "Eq. 2 curvature [1/mm]": k_eq2.ravel(),
            "bar-and-hinge curvature [1/mm]": bh.ravel(),
            "FE - Eq. 2 [1/mm]": d_eq2.ravel(),
            "FE - bar-and-hinge [1/mm]": d_bh.ravel(),
        },
    )
    src_eq2 = f"{eta.source}; {reference_data.eq2_inputs_note()}"
    src_fe = f"{FE}; mesh level {level} ({mesh.element_size():g} mm), swept through the grid"
    sources = [eta.cite, FE, BH]
    fine = np.linspace(lam[0], lam[-1], 29)
    surface = eq2_curvature(*np.meshgrid(fine, fine, indexing="xy"), law2)
    points = [
        plots.MapPoints(lt.ravel(), lb.ravel(), kappa.ravel(), "3D FE", "model"),
        plots.MapPoints(lt.ravel(), lb.ravel(), bh.ravel(), "bar-and-hinge", "published model"),
    ]
    for style, suffix in (("surface", ""), ("map", "_top_view")):
        png = plots.map_plot(
            ctx.path(f"beam_curvature_map_fe{suffix}.png"),
            fine,
            fine,
            surface,
            xlabel="lambda_T [-]",
            ylabel="lambda_B [-]",
            zlabel="kappa [1/mm]",
            style=style,
            points=points,
            title="Composite beam curvature: Eq. 2 (surface), 3D FE and bar-and-hinge",
            sources=sources,
        )
        ctx.add_figure(
            png,
            plots.caption(
                "Curvature of the 4-segment composite beam against the relative lengths of its "
                "top and "
                f"bottom strips: Eq. 2 of seed 001 ({reference_data.eq2_parameters()}), "
                "the 3D FE model and the bar-and-hinge model (circle through the middle junction "
                "centres, "
                "positive when the beam bends towards its bottom strips). Compare seed 001 Fig. "
                "3B.",
                sources,
            ),
        )
    for diff, label, suffix in (
        (d_eq2, "kappa_FE - kappa_Eq2", "eq2"),
        (d_bh, "kappa_FE - kappa_BH", "bh"),
    ):
        png = plots.map_plot(
            ctx.path(f"beam_curvature_map_fe_minus_{suffix}.png"),
            lam,
            lam,
            diff.T,
            xlabel="lambda_T [-]",
            ylabel="lambda_B [-]",
            zlabel=f"{label} [1/mm]",
            title=label.replace("kappa_", ""),
            sources=sources,
        )
        ctx.add_figure(png, plots.caption(f"{label} over the grid.", sources))
    _render(
        ctx,
        last,
        "beam_fe_last_state",
        f"3D FE beam at (lambda_T, lambda_B) = ({last.lambda_top:.3g}, {last.lambda_bottom:.3g})",
        sources,
    )
    i_t, i_b = n - 1, 0  # (1.33, 1.05)
    sign_ok = float(np.mean(np.sign(kappa[off]) == np.sign(k_eq2[off])))
    ratio = np.abs(kappa[off] / k_eq2[off] - 1.0)
    ordered = _ordered_fraction(kappa)
    metrics = [
        Metric.within(
            name,
            "max |kappa_FE - kappa_Eq2| over the grid",
            float(np.max(np.abs(d_eq2))),
            "1/mm",
            0.0,
            MAP_TOLERANCE * scale,
            f"{src_eq2}; tolerance MAP_TOLERANCE x max|kappa_Eq2| "
            "(as the bar-and-hinge map: eta = 0.57 fitted against its geometric 0.5)",
        ),
        Metric.within(
            name,
            "largest |kappa_FE/kappa_Eq2 - 1| off the diagonal",
            float(np.max(ratio)),
            "-",
            0.0,
            RATIO_BOUND,
            f"{src_eq2}; RATIO_BOUND: the same magnitude as the fitted "
            "estimate (Eq. 2 assumes strips on concentric circular arcs and the buckled height "
            "of an inextensible ribbon)",
        ),
        Metric.within(
            name,
            "fraction of grid neighbours ordered as Eq. 2 (kappa up with lambda_T, down "
            "with lambda_B)",
            ordered,
            "-",
            1.0,
            0.0,
            src_eq2,
        ),
        Metric.info(
            name,
            "RMS (kappa_FE - kappa_Eq2) over the grid",
            float(np.sqrt(np.mean(d_eq2**2))),
            "1/mm",
            src_eq2,
        ),
        Metric.info(
            name,
            "max |kappa_FE - kappa_BH| over the grid",
            float(np.max(np.abs(d_bh))),
            "1/mm",
            f"{src_fe}; {BH}",
        ),
        Metric.info(
            name,
            "RMS (kappa_FE - kappa_BH) over the grid",
            float(np.sqrt(np.mean(d_bh**2))),
            "1/mm",
            f"{src_fe}; {BH}",
        ),
        Metric.within(
            name,
            "fraction of off-diagonal points where kappa_FE has the sign of Eq. 2",
            sign_ok,
            "-",
            1.0,
            0.0,
            src_eq2,
        ),
        Metric.within(
            name,
            "max |kappa_FE| for equal strips (lambda_T = lambda_B)",
            float(np.max(np.abs(kappa[~off]))),
            "1/mm",
            0.0,
            EQUAL_STRIPS_TOLERANCE * scale,
            "Eq. 2 gives 0 for equal strips; tolerance EQUAL_STRIPS_TOLERANCE x max|kappa_Eq2| "
            "(top and bottom strips are bonded differently)",
        ),
        Metric.relative(
            name,
            "kappa_FE at (1.33, 1.05)",
            float(kappa[i_t, i_b]),
            "1/mm",
            float(k_eq2[i_t, i_b]),
            EQ2_POINT_TOLERANCE,
            f"{src_fe}; reference Eq. 2; "
            "tolerance EQ2_POINT_TOLERANCE (14 %: the fitted eta = 0.57 against its geometric 0.5)",
        ),
        Metric.info(name, "kappa_Eq2 at (1.33, 1.05)", float(k_eq2[i_t, i_b]), "1/mm", src_eq2),
        Metric.info(
            name,
            "kappa_BH at (1.33, 1.05)",
            float(bh[i_t, i_b]),
            "1/mm",
            f"{NOT_JUDGED}judged in beam_curvature_map_bh; {BH}",
            reference=float(k_eq2[i_t, i_b]),
        ),
        Metric.relative(
            name,
            "kappa_FE at (1.05, 1.33)",
            float(kappa[0, n - 1]),
            "1/mm",
            float(k_eq2[0, n - 1]),
            EQ2_POINT_TOLERANCE,
            f"{src_fe}; reference Eq. 2; "
            "tolerance EQ2_POINT_TOLERANCE (14 %: the fitted eta = 0.57 against its geometric 0.5)",
        ),
        Metric.info(
            name,
            "largest strip-ribbon contact force over the grid",
            stats["max_contact_force [N]"],
            "N",
            f"{src_fe}; penalty contact (lcefem.solvers.contact)",
        ),
        Metric.info(
            name, "smallest strip-ribbon gap over the grid", stats["min_gap [mm]"], "mm", src_fe
        ),
        Metric.info(
            name, "FE Newton iterations over the grid", float(stats["iterations"]), "-", src_fe
        ),
        Metric.info(name, "FE wall time over the grid", stats["wall_time [s]"], "s", src_fe),
    ]
    if not ctx.quick:  # the sweep's value against a ramp from the as-built state
        direct, _ = _direct(level, float(lam[i_t]), float(lam[i_b]))
        metrics.append(
            Metric.relative(
                name,
                "kappa_FE at (1.33, 1.05): grid sweep vs ramp from as built",
                float(kappa[i_t, i_b]),
                "1/mm",
                direct.curvature(),
                0.01,
                f"{src_fe}; the equilibrium does not depend on the path (1 %)",
            )
        )
    return metrics


@case(
    "beam_curvature_fe",
    "Composite beam curvature at (lambda_T, lambda_B) = (1.33, 1.05) in 3D FE at "
    "one mesh level (for lcefem converge); Eq. 2 and bar-and-hinge alongside",
    fe=True,
    convergence=True,
)
def beam_curvature_fe(ctx: CaseContext) -> list[Metric]:
    from lcefem.meshes.composite_beam_fe import BeamFEMesh

    name = ctx.case or "beam_curvature_fe"
    eta = reference("eq2.eta")
    level = _level(ctx)
    ctx.mesh_size = BeamFEMesh(level=level).element_size()
    lt, lb = 1.33, 1.05  # seed 001 Fig. 4C (dome)
    model, wall, iterations, reused = _equilibrium(level, lt, lb)
    kappa = model.curvature()
    k_eq2 = float(eq2_curvature(lt, lb, Eq2()))
    k_bh = beam_bh.solve_beam(lt, lb).curvature
    stations = model.stations.points(model.u)
    write_csv(
        ctx.path("stations.csv"),
        {"x [mm]": stations[:, 0], "y [mm]": stations[:, 1], "z [mm]": stations[:, 2]},
    )
    src = f"{FE}; mesh level {level} ({ctx.mesh_size:g} mm), {model.ndofs} DOFs" + (
        "; equilibrium of beam_curvature_map_fe's sweep in this run, confirmed by Newton"
        if reused
        else ""
    )
    _render(ctx, model, "beam_fe_1p33_1p05", "3D FE beam at (1.33, 1.05)", [FE])
    write_csv(
        ctx.path("solve.csv"),
        {
            "DOFs [-]": [model.ndofs],
            "Newton iterations [-]": [iterations],
            "ramp wall time [s]": [wall],
            "from the map's equilibrium [0/1]": [int(reused)],
        },
    )
    return [
        Metric.within(
            name,
            "kappa_FE at (1.33, 1.05) vs Eq. 2",
            kappa,
            "1/mm",
            k_eq2,
            EQ2_POINT_TOLERANCE * abs(k_eq2),
            f"{eta.source}; {reference_data.eq2_inputs_note()}; "
            "tolerance EQ2_POINT_TOLERANCE x |kappa_Eq2| (14 %: the fitted eta = 0.57 against "
            "its geometric 0.5)",
        ),
        Metric.info(
            name,
            "kappa_BH at (1.33, 1.05)",
            k_bh,
            "1/mm",
            f"{NOT_JUDGED}judged in beam_curvature_map_bh; {BH}",
            reference=k_eq2,
        ),
        Metric.info(
            name,
            "height of the middle junction above the end stations' chord",
            float(_sagitta(stations)),
            "mm",
            src,
        ),
    ]


def _ordered_fraction(kappa: np.ndarray) -> float:
    """Fraction of neighbouring grid pairs with kappa increasing in lambda_T (first index) and
    decreasing in lambda_B (second index), as Eq. 2."""
    up = np.diff(kappa, axis=0) > 0
    down = np.diff(kappa, axis=1) < 0
    return float((up.sum() + down.sum()) / (up.size + down.size))


def _sagitta(stations: np.ndarray) -> float:
    """Distance [mm] of the middle station from the chord through the first and last station."""
    a, b = stations[0], stations[-1]
    m = stations[len(stations) // 2]
    t = b - a
    d = m - a
    return float(np.linalg.norm(d - t * np.dot(d, t) / np.dot(t, t)))
