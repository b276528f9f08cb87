"""The measured effect of each of our departures from the published configuration, on all eight
published recipes (issue 30; the table of docs/gridshell_configuration.md).

    python -m lcefem.validation.studies.gridshell.gridshell_configuration \
        [--recipes dome,saddle] [--out DIR]

For every recipe (:data:`lcefem.validation.cases.programs.RECIPES`) it runs the published
configuration (its published support, glue squares, bar law A f P(p), no strip-ribbon contact), the
published configuration with one departure
(:data:`~lcefem.solvers.problems.gridshell_bh_run.DEPARTURES`) at a time, all departures together,
and the configuration shipped before issue 30 (all departures, on the middle ribbons' rollers for
every recipe but the saddle; for dome, cylinder and table the same as all departures, so not
repeated). Per run: converged, centre curvatures by the circle (Fig. 4) and the nine-point quadratic
fit, z range, the nine junction centres' RMS distance to the published run's after a rigid (Kabsch)
fit, increments, Newton iterations, wall time. Writes ``configuration_effects.csv`` (units in the
header) and ``configuration_effects.md`` into DIR (default results/gridshell_configuration), each
through a .part name.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import pathlib
import time

import numpy as np

from lcefem.meshes.composite_beam import BeamBarHingeMesh
from lcefem.meshes.gridshell import build_gridshell_bar_hinge
from lcefem.models import bar_hinge_materials as bhm
from lcefem.models.errors import ConvergenceError
from lcefem.solvers.analysis.curvature import junction_centre_points
from lcefem.solvers.problems import gridshell_bh as g
from lcefem.solvers.problems import gridshell_bh_run as grun
from lcefem.solvers.runtime.files import write_text
from lcefem.validation.cases.programs import RECIPES

#: The variants measured: label -> (departures, support override or None).
VARIANTS = {
    "published": ((), None),
    **{f"+{d}": ((d,), None) for d in grun.DEPARTURES},
    "all departures": (tuple(grun.DEPARTURES), None),
    "shipped before issue 30": (("contact", "contracting_squares", "volume_law"), "former"),
}


def former_support(recipe: str) -> str:
    """The support shipped before issue 30: the centre clamp for the saddle, the middle ribbons'
    rollers for every other recipe."""
    return "clamp" if recipe == "saddle" else "middle_rollers"


def rigid_rms(a: np.ndarray, b: np.ndarray) -> float:
    """RMS distance [mm] between point sets a and b (m, 3) after the best rigid motion of b onto
    a."""
    ca, cb = a.mean(axis=0), b.mean(axis=0)
    u, _, vt = np.linalg.svd((b - cb).T @ (a - ca))
    d = np.sign(np.linalg.det(u @ vt))
    rot = u @ np.diag([1.0, 1.0, d]) @ vt
    return float(np.sqrt(np.mean(np.sum(((b - cb) @ rot - (a - ca)) ** 2, axis=1))))


def penetration(mesh: BeamBarHingeMesh, x: np.ndarray) -> float:
    """Deepest strip-ribbon interpenetration [mm] of positions x (n, 3) of the default gridshell
    built with ``mesh`` (:func:`lcefem.solvers.problems.gridshell_bh.strip_ribbon_penetration`)."""
    return g.strip_ribbon_penetration(x, mesh=mesh)


def run_variant(recipe: str, departures, support_override) -> dict:
    """One recipe in one configuration: the numbers of the table (NaN where it did not converge)."""
    p0, support = RECIPES[recipe]
    if support_override == "former":
        mesh, lce, _ = grun.published_configuration(
            BeamBarHingeMesh(), bhm.LCEStripBars(), support, departures
        )
        support = former_support(recipe)
    else:
        mesh, lce, support = grun.published_configuration(
            BeamBarHingeMesh(), bhm.LCEStripBars(), support, departures
        )
    s = build_gridshell_bar_hinge(mesh=mesh)
    materials = dataclasses.replace(bhm.BarHingeMaterials(), lce=lce)
    setup = g.setup_gridshell(
        g.targets_from_recipe(s, p0), support, structure=s, materials=materials
    )
    t0 = time.perf_counter()
    out = {"recipe": recipe, "support": support, "converged": False, "why": ""}
    try:
        sol = g.solve_gridshell(setup)
    except ConvergenceError as exc:
        out.update(seconds=time.perf_counter() - t0, why=str(exc).splitlines()[0][:120])
        return out
    k = sol.curvatures
    summ = g.shape_summary(s, sol.final.x)
    out.update(
        converged=True,
        seconds=time.perf_counter() - t0,
        circle_x=k["circle_x"],
        circle_y=k["circle_y"],
        quad_kx=k["quad_kx"],
        quad_ky=k["quad_ky"],
        z_range=summ["z_range [mm]"],
        increments=len(sol.path.states) - 1,
        newton=int(sum(sol.path.newton_iterations)),
        centres=junction_centre_points(s, sol.final.x).reshape(-1, 3),
        penetration=penetration(mesh, sol.final.x),
    )
    return out


COLUMNS = [
    ("recipe", "recipe [-]"),
    ("variant", "variant [-]"),
    ("support", "support [-]"),
    ("converged", "converged [-]"),
    ("circle_x", "circle kappa_x [1/mm]"),
    ("circle_y", "circle kappa_y [1/mm]"),
    ("quad_kx", "quad kappa_x [1/mm]"),
    ("quad_ky", "quad kappa_y [1/mm]"),
    ("z_range", "z range [mm]"),
    ("rms", "junction centres RMS vs published [mm]"),
    ("penetration", "deepest strip-ribbon penetration [mm]"),
    ("increments", "increments [-]"),
    ("newton", "Newton iterations [-]"),
    ("seconds", "wall time [s]"),
]


def measure(recipes, variants=VARIANTS, echo=print) -> list[dict]:
    rows = []
    for recipe in recipes:
        base = None
        for label, (deps, override) in variants.items():
            if label == "+middle_rollers" and RECIPES[recipe][1] != "rollers":
                continue  # no effect where the published support is the clamp
            if override == "former" and RECIPES[recipe][1] == "rollers":
                continue  # the same as "all departures" (middle rollers included)
            r = run_variant(recipe, deps, override)
            r["variant"] = label
            if label == "published" and r["converged"]:
                base = r["centres"]
            r["rms"] = (
                rigid_rms(base, r["centres"]) if (base is not None and r["converged"]) else math.nan
            )
            rows.append(r)
            echo(
                " ".join(
                    f"{r.get(k, math.nan):.4g}"
                    if isinstance(r.get(k), float)
                    else str(r.get(k, ""))
                    for k, _ in COLUMNS
                )
                + (f"  ({r['why']})" if r["why"] else "")
            )
    return rows


def write_tables(rows: list[dict], out: pathlib.Path) -> None:
    out.mkdir(parents=True, exist_ok=True)
    lines = [",".join(h for _, h in COLUMNS)]
    md = [
        "| recipe | variant | support | circle kx | circle ky | quad kx | quad ky | z range | "
        "RMS vs published | penetration | Newton it. | time |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        vals = []
        for k, _ in COLUMNS:
            v = r.get(k, math.nan)
            vals.append(
                f"{v:.6g}" if isinstance(v, float) else str(int(v) if isinstance(v, bool) else v)
            )
        lines.append(",".join(vals))
        if r["converged"]:
            md.append(
                f"| {r['recipe']} | {r['variant']} | {r['support']} | {r['circle_x']:.4f} | "
                f"{r['circle_y']:.4f} | {r['quad_kx']:.4f} | {r['quad_ky']:.4f} | "
                f"{r['z_range']:.1f} | {r['rms']:.2f} | {r['penetration']:.2f} | {r['newton']} | "
                f"{r['seconds']:.1f} s "
                "|"
            )
        else:
            md.append(
                f"| {r['recipe']} | {r['variant']} | {r['support']} | did not converge "
                f"({r['why']}) | | | | | | | | {r['seconds']:.1f} s |"
            )
    write_text(out / "configuration_effects.csv", "\n".join(lines) + "\n")
    write_text(out / "configuration_effects.md", "\n".join(md) + "\n")


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--recipes", default=",".join(RECIPES), help="comma-separated recipes")
    p.add_argument("--out", default="results/gridshell_configuration")
    args = p.parse_args(argv)
    recipes = [r.strip() for r in args.recipes.split(",") if r.strip()]
    for r in recipes:
        if r not in RECIPES:
            p.error(f"--recipes: unknown recipe {r!r} (allowed: {', '.join(RECIPES)})")
    rows = measure(recipes)
    write_tables(rows, pathlib.Path(args.out))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
