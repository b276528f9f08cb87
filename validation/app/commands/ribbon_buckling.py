"""The passive Kapton ribbon's buckling test (seed 001, Fig. 2G): a 36 x 7 x 0.127 mm specimen,
fixed-fixed, shortened by a prescribed end displacement.

``lcefem run ribbon-buckling [--compression 0.5] [--out DIR] [--config FILE.toml] [--quiet]
[--model bar-hinge|fe] [--mesh-level L]``

The run follows the force-compression path of the slightly imperfect specimen (first fixed-fixed
mode, amplitude 1e-3 of the length), and finds the critical load of the perfect specimen as the
end shortening where the tangent stiffness of the straight state loses positive definiteness. It
compares them with the measured 0.18 N, with the Euler load 4 pi^2 EI/L^2 of the same specimen
(datasheet E), with the Euler load of the bar-and-hinge chain's own bending stiffness (closed form,
lcefem.models.bar_hinge.n5b8_ribbon_bending_stiffness), and the post-buckling force
with the inextensible elastica.

With ``--model fe`` the specimen is a 3D neo-Hookean solid (datasheet E and nu) meshed with
quadratic hexahedra (one through the thickness; half model about y = W/2); the critical load comes
from the linearised buckling eigenproblem about the straight state (SLEPc), the path is seeded with
the first eigenmode (amplitude 1e-3 of the length); outputs: displacement.bp (VTX), history.csv,
ribbon_buckling.png, summary.json (also the plate-strip Euler load with E/(1 - nu^2) and the free
length and modulus that would give the measured 0.18 N).

The problems: lcefem.solvers.problems.kapton_specimen_bh and kapton_specimen; this module adds the
measured load and the plot (a report hook).

Outputs in --out DIR (bar-hinge): ribbon.pvd + ribbon_steps/*.vtp, history.csv (compression [-], end
shortening [mm], force [N], Newton iterations), ribbon_buckling.png, summary.json. Files carry
.part names until complete; a failed run leaves *.partial.* files, last_converged.vtp and
failure.json.
"""

from __future__ import annotations

import argparse
import dataclasses

import numpy as np

from lcefem.models import buckling
from lcefem.models.errors import InputError
from lcefem.solvers.problems.kapton_specimen_bh import KaptonSpecimenConfig, run_specimen
from lcefem.solvers.runtime.outdir import add_out_arguments
from lcefem.validation.app import plots
from lcefem.validation.app.commands import MODELS, parallel_if_fe
from lcefem.validation.app.config import config_from_toml, override
from lcefem.validation.cases.reference_data import reference

PARALLEL = parallel_if_fe
SOURCES = ["Euler: 4 pi^2 EI/L^2, fixed-fixed", "elastica: Timoshenko & Gere 1961"]


def _plot(
    out,
    compression,
    force,
    label: str,
    p_cr: float,
    p_cr_label: str,
    digits: int,
    closed: list,
    title: str,
):
    """ribbon_buckling.png: the model's force-compression path, the elastica scaled by its critical
    load, the measured load, the critical load [N] (``digits`` decimals) and the closed forms
    ``closed`` (plots.Line)."""
    measured = reference("ribbon.buckling_load")
    c_el = np.linspace(0.0, compression[-1], 60)
    f_el = p_cr * np.array([buckling.elastica_force_ratio(c) for c in c_el])
    plots.comparison_plot(
        out / "ribbon_buckling.png",
        [
            plots.Series(100 * compression, force, label, "model"),
            plots.Series(100 * c_el, f_el, f"elastica x P_cr ({p_cr_label})", "closed form"),
        ],
        xlabel="compression (end shortening / length) [%]",
        ylabel="compressive force [N]",
        hlines=[
            plots.Line(
                measured.value, f"measured critical load {measured.value:g} N", "experiment"
            ),
            plots.Line(p_cr, f"P_cr {p_cr_label} {p_cr:.{digits}f} N", "model"),
            *closed,
        ],
        title=title,
        sources=[measured.cite, *SOURCES],
    )
    return measured


def report_bar_hinge(out, cfg, solution, p_cr, euler) -> dict:
    """ribbon_buckling.png (path, elastica, measured and closed-form loads) and the measured
    load."""
    measured = _plot(
        out,
        solution.compression,
        solution.force,
        f"bar-and-hinge ({cfg.mesh.panels} panels)",
        p_cr,
        "bar-and-hinge",
        3,
        [plots.Line(v, f"{k} = {v:.3f} N", "closed form") for k, v in euler.items()],
        "Fixed-fixed Kapton ribbon 36 x 7 x 0.127 mm",
    )
    return {"measured critical load [N]": measured.value}


def report_fe(out, cfg, model, critical, history) -> dict:
    """ribbon_buckling.png and the closed forms that need the measured load (the free length and
    modulus that would give it)."""
    measured = reference("ribbon.buckling_load")
    closed = buckling.specimen_closed_forms(
        cfg.specimen, cfg.kapton.youngs_modulus, cfg.kapton.poisson_ratio, measured.value
    )
    euler = closed["Euler, E I (datasheet E) [N]"]
    plate = closed["Euler, plate strip E I/(1 - nu^2) [N]"]
    _plot(
        out,
        history.column("compression [-]"),
        history.column("force [N]"),
        f"3D FE (Q2, {model.ndofs} DOFs, mode imperfection)",
        critical.force,
        "FE",
        4,
        [
            plots.Line(euler, f"Euler E I = {euler:.4f} N", "closed form"),
            plots.Line(plate, f"Euler E I/(1-nu^2) = {plate:.4f} N", "reference"),
        ],
        "Fixed-fixed Kapton ribbon 36 x 7 x 0.127 mm (3D FE)",
    )
    return {"measured critical load [N]": measured.value, **closed}


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--compression", type=float, help="final end shortening / length [-] (default 0.5)"
    )
    p.add_argument(
        "--model",
        choices=MODELS,
        default="bar-hinge",
        help="bar-and-hinge model or 3D FE (default bar-hinge)",
    )
    p.add_argument(
        "--mesh-level", type=int, help="FE refinement level (in-plane element size 1 mm/(level+1))"
    )
    p.add_argument(
        "--config",
        help="TOML case file; sections: "
        + ", ".join(f.name for f in dataclasses.fields(KaptonSpecimenConfig))
        + " (bar-hinge); run, specimen, mesh, kapton, "
        "path (fe)",
    )
    add_out_arguments(p, "results/ribbon-buckling")


def config_from_args(args: argparse.Namespace):
    if args.model == "fe":
        from lcefem.solvers.problems.kapton_specimen import (
            KaptonSpecimenFEConfig,
        )  # FEniCSx only when asked

        cfg = override(
            config_from_toml(args.config, KaptonSpecimenFEConfig()), "mesh", level=args.mesh_level
        )
    else:
        cfg = config_from_toml(args.config, KaptonSpecimenConfig())
    return override(cfg, "run", compression=args.compression)


def prepare(args: argparse.Namespace):
    """The validated configuration of the chosen model (before the output folder is touched)."""
    if args.model != "fe" and getattr(args, "mesh_level", None) is not None:
        raise InputError("--mesh-level: only with --model fe")
    return config_from_args(args).validated()


def main(args: argparse.Namespace) -> int:
    cfg = args.prepared
    if args.model == "fe":
        from lcefem.solvers.problems.kapton_specimen import run_specimen_fe

        summary = run_specimen_fe(cfg, args.out, progress=not args.quiet, report=report_fe)
        r = summary["results"]
        print(
            f"lcefem: ribbon buckling (fe, {summary['dofs']} DOFs): critical load "
            f"{r['critical load [N]']:.4f} N (measured {r['measured critical load [N]']:g} N; "
            "Euler E "
            "I "
            f"{r['Euler, E I (datasheet E) [N]']:.4f} N, plate strip "
            f"{r['Euler, plate strip E I/(1 - nu^2) [N]']:.4f} N); force at "
            f"{100 * r['final compression [-]']:.0f} % compression {
                r['force at final compression [N]']:.4f} N; "
            f"{summary['wall_time [s]']:.1f} s; results in {args.out}"
        )
        return 0
    summary = run_specimen(cfg, args.out, progress=not args.quiet, report=report_bar_hinge)
    r = summary["results"]
    print(
        f"lcefem: ribbon buckling ({args.model}): critical load {r['critical load [N]']:.4f} N "
        f"(measured {r['measured critical load [N]']:g} N; Euler E I "
        f"{r['Euler, E I (datasheet E) [N]']:.4f} N); force at "
        f"{100 * r['final compression [-]']:.0f} "
        "% "
        f"compression {r['force at final compression [N]']:.4f} N; {summary['wall_time [s]']:.1f} "
        "s; "
        f"results in {args.out}"
    )
    return 0
