"""Bar-and-hinge cases of seed 001's passive ribbon and composite beam (no finite elements).

- ``ribbon_buckling_bh``: the 36 x 7 x 0.127 mm fixed-fixed specimen (Fig. 2G): critical load of the
  bar-and-hinge model against the measured 0.18 N and against the Euler load of the chain's own
  bending stiffness (closed form); the Euler loads of the specimen with the datasheet E, with and
  without the published model's factor 5.5; the post-buckling force against the elastica; the LCE
  strain under the model's post-buckling force.
- ``beam_curvature_map_bh``: kappa(lambda_T, lambda_B) of the composite beam over [1.05, 1.33]^2 (5
  x 5; 3 x 3 quick) against Eq. 2 (seed 001), table and a figure like Fig. 3B.
- ``beam_segment_count_bh``: the middle curvature at (1.33, 1.05) against the number of segments,
  the evidence for the 4 segments of :class:`~lcefem.meshes.composite_beam.CompositeBeamGeometry`.

(The statement "a 0.18 N ribbon tension gives at most 5 % LCE strain" is the case
``ribbon_load_strain`` of validation/cases/empirical.py.)
"""

from __future__ import annotations

import math

import numpy as np

from lcefem.meshes.composite_beam import CompositeBeamGeometry
from lcefem.meshes.kapton_ribbon import KaptonBarHingeMesh, KaptonSpecimenGeometry
from lcefem.models import bar_hinge as law
from lcefem.models import bar_hinge_materials as bhm
from lcefem.models import buckling, hyperelastic
from lcefem.models.empirical import Eq2, eq2_curvature
from lcefem.solvers.problems import composite_beam_bh as beam_bh
from lcefem.solvers.problems import kapton_specimen_bh as kapton_bh
from lcefem.validation.app import plots
from lcefem.validation.cases import NOT_JUDGED, CaseContext, Metric, case, reference_data, write_csv
from lcefem.validation.cases.reference_data import reference

PUBLISHED = bhm.PUBLISHED
BH = "bar-and-hinge model (lcefem.solvers.bar_hinge)"

#: Tolerance of the bar-and-hinge critical load against the measured 0.18 N: the published hinge
#: stiffness was fitted to this test (seed 001: "We fit the constitutive behaviors ... using the
#: experimental data"), so the model should reproduce it to within the error of its hinge chain:
#: 5 % (discrete chain vs continuum, see CHAIN_TOLERANCE) plus the 3 % softer chain of 3.27 mm
#: panels than of the 3.36 mm hinge spacing the stiffness formula refers to.
MEASURED_TOLERANCE = 0.10
#: The discrete hinge chain buckles below the continuum Euler load of its own bending stiffness by
#: an error of first order in panel length / length: 5.3 %, 3.4 %, 1.8 % at 11, 16, 32 panels
#: (tests/validation/test_beam_bar_hinge.py).
CHAIN_TOLERANCE = 0.06
#: Tolerance of the map against Eq. 2: Eq. 2 is an estimate whose factor eta = 0.57 was fitted to
#: the experiments (its geometric value for strips on concentric arcs 1/2 apart is 0.5: a 14 %
#: correction), so a model may differ from it by at least that; 25 % of the largest |kappa| of Eq. 2
#: on the grid.
MAP_TOLERANCE = 0.25
#: Tolerance of one point of a model against Eq. 2: the fitted eta = 0.57 differs from its geometric
#: value 0.5 (strips on concentric arcs) by 14 %, the size of the correction the fit carries; the
#: seed states no scatter of the measured curvatures, so this assumption is the reference's
#: uncertainty.
EQ2_POINT_TOLERANCE = 0.14
#: The chosen number of segments must give the middle curvature within 2 % of the longest beam.
SEGMENT_TOLERANCE = 0.02


def _grid(quick: bool) -> np.ndarray:
    return np.linspace(1.05, 1.33, 3 if quick else 5)


@case(
    "ribbon_buckling_bh",
    "Passive Kapton ribbon, fixed-fixed buckling (seed 001 Fig. 2G): "
    "bar-and-hinge critical load vs 0.18 N measured and the Euler loads; post-buckling vs elastica",
    fe=False,
)
def ribbon_buckling_bh(ctx: CaseContext) -> list[Metric]:
    name = ctx.case or "ribbon_buckling_bh"
    measured = reference("ribbon.buckling_load")
    plateau_to = reference("ribbon.plateau_compression")
    strain_bound = reference("tension.strain_at_ribbon_load")
    spec, mesh, mat = KaptonSpecimenGeometry(), KaptonBarHingeMesh(), bhm.BarHingeMaterials()
    kap = mat.kapton
    ctx.mesh_size = spec.length / mesh.panels
    ei = kap.youngs_modulus * spec.second_moment
    k = kap.hinge_stiffness(spec.thickness)
    ei_chain = law.n5b8_ribbon_bending_stiffness(k, ctx.mesh_size, spec.width)
    euler = buckling.euler_fixed_fixed(ei, spec.length)
    euler_factor = buckling.euler_fixed_fixed(kap.bending_factor * ei, spec.length)
    euler_chain = buckling.euler_fixed_fixed(ei_chain, spec.length)

    p_cr, _ = kapton_bh.critical_load(spec, mesh, mat)
    no_factor = bhm.BarHingeMaterials(kapton=bhm.KaptonBarHinge(bending_factor=1.0))
    p_cr_1, _ = kapton_bh.critical_load(spec, mesh, no_factor)
    fine = KaptonBarHingeMesh(panels=16)
    p_cr_16, _ = kapton_bh.critical_load(spec, fine, mat)
    sol = kapton_bh.solve_specimen_buckling(plateau_to.value, spec, mesh, mat)
    c, f = sol.compression, sol.force
    ratio_end = float(f[-1] / p_cr)
    elastica_end = buckling.elastica_force_ratio(float(c[-1]))
    section = CompositeBeamGeometry().strip_section
    # The largest compression the surface sees: segments shortened to lambda_min/lambda_N with the
    # smallest lambda of seed 001's shapes (1.05), i.e. 25 %.
    lam_min = reference("surface.dome.lambda_sim")
    worst = 1.0 - min(lam_min.value) / mat.lce.lambda_N
    f_worst = float(np.interp(worst, c, f))
    strain_worst = hyperelastic.lce_strain_under_force(f_worst, section)
    strain_end = hyperelastic.lce_strain_under_force(float(f[-1]), section)
    l_eff = 2.0 * math.pi * math.sqrt(ei / measured.value)
    e_eff = measured.value * spec.length**2 / (4.0 * math.pi**2 * spec.second_moment)

    c_el = np.linspace(0.0, float(c[-1]), len(c))
    write_csv(
        ctx.path("ribbon_buckling_bh.csv"),
        {
            "compression [-]": c,
            "end shortening [mm]": c * spec.length,
            "force [N]": f,
            "elastica force [N]": p_cr * np.array([buckling.elastica_force_ratio(x) for x in c]),
        },
    )
    png = plots.comparison_plot(
        ctx.path("ribbon_buckling_bh.png"),
        [
            plots.Series(100 * c, f, f"bar-and-hinge ({mesh.panels} panels, published k)", "model"),
            plots.Series(
                100 * c_el,
                p_cr * np.array([buckling.elastica_force_ratio(x) for x in c_el]),
                "elastica x P_cr (closed form)",
                "closed form",
            ),
        ],
        xlabel="compression (end shortening / length) [%]",
        ylabel="compressive force [N]",
        hlines=[
            plots.Line(
                measured.value,
                f"measured critical load {measured.value:g} N (9 samples)",
                "experiment",
            ),
            plots.Line(euler, f"Euler 4 pi^2 E I/L^2 = {euler:.3f} N", "closed form"),
            plots.Line(euler_chain, f"Euler of the chain's EI = {euler_chain:.3f} N", "reference"),
        ],
        title="Fixed-fixed Kapton ribbon 36 x 7 x 0.127 mm",
        sources=[measured.cite, PUBLISHED, "elastica: Timoshenko & Gere 1961, Sec. 2.7"],
    )
    ctx.add_figure(
        png,
        plots.caption(
            "Compressive force vs end shortening of the fixed-fixed Kapton ribbon in the "
            "bar-and-hinge "
            f"model ({mesh.panels} N5B8 panels, hinge stiffness of the published model) against "
            "the "
            "measured critical load, the Euler load of the specimen with the datasheet modulus, "
            "the "
            "Euler load of the hinge chain's own bending stiffness and the elastica.",
            [measured.cite, PUBLISHED],
        ),
    )
    src_bh = f"{BH}, {mesh.panels} panels; {PUBLISHED}"
    return [
        Metric.relative(
            name,
            "critical load vs measured",
            p_cr,
            "N",
            measured.value,
            MEASURED_TOLERANCE,
            f"{measured.source}; {src_bh}; tolerance: "
            "MEASURED_TOLERANCE in validation/cases/beam_bar_hinge.py",
        ),
        Metric.relative(
            name,
            "critical load vs Euler load of the chain's bending stiffness",
            p_cr,
            "N",
            euler_chain,
            CHAIN_TOLERANCE,
            "closed form EI_eff = k W H D^3/(2 H^3 + D^3) "
            "(models/bar_hinge.n5b8_ribbon_bending_stiffness); tolerance: "
            "CHAIN_TOLERANCE (discrete chain, first order in W/L)",
        ),
        Metric.info(
            name,
            "Euler load 4 pi^2 E I/L^2 (datasheet E, L = 36 mm)",
            euler,
            "N",
            NOT_JUDGED
            + "what-if that sizes the gap to the measured 0.18 N, not a prediction; "
            + "DuPont Kapton HN datasheet E = 2.5 GPa; seed 001 specimen 36 x 7 x 0.127 mm",
            reference=measured.value,
        ),
        Metric.info(
            name,
            f"Euler load with the published factor ({kap.bending_factor:g} E I)",
            euler_factor,
            "N",
            NOT_JUDGED + "closed form of the published hinge factor, for scale; " + PUBLISHED,
            reference=measured.value,
        ),
        Metric.info(
            name,
            "critical load without the factor 5.5 (k = E t^3/(12 s))",
            p_cr_1,
            "N",
            NOT_JUDGED
            + "what-if that sizes the gap to the measured 0.18 N, not a prediction; "
            + f"{BH}, {mesh.panels} panels",
            reference=measured.value,
        ),
        Metric.info(
            name,
            "critical load with 16 panels of 2.25 mm (the beam's flank panels)",
            p_cr_16,
            "N",
            f"{NOT_JUDGED}what-if (another panel length); {BH}; the published k is per unit "
            "length, so the chain's "
            "EI "
            "scales with the panel length",
            reference=measured.value,
        ),
        Metric.info(
            name,
            "free length for which 4 pi^2 E I/L^2 = 0.18 N",
            l_eff,
            "mm",
            NOT_JUDGED
            + "what-if that sizes the gap to the measured 0.18 N, not a prediction; "
            + "datasheet E; seed 001 measured 0.18 N",
            reference=spec.length,
        ),
        Metric.info(
            name,
            "modulus for which 4 pi^2 E I/L^2 = 0.18 N at L = 36 mm",
            e_eff,
            "MPa",
            NOT_JUDGED
            + "what-if that sizes the gap to the measured 0.18 N, not a prediction; "
            + "seed 001 measured 0.18 N",
            reference=kap.youngs_modulus,
        ),
        Metric.info(
            name,
            "force at 50 % compression / critical load",
            ratio_end,
            "-",
            f"{NOT_JUDGED}model vs closed form with no agreed band (the chain is extensible, the "
            "elastica "
            f"is not); {BH}; reference: inextensible elastica (Timoshenko & Gere 1961); seed 001: "
            f"'{plateau_to.quote}'",
            reference=elastica_end,
        ),
        Metric.between(
            name,
            f"LCE strain under the model's ribbon force at {100 * worst:.0f} % "
            "compression (the largest in the surface)",
            strain_worst,
            "-",
            0.0,
            strain_bound.value,
            f"{strain_bound.source}; compression 1 - 1.05/lambda_N ({lam_min.cite}); Ogden "
            f"law on the 10 mm^2 cast section ({PUBLISHED})",
        ),
        Metric.info(
            name,
            "LCE strain under the model's ribbon force at 50 % compression",
            strain_end,
            "-",
            f"{NOT_JUDGED}the seed's bound holds up to the surface's largest compression (judged "
            f"above), not at 50 %; {strain_bound.source}; Ogden law on the 10 mm^2 cast section",
            reference=strain_bound.value,
        ),
    ]


@case(
    "beam_curvature_map_bh",
    "Composite beam curvature kappa(lambda_T, lambda_B) over [1.05, 1.33]^2: "
    "bar-and-hinge model vs Eq. 2 (seed 001, Fig. 3B)",
    fe=False,
)
def beam_curvature_map_bh(ctx: CaseContext) -> list[Metric]:
    name = ctx.case or "beam_curvature_map_bh"
    eta = reference("eq2.eta")
    law2 = Eq2()
    geometry = CompositeBeamGeometry()
    ctx.mesh_size = (geometry.segment_length - geometry.crown_bond_length) / 10.0  # flank panel
    lam = _grid(ctx.quick)
    n = lam.size
    kappa = np.zeros((n, n))
    iterations = 0
    for i, lt in enumerate(lam):
        for j, lb in enumerate(lam):
            sol = beam_bh.solve_beam(float(lt), float(lb), geometry)
            kappa[i, j] = sol.curvature
            iterations += sum(sol.path.newton_iterations)
    lt, lb = np.meshgrid(lam, lam, indexing="ij")
    k_eq2 = eq2_curvature(lt, lb, law2)
    diff = kappa - k_eq2
    scale = float(np.max(np.abs(k_eq2)))
    off = ~np.isclose(lt, lb)
    write_csv(
        ctx.path("beam_curvature_map_bh.csv"),
        {
            "lambda_top [-]": lt.ravel(),
            "lambda_bottom [-]": lb.ravel(),
            "bar-and-hinge curvature [1/mm]": kappa.ravel(),
            "Eq. 2 curvature [1/mm]": k_eq2.ravel(),
            "difference [1/mm]": diff.ravel(),
        },
    )
    src_eq2 = f"{eta.source}; {reference_data.eq2_inputs_note()}"
    fine = np.linspace(lam[0], lam[-1], 29)
    surface = eq2_curvature(
        *np.meshgrid(fine, fine, indexing="xy"), law2
    )  # [j, i] at (fine[i], fine[j])
    bh_points = [plots.MapPoints(lt.ravel(), lb.ravel(), kappa.ravel(), "bar-and-hinge", "model")]
    sources = [
        eta.cite,
        PUBLISHED,
        "lcefem bar-and-hinge model (validation/cases/beam_bar_hinge.py)",
    ]
    for style, suffix in (("surface", ""), ("map", "_top_view")):
        png = plots.map_plot(
            ctx.path(f"beam_curvature_map_bh{suffix}.png"),
            fine,
            fine,
            surface,
            xlabel="lambda_T [-]",
            ylabel="lambda_B [-]",
            zlabel="kappa [1/mm]",
            style=style,
            points=bh_points,
            title="Composite beam curvature: Eq. 2 and bar-and-hinge (dots)",
            sources=sources,
        )
        ctx.add_figure(
            png,
            plots.caption(
                "Curvature of a 4-segment composite beam against the relative lengths of its top "
                "and "
                "bottom strips: Eq. 2 of seed 001 ("
                + ("surface" if style == "surface" else "colour map")
                + ", "
                + reference_data.eq2_parameters()
                + ") and the bar-and-hinge model "
                "(dots; circle through the middle junction centres, positive when the beam bends "
                "towards "
                "its bottom strips). Compare seed 001 Fig. 3B.",
                [eta.cite, PUBLISHED],
            ),
        )
    png2 = plots.map_plot(
        ctx.path("beam_curvature_map_bh_difference.png"),
        lam,
        lam,
        diff.T,
        xlabel="lambda_T [-]",
        ylabel="lambda_B [-]",
        zlabel="kappa_BH - kappa_Eq2 [1/mm]",
        title="Bar-and-hinge minus Eq. 2",
        sources=[eta.cite, PUBLISHED],
    )
    ctx.add_figure(
        png2,
        plots.caption(
            "Difference of the bar-and-hinge curvature from Eq. 2 over the grid.", [eta.cite]
        ),
    )
    i_t, i_b = n - 1, 0  # (1.33, 1.05): the dome of seed 001 Fig. 4C
    sign_ok = float(np.mean(np.sign(kappa[off]) == np.sign(k_eq2[off])))
    return [
        Metric.within(
            name,
            "max |kappa_BH - kappa_Eq2| over the grid",
            float(np.max(np.abs(diff))),
            "1/mm",
            0.0,
            MAP_TOLERANCE * scale,
            f"{src_eq2}; tolerance: MAP_TOLERANCE x max|kappa_Eq2| "
            "(validation/cases/beam_bar_hinge.py)",
        ),
        Metric.info(
            name,
            "RMS (kappa_BH - kappa_Eq2) over the grid",
            float(np.sqrt(np.mean(diff**2))),
            "1/mm",
            src_eq2,
        ),
        Metric.within(
            name,
            "fraction of off-diagonal points where kappa_BH has the sign of Eq. 2",
            sign_ok,
            "-",
            1.0,
            0.0,
            src_eq2,
        ),
        Metric.within(
            name,
            "max |kappa_BH| for equal strips (lambda_T = lambda_B)",
            float(np.max(np.abs(kappa[~off]))),
            "1/mm",
            0.0,
            0.05 * scale,
            "Eq. 2 gives 0 for equal strips; tolerance 5 % of max|kappa_Eq2| (the model's "
            "top and bottom strips are attached differently, so it is not exactly symmetric)",
        ),
        Metric.relative(
            name,
            "kappa_BH at (1.33, 1.05)",
            float(kappa[i_t, i_b]),
            "1/mm",
            float(k_eq2[i_t, i_b]),
            EQ2_POINT_TOLERANCE,
            f"{BH}; reference: Eq. 2; tolerance EQ2_POINT_TOLERANCE (14 %: the fitted eta = "
            "0.57 against its geometric 0.5)",
        ),
        Metric.info(name, "Newton iterations over the grid", float(iterations), "-", BH),
    ]


@case(
    "beam_segment_count_bh",
    "Composite beam: middle curvature at (1.33, 1.05) vs the number of "
    "segments (bar-and-hinge), justifying the 4-segment beam",
    fe=False,
)
def beam_segment_count_bh(ctx: CaseContext) -> list[Metric]:
    name = ctx.case or "beam_segment_count_bh"
    counts = [2, 4, 6] if ctx.quick else [2, 4, 6, 8]
    chosen = CompositeBeamGeometry().segments
    kappa = [
        beam_bh.solve_beam(1.33, 1.05, CompositeBeamGeometry(segments=n)).curvature for n in counts
    ]
    ctx.mesh_size = 2.3
    write_csv(
        ctx.path("beam_segment_count_bh.csv"),
        {"segments [-]": counts, "middle curvature [1/mm]": kappa},
    )
    png = plots.comparison_plot(
        ctx.path("beam_segment_count_bh.png"),
        [
            plots.Series(
                counts,
                kappa,
                "bar-and-hinge, (lambda_T, lambda_B) = (1.33, 1.05)",
                "model",
                marker="o",
            )
        ],
        xlabel="number of segments N [-]",
        ylabel="middle curvature [1/mm]",
        vlines=[plots.Line(chosen, f"chosen N = {chosen}", "model")],
        title="Middle curvature vs beam length",
        sources=[BH],
    )
    ctx.add_figure(
        png,
        plots.caption(
            "Curvature through the middle stations of a composite beam of N segments (free ends) "
            "at "
            "(lambda_T, lambda_B) = (1.33, 1.05): the middle is not dominated by the ends from N "
            "= 4 on.",
            [BH],
        ),
    )
    longest = kappa[-1]
    at_chosen = kappa[counts.index(chosen)]
    return [
        Metric.relative(
            name,
            f"middle curvature with N = {chosen} vs N = {counts[-1]}",
            at_chosen,
            "1/mm",
            longest,
            SEGMENT_TOLERANCE,
            f"{BH}; tolerance: SEGMENT_TOLERANCE (validation/cases/beam_bar_hinge.py)",
        ),
        *(
            Metric.info(name, f"middle curvature, N = {n}", kk, "1/mm", BH)
            for n, kk in zip(counts, kappa)
        ),
    ]
