"""Cross-validation of the two gridshell models (issue 30): the bar-and-hinge (BH) against the 3D FE
on identical supports and lambdas, the four Fig. 4 shapes, with the FE results stored in
validation/data (running the FE gridshell takes minutes to hours).

- ``gridshell_bh_vs_fe``: the BH gridshell in the configuration that matches the FE model's physics
  (:data:`AS_FE`: the published supports and glue squares, strip-ribbon contact as the FE's penalty
  contact, the constant-volume bar law as the FE's incompressible LCE) against the stored FE centre
  curvatures, both measures. Judged rows "<shape>: circle kappa_<x|y> BH vs FE": within 10 % of the
  FE or 0.002 1/mm, the larger (the issue's target). At the full level, controlled changes of the
  BH (one at a time) on every shape whose difference exceeds 10 %: the hinge factor doubled, the
  contracting squares, the contact removed, the published bar law, the middle ribbons' rollers:
  informative rows that show which of them moves the BH towards the FE. The quick level runs table,
  saddle and cylinder (not the dome, minutes) and the beam map's 2 x 2 corners.
- The beam map: the 4-segment composite beam's curvature over [1.05, 1.33]^2 (5 x 5) against the
  stored FE map (level 0), ours judged, the FE's configuration and controlled changes informative.
- The strip element (``mesh.strip_element = "beam"``: the strips' centroid offset and own bending)
  and the plate's torsion of the Kapton panels (``kapton.twist = "plate"``) with the FE-calibrated
  parameters of validation/data/bar_hinge_calibration.json (``lcefem calibrate bar-hinge``): judged
  rows "<shape>: circle kappa_<x|y> BH vs FE (strip element, FE-calibrated)" on the four shapes (the
  dome included: with the strip element it takes seconds) and the beam map (the FE beam's
  configuration: its top strips contract over the junctions; quick: the 4 corners); at the full
  level the offset alone, the bending alone and both, with the N5B8 panels' and with the plate's
  torsion, at the published factors, informative (docs/gridshell_calibration.md).

- The layouts (issue 47): the FE-calibrated BH against the 3D FE on the gmsh mesh of a refined
  (5 x 5, quarter, rollers) and a non-orthogonal (rhombic 60 deg, whole, clamp) layout, a tenth of
  the dome's ramp (:func:`_layouts`, stored FE: :data:`FE_LAYOUTS`); judged rows "<layout> dome
  (...): circle kappa_<x|y> BH vs FE", at both levels (the BH takes seconds). At the full ramp
  (:data:`FE_LAYOUTS_FULL`, level 0) a layout with the FE at mesh level 1
  (:data:`FE_LAYOUTS_FULL_FINE`, with the control: the published 3 x 3 under the clamp) is judged
  against level 1, its level-0 rows informative ("... (FE mesh level 0)").

FE references (:data:`FE_REFERENCE`): gridshell_fe_fig4_quarter_level0.json (quarter model, mesh
level 0, 26,904 Q2 DOFs; the published supports) and, for the dome, the mesh-converged level 2 of
gridshell_fe_dome_full_ramp_from_flat_levels.json (levels 0-2: circle -0.02217, -0.01952, -0.01933
1/mm, observed order 3.6, GCI of the finest level 0.0037 1/mm): the level-0 circle of the dome is 15
% off its extrapolated value, which is the stated discretisation error of the other three shapes' FE
values (level 0 only).
"""

from __future__ import annotations

import dataclasses
import json
import math
import time

from lcefem.meshes.composite_beam import BeamBarHingeMesh
from lcefem.models import bar_hinge_materials as law
from lcefem.models.errors import ConvergenceError
from lcefem.solvers.problems import gridshell_bh as problem_bh
from lcefem.validation.cases import NOT_JUDGED, CaseContext, Metric, case, write_csv
from lcefem.validation.cases.reference_data import DATA_DIR
from lcefem.validation.studies.gridshell.calibrate import (
    ABS_TOL,
    AS_FE,
    REL_TOL,
    fe_reference,
    shape_setup,
    tolerance,
)

BH = "bar-and-hinge gridshell (lcefem.solvers.problems.gridshell_bh)"
#: Controlled changes of the BH (label -> (departures, kapton bending factor multiplier, support)).
CHANGES = {
    "hinge factor x2": (AS_FE, 2.0, None),
    "contracting squares": ((*AS_FE, "contracting_squares"), 1.0, None),
    "no contact (published)": (("volume_law",), 1.0, None),
    "published bar law A f P": (("contact",), 1.0, None),
    "middle ribbons' rollers": ((*AS_FE, "middle_rollers"), 1.0, None),
}


def solve_bh(shape: str, departures=AS_FE, bending=1.0, support=None):
    """The BH gridshell with the Fig. 4 lambdas of ``shape`` in the published configuration plus
    ``departures``, the Kapton hinge factor times ``bending``; returns (curvatures or None, seconds,
    why)."""
    base = law.BarHingeMaterials()
    kapton = dataclasses.replace(base.kapton, bending_factor=base.kapton.bending_factor * bending)
    setup = shape_setup(shape, dataclasses.replace(base, kapton=kapton), "bar", departures, support)
    t0 = time.perf_counter()
    try:
        sol = problem_bh.solve_gridshell(setup)
    except ConvergenceError as exc:
        return None, time.perf_counter() - t0, str(exc)
    return sol.curvatures, time.perf_counter() - t0, ""


#: Beam-map variants of the BH (label -> (mesh, materials)): ours (beam_curvature_map_bh's), and the
#: configuration of the FE beam (its bond pads are passive: the top strip does not contract over
#: the junction, i.e. glue squares), plus controlled changes of the latter.
def _beam_variants() -> dict:
    base = law.BarHingeMaterials()
    glue = BeamBarHingeMesh(top_junction="glue")
    return {
        "ours (contracting squares)": (BeamBarHingeMesh(), base),
        "as FE (glue squares)": (glue, base),
        "as FE, published bar law A f P": (
            glue,
            dataclasses.replace(base, lce=law.LCEStripBars(force_law="published")),
        ),
        "as FE, hinge factor x2": (
            glue,
            dataclasses.replace(base, kapton=law.KaptonBarHinge(bending_factor=11.0)),
        ),
        "as FE, strip-panel springs at the strip's bending stiffness": (
            glue,
            dataclasses.replace(
                base, strip_contact=law.StripContactSprings(stiffness=STRIP_BENDING_SPRING)
            ),
        ),
    }


#: Stiffness per unit hinge length [N mm/(rad mm)] of a strip end clamped against rotation by the
#: strip's own bending: 4 E I/(L w) with E I = 0.53 MPa x 5 x 2^3/12 mm^4 = 1.77 N mm^2 (the 5 x 2
#: mm strip at 3 mu_0 of the published Ogden law), L = 30 mm, w = 7 mm (the hinge's axis: the ribbon
#: width): 0.034 (a controlled change, not a calibrated value).
STRIP_BENDING_SPRING = 4.0 * 0.53 * 5.0 * 2.0**3 / 12.0 / (30.0 * 7.0)


def _beam_map(ctx: CaseContext, name: str) -> list[Metric]:
    """The 4-segment composite beam's curvature map, BH vs the stored FE map (level 0)."""
    import numpy as np

    from lcefem.solvers.problems import composite_beam_bh as beam_bh

    data = json.loads((DATA_DIR / "beam_fe_curvature_map_level0.json").read_text())
    lt, lb = np.array(data["lambda_top [-]"]), np.array(data["lambda_bottom [-]"])
    kfe = np.array(data["FE curvature [1/mm]"])
    pick = np.ones(lt.size, dtype=bool)
    if ctx.quick:  # the 2 x 2 corners
        pick = np.isin(lt, (lt.min(), lt.max())) & np.isin(lb, (lb.min(), lb.max()))
    src = (
        "3D FE composite beam, mesh level 0 (validation/data/beam_fe_curvature_map_level0.json: "
        "level 0 within 1.1 % of the extrapolated curvature at (1.33, 1.05)); " + BH
    )
    out = []
    variants = _beam_variants()
    if ctx.quick:
        variants = dict(list(variants.items())[:2])
    for label, (mesh, mats) in variants.items():
        kbh = np.array(
            [
                beam_bh.solve_beam(float(a), float(b), mesh=mesh, materials=mats).curvature
                for a, b in zip(lt[pick], lb[pick])
            ]
        )
        ref = kfe[pick]
        excess = np.abs(kbh - ref) / np.maximum(REL_TOL * np.abs(ref), ABS_TOL)
        worst = int(np.argmax(excess))
        where = (
            f"worst at (lambda_T, lambda_B) = ({lt[pick][worst]:.2f}, {lb[pick][worst]:.2f}): BH "
            f"{kbh[worst]:.4f}, FE {ref[worst]:.4f} 1/mm"
        )
        metric = (
            f"beam map: largest |kappa_BH - kappa_FE| in units of the tolerance, BH vs FE ({label})"
        )
        if label.startswith("ours"):
            out.append(
                Metric.within(
                    name,
                    metric,
                    float(excess.max()),
                    "-",
                    0.0,
                    1.0,
                    src + "; tolerance per point: 10 % of the FE or 0.002 1/mm; " + where,
                )
            )
        else:
            out.append(
                Metric.info(
                    name,
                    metric,
                    float(excess.max()),
                    "-",
                    NOT_JUDGED + "a configuration / controlled change; " + src + "; " + where,
                    reference=1.0,
                )
            )
        out.append(
            Metric.info(
                name,
                f"beam map: RMS (kappa_BH - kappa_FE) ({label})",
                float(np.sqrt(np.mean((kbh - ref) ** 2))),
                "1/mm",
                src,
            )
        )
    return out


@case(
    "gridshell_bh_vs_fe",
    "Robotic surface: bar-and-hinge vs 3D FE on identical supports and lambdas "
    "(Fig. 4 shapes), with controlled changes of the BH where they differ by > 10 %",
    fe=False,
)
def gridshell_bh_vs_fe(ctx: CaseContext) -> list[Metric]:
    name = ctx.case or "gridshell_bh_vs_fe"
    fe = fe_reference()
    metrics: list[Metric] = []
    rows = {
        k: [] for k in ("shape", "variant", "circle_x", "circle_y", "quad_kx", "quad_ky", "seconds")
    }
    # The quick level leaves out the dome: its snap-through (a dense eigensolve of ~2500 DOFs per
    # escape) takes 1-10 min on the shared machine (docs/gridshell_configuration.md, speed).
    shapes = (
        ("table", "saddle", "cylinder") if ctx.quick else ("table", "dome", "saddle", "cylinder")
    )
    for shape in shapes:
        ref = fe[shape]
        k, secs, why = solve_bh(shape)
        src = f"{ref['source']}; {BH}, published supports and glue squares + contact + volume law"
        if k is None:
            metrics.append(Metric(name, f"{shape}: BH converged", 0.0, "-", 1.0, 0.0, False, why))
            continue
        comps = ("x",) if shape in ("table", "dome") else ("x", "y")  # x = y by symmetry
        far = False
        for c in comps:
            key = f"circle_{c}"
            m = Metric.within(
                name,
                f"{shape}: circle kappa_{c} BH vs FE",
                k[key],
                "1/mm",
                ref[key],
                tolerance(ref[key]),
                src + "; tolerance: 10 % or 0.002 1/mm (issue 30)",
            )
            metrics.append(m)
            far |= not m.passed
            q = f"quad_k{c}"
            metrics.append(
                Metric.info(
                    name,
                    f"{shape}: quadratic-fit kappa_{c} BH vs FE",
                    k[q],
                    "1/mm",
                    NOT_JUDGED + "the Fig. 5 measure, informative here; " + src,
                    reference=ref[q],
                )
            )
        for key, v in zip(
            rows, [shape, "as FE", k["circle_x"], k["circle_y"], k["quad_kx"], k["quad_ky"], secs]
        ):
            rows[key].append(v)
        if ctx.quick or not far:
            continue
        for label, (deps, bending, support) in CHANGES.items():
            kc, secs_c, why_c = solve_bh(shape, deps, bending, support)
            vals = [
                kc[c] if kc else math.nan for c in ("circle_x", "circle_y", "quad_kx", "quad_ky")
            ]
            for key, v in zip(rows, [shape, label, *vals, secs_c]):
                rows[key].append(v)
            for c in comps:
                key = f"circle_{c}"
                metrics.append(
                    Metric.info(
                        name,
                        f"{shape}: circle kappa_{c} BH vs FE, controlled change: {label}",
                        kc[key] if kc else math.nan,
                        "1/mm",
                        NOT_JUDGED
                        + "a controlled change that shows the cause of the difference; "
                        + (why_c or src),
                        reference=ref[key],
                    )
                )
    metrics += _beam_map(ctx, name)
    metrics += _strip_element(ctx, name, fe)
    metrics += _layouts(ctx, name)
    write_csv(
        ctx.path("gridshell_bh_vs_fe.csv"),
        {
            "row [-]": list(range(len(rows["shape"]))),
            "circle kappa_x [1/mm]": rows["circle_x"],
            "circle kappa_y [1/mm]": rows["circle_y"],
            "quad kappa_x [1/mm]": rows["quad_kx"],
            "quad kappa_y [1/mm]": rows["quad_ky"],
            "wall time [s]": rows["seconds"],
        },
    )
    (ctx.path("gridshell_bh_vs_fe_rows.txt")).write_text(
        "\n".join(f"{i}: {s} / {v}" for i, (s, v) in enumerate(zip(rows["shape"], rows["variant"])))
        + "\n"
    )
    return metrics


#: The strip element's and the panels' torsion's controlled changes (label -> (mesh.strip_element,
#: kapton.twist)), published factors. The dome with bars and the plate's torsion is left out: its
#: ramp does not converge (stopped after 207 s CPU, docs/gridshell_calibration.md).
STRIP_CHANGES = {
    "strip centroid offset alone": ("offset", "n5b8"),
    "strip bending alone": ("bending", "n5b8"),
    "strip element (offset + bending)": ("beam", "n5b8"),
    "plate torsion alone (bars)": ("bar", "plate"),
    "strip centroid offset + plate torsion": ("offset", "plate"),
    "strip element + plate torsion": ("beam", "plate"),
}
SKIP = {("dome", "plate torsion alone (bars)")}


def _strip_element(ctx: CaseContext, name: str, fe: dict) -> list[Metric]:
    """The BH with the strip element (mesh.strip_element = 'beam') and the FE-calibrated parameters
    of validation/data/bar_hinge_calibration.json (``lcefem calibrate bar-hinge``), judged against
    the FE on the four shapes and the beam map; at the full level, the offset alone, the bending
    alone and both at the published factors (informative, controlled changes)."""
    import numpy as np

    from lcefem.validation.studies.gridshell import calibrate as cal

    record = cal.load()
    out: list[Metric] = []
    if record is None:
        return [
            Metric(
                name,
                "calibrated set: parameter file present",
                0.0,
                "-",
                1.0,
                0.0,
                False,
                "validation/data/bar_hinge_calibration.json missing: run lcefem calibrate "
                "bar-hinge",
            )
        ]
    mats = cal.calibrated_materials(record)
    params = ", ".join(f"{k} = {v:.4g}" for k, v in record["parameters"].items())
    fixed = ", ".join(f"{k} = '{v}'" for k, v in record.get("fixed", {}).items())
    src = (
        f"{BH} with the strip element (mesh.strip_element = 'beam'), {fixed}, FE-calibrated: "
        f"{params} "
        "(validation/data/bar_hinge_calibration.json, lcefem calibrate bar-hinge); published "
        "supports "
        "and glue squares + contact + volume law"
    )
    for shape in ("table", "dome", "saddle", "cylinder"):
        ref = fe[shape]
        k = cal.solve_shape(shape, mats)
        if k is None:
            out.append(
                Metric(
                    name,
                    f"{shape}: BH converged (strip element, FE-calibrated)",
                    0.0,
                    "-",
                    1.0,
                    0.0,
                    False,
                    src,
                )
            )
            continue
        for c in cal.components(shape):
            out.append(
                Metric.within(
                    name,
                    f"{shape}: circle kappa_{c[-1]} BH vs FE (strip element, FE-calibrated)",
                    k[c],
                    "1/mm",
                    ref[c],
                    tolerance(ref[c]),
                    ref["source"] + "; " + src + "; tolerance: 10 % or 0.002 1/mm",
                )
            )
        if ctx.quick:
            continue
        for label, (element, twist) in STRIP_CHANGES.items():
            if (shape, label) in SKIP:
                continue
            kc = cal.solve_shape(shape, cal.fe_equivalent(twist=twist), element)
            for c in cal.components(shape):
                out.append(
                    Metric.info(
                        name,
                        f"{shape}: circle kappa_{c[-1]} BH vs FE, controlled change: {label}",
                        kc[c] if kc else math.nan,
                        "1/mm",
                        NOT_JUDGED + "published hinge factor and strip E I; " + BH,
                        reference=ref[c],
                    )
                )
    targets = cal.fe_targets((), "corners" if ctx.quick else "all")
    lt, lb, kfe = targets["beam"]
    fe_src = (
        "3D FE composite beam, mesh level 0 (validation/data/beam_fe_curvature_map_level0.json; "
        "its top strips contract over the junctions: BH mesh.top_junction = 'lce')"
    )
    variants = {"strip element, FE-calibrated": ("beam", mats)}
    if not ctx.quick:
        variants.update(
            {
                f"{label}, published factors": (el, cal.fe_equivalent(twist=tw))
                for label, (el, tw) in STRIP_CHANGES.items()
            }
        )
    for label, (element, m) in variants.items():
        kbh = cal.solve_beam_map(lt, lb, m, element)
        excess = np.abs(kbh - kfe) / np.maximum(REL_TOL * np.abs(kfe), ABS_TOL)
        w = int(np.nanargmax(excess))
        where = (
            f"worst at (lambda_T, lambda_B) = ({lt[w]:.2f}, {lb[w]:.2f}): BH {kbh[w]:.4f}, FE "
            f"{kfe[w]:.4f} 1/mm"
        )
        metric = (
            f"beam map: largest |kappa_BH - kappa_FE| in units of the tolerance, BH vs FE ({label})"
        )
        if label.endswith("FE-calibrated"):
            out.append(
                Metric.within(
                    name,
                    metric,
                    float(np.nanmax(excess)),
                    "-",
                    0.0,
                    1.0,
                    fe_src + "; " + src + "; tolerance per point: 10 % of the FE or "
                    "0.002 1/mm; " + where,
                )
            )
        else:
            out.append(
                Metric.info(
                    name,
                    metric,
                    float(np.nanmax(excess)),
                    "-",
                    NOT_JUDGED + "a controlled change; " + fe_src + "; " + where,
                    reference=1.0,
                )
            )
    return out


#: FE references of the layouts (issue 47): the 3D FE gridshell on the gmsh mesh of a refined and a
#: non-orthogonal layout, mesh level 0, a fraction of the Fig. 4 dome's ramp
#: (FE_LAYOUTS["fraction"]), and the full ramp (FE_LAYOUTS_FULL,
#: benchmarks/gridshell_fe_layouts_full_ramp.py).
FE_LAYOUTS = DATA_DIR / "gridshell_fe_layouts_level0.json"
FE_LAYOUTS_FULL = DATA_DIR / "gridshell_fe_layouts_full_ramp_level0.json"
#: The full ramp at mesh level 1 (benchmarks/gridshell_fe_layouts_full_ramp.py --level 1): where a
#: layout has it, its rows are judged against it and its level-0 rows are informative. The level-0
#: FE over-bends the dome at the full ramp: the published 3 x 3 under the rollers -0.02217 against
#: -0.01952 (level 1) and -0.01933 (level 2, the level the set was calibrated on), under the clamp
#: -0.021672 against -0.019580 (level 1, 2026-12-08; docs/notes/fe_bodies_log.md).
FE_LAYOUTS_FULL_FINE = DATA_DIR / "gridshell_fe_layouts_full_ramp_level1.json"
#: Full-ramp layouts whose bar-and-hinge run is left to the full level: the 5 x 5 under the rollers
#: stalled (t = 0.83 of the ramp) on the floating raised top square of its centre junction (its top
#: strips slack, tangent eigenvalues 5e-8 N/mm), which the Newton's settle step now passes; beyond
#: t = 0.8 it leaves its x-y symmetry and its fold costs minutes (332 s CPU to t = 1 with the first
#: version of the step; docs/layouts/index.md, speed; validation/data/case_costs.toml).
FULL_LEVEL_ONLY = {"5x5"}


def _layouts(ctx: CaseContext, name: str) -> list[Metric]:
    """Judged rows "<layout> <shape> (<support>, <f> of the ramp): circle kappa_<x|y> BH vs FE"
    ("circle kappa, <more|less> bent family, BH vs FE" when the FE bends x and y alike, so that a
    row never depends on which family a BH bifurcation picks by round-off): the
    FE-calibrated bar-and-hinge (the model set of ``lcefem run gridshell``, its materials for the
    layout) against the stored FE of each layout of :data:`FE_LAYOUTS`, both from the as-built
    state to the same fraction f of the Fig. 4 lambdas. Tolerance: 10 % of the FE (issue 30's
    target) or 0.002 1/mm x f, the floor of the full shapes scaled with the ramp (a tenth of the
    ramp bends the surface about a tenth as much). The full ramp (:data:`FE_LAYOUTS_FULL`, f = 1):
    rows "<layout> <shape> (<support>, full ramp): ...", 10 % or 0.002 1/mm (the Fig. 4 rows'
    tolerance); the layouts of :data:`FULL_LEVEL_ONLY` at the full level only. A full-ramp row
    whose layout, shape and support :data:`FE_LAYOUTS_FULL_FINE` (mesh level 1) holds is judged
    against level 1, with the same name; its level-0 rows stay, informative, named "... BH vs FE
    (FE mesh level 0)"; the fine file's other rows (the control: the published 3 x 3 under the
    clamp) are judged as the layouts'."""

    def key(r: dict) -> tuple:
        return r["layout"], r["shape"], r["support"]

    def load(path) -> dict | None:
        if not path.exists():
            return None
        ref = json.loads(path.read_text())
        ref["rows"] = [
            r
            for r in ref["rows"]
            if not (ctx.quick and ref["fraction"] == 1.0 and r["layout"] in FULL_LEVEL_ONLY)
        ]
        return ref

    fine = load(FE_LAYOUTS_FULL_FINE)
    finer = {key(r) for r in fine["rows"]} if fine else set()
    coarse = {}
    out = []
    for ref in (load(FE_LAYOUTS), load(FE_LAYOUTS_FULL)):
        if ref is None:
            continue
        rows = []
        for r in ref["rows"]:
            if ref["fraction"] == 1.0 and key(r) in finer:
                coarse[key(r)] = (ref, r)
            else:
                rows.append(r)
        out += _layout_rows(name, ref, rows)
    if fine:
        out += _layout_rows(name, fine, fine["rows"], coarse)
    return out


#: Relative difference of the FE's circle kappa_x and kappa_y below which a stored layout row
#: counts as x <-> y symmetric (measured: at most 3.4e-12 on the stored dome rows; the FE keeps the
#: diagonal mirror to round-off).
FE_MIRROR_RTOL = 1e-9


def _mirror_symmetric(row: dict) -> bool:
    """Whether the stored FE row bends x and y alike (a dome drive on a layout symmetric under
    x <-> y)."""
    x, y = row["circle_x"], row["circle_y"]
    return abs(x - y) <= FE_MIRROR_RTOL * max(abs(x), abs(y))


def _layout_rows(
    name: str, ref: dict, rows: list[dict], coarse: dict | None = None
) -> list[Metric]:
    """The rows of :func:`_layouts` for the stored FE ``ref`` (one fraction of the ramp and mesh
    level), judged; ``coarse`` ((layout, shape, support) -> (the level-0 file, its row)): the same
    BH against the level-0 FE as well, informative."""
    from lcefem.meshes.gridshell_layout import NAMED_LAYOUTS
    from lcefem.models.bar_hinge_materials import PUBLISHED_LAMBDA_N
    from lcefem.solvers.problems.gridshell_bh import GridshellBH, GridshellBHConfig
    from lcefem.validation.studies.gridshell import calibrate as cal
    from lcefem.validation.studies.gridshell import gridshell_bh as gs

    f = float(ref["fraction"])
    ms = cal.model_set("fe-calibrated")
    out = []
    for row in rows:
        layout = NAMED_LAYOUTS[row["layout"]]
        lambdas = {
            k: PUBLISHED_LAMBDA_N + f * (v - PUBLISHED_LAMBDA_N)
            for k, v in gs.SHAPES[row["shape"]]["lambdas"].items()
        }
        ramp = "full ramp" if f == 1.0 else f"{f:g} of the ramp"
        label = f"{row['layout']} {row['shape']} ({row['support']}, {ramp})"
        bh_src = (
            f"{BH}, FE-calibrated model set (validation.calibrate.model_set, materials_for the "
            "layout)"
        )
        src = f"{ref['source']}; {bh_src}; tolerance: 10 % or 0.002 1/mm" + (
            "" if f == 1.0 else f" x {f:g}"
        )
        try:
            p = GridshellBH(
                ms.structure(layout),
                GridshellBHConfig(materials=ms.materials_for(layout), support=row["support"]),
            )
            p.set_drives(lambdas)
            p.advance()
        except ConvergenceError as exc:
            out.append(Metric(name, f"{label}: BH converged", 0.0, "-", 1.0, 0.0, False, str(exc)))
            continue
        k = p.observables()
        bh = {c: k[f"circle kappa_{c} [1/mm]"] for c in ("x", "y")}
        families = {c: c for c in ("x", "y")}
        if _mirror_symmetric(row):
            # The FE keeps x = y, and the drive and the layout are symmetric under x <-> y: a BH
            # that leaves that symmetry (the rhombic dome with skewed free panels bifurcated at
            # t = 0.670; with the rectangular ones it keeps x = y,
            # docs/layouts/rhombic.md) bends one family more, and which one is set by round-off.
            # So the rows name the more and the less bent family, not x and y.
            more, less = sorted(("x", "y"), key=lambda c: -abs(bh[c]))
            families = {more: "more bent family", less: "less bent family"}
        for c in ("x", "y"):
            fe_k = row[f"circle_{c}"]
            what = f"kappa_{c}" if families[c] == c else f"kappa, {families[c]},"
            out.append(
                Metric.within(
                    name,
                    f"{label}: circle {what} BH vs FE",
                    bh[c],
                    "1/mm",
                    fe_k,
                    max(REL_TOL * abs(fe_k), ABS_TOL * f),
                    src,
                )
            )
            out.append(
                Metric.info(
                    name,
                    f"{label}: quadratic-fit kappa_{c} BH vs FE",
                    k.get(f"quad kappa_{c} [1/mm]", math.nan),
                    "1/mm",
                    NOT_JUDGED + "the Fig. 5 measure, informative here; " + src,
                    reference=row[f"quad_{c}"],
                )
            )
        key = (row["layout"], row["shape"], row["support"])
        if coarse and key in coarse:
            ref0, row0 = coarse[key]
            src0 = (
                f"{NOT_JUDGED}the level-0 FE, which over-bends the published dome at the full "
                f"ramp by 11-14 % (the judged row uses level {ref.get('mesh level')}); "
                f"{ref0['source']}; {bh_src}"
            )
            for c in ("x", "y"):
                what = f"kappa_{c}" if families[c] == c else f"kappa, {families[c]},"
                out.append(
                    Metric.info(
                        name,
                        f"{label}: circle {what} BH vs FE (FE mesh level 0)",
                        bh[c],
                        "1/mm",
                        src0,
                        reference=row0[f"circle_{c}"],
                    )
                )
                out.append(
                    Metric.info(
                        name,
                        f"{label}: quadratic-fit kappa_{c} BH vs FE (FE mesh level 0)",
                        k.get(f"quad kappa_{c} [1/mm]", math.nan),
                        "1/mm",
                        src0,
                        reference=row0[f"quad_{c}"],
                    )
                )
    return out
