"""A composite beam (seed 001, Fig. 3) actuated by prescribing its strips' relative lengths.

``lcefem run beam --lambda-top 1.33 --lambda-bottom 1.05 [--segments N] [--out DIR] [--config
FILE.toml] [--quiet] [--model bar-hinge|fe] [--mesh-level L] [--current A --heated bottom|top|both
--duration S]``

lambda_T and lambda_B are the top and bottom strips' lengths relative to their isotropic length, as
the paper's lambda (as built: lambda_N = 1.4). The rest lengths are ramped linearly from the
as-built (nematic) lengths to the target (the paper's quasi-static route); the curvature is the
signed curvature of the circle through the middle stations (junction centres), positive when the
beam bends towards its bottom strips, as Eq. 2 (lcefem.solvers.analysis.curvature.beam_curvature).

Outputs in --out DIR: beam.pvd + beam_steps/*.vtp (ParaView: ribbon triangles, strips and glue as
lines; displacement and bar forces), history.csv (one row per converged step), beam.png (curvature
along the ramp vs Eq. 2, and the final side view), summary.json (resolved configuration and
results). Files carry .part names until the run completes; a failed run leaves *.partial.* files,
last_converged.vtp and failure.json.

Models: ``bar-hinge`` (our MERLIN-type model, lcefem.solvers.problems.composite_beam_bh) and ``fe``
(the 3D FEniCSx beam of lcefem.solvers.problems.composite_beam: Kapton neo-Hookean, LCE strips with
a prescribed spontaneous stretch, strip-ribbon penalty contact; quarter model by default). With
``--model fe`` the outputs are displacement.bp (VTX, ParaView; the mesh is the quarter x >= L_tot/2,
y <= W/2), history.csv, beam_fe.png (curvature along the ramp, side view), beam_fe_3d.png (render;
serial runs only) and summary.json. ``--current`` drives the FE beam by a coil current through the
heat model instead (one strip group, ``--heated``), for ``--duration`` seconds; history.csv then has
time, temperatures and curvature. The FE model runs under ``mpiexec -n N`` too (both drives).
"""

from __future__ import annotations

import argparse
import dataclasses

from lcefem.meshes.composite_beam import STRIP_ELEMENTS
from lcefem.models import bar_hinge_materials as law
from lcefem.models.errors import InputError
from lcefem.solvers.problems.composite_beam_bh import BeamConfig, run_beam
from lcefem.solvers.runtime.outdir import add_out_arguments
from lcefem.solvers.runtime.ranks import world_rank
from lcefem.validation.app.commands import MODELS, parallel_if_fe
from lcefem.validation.app.config import config_from_toml, override
from lcefem.validation.cases import reference_data

#: Under mpiexec: the FE model only, both routes (lambda ramp and coil current). Its curvature
#: stations (composite_beam.BeamStations) take each point from the rank that owns its node and
#: combine them with one allreduce, the strip-ribbon contact runs on N ranks (solvers/contact.py),
#: the side view gathers the nodes to rank 0; 2 ranks give the serial curvature
#: (tests/validation/test_beam_fe_mpi.py). beam_fe_3d.png (pyvista: one process's mesh) is
#: drawn in serial only. The bar-and-hinge model is numpy/scipy (ranks would race on one folder).
PARALLEL = parallel_if_fe


def report_bar_hinge(out, cfg, solution, history) -> dict:
    """beam.png (curvature along the ramp vs Eq. 2, final side view) and Eq. 2's inputs."""
    from lcefem.validation.studies.beam.beam_plots import plot_beam_run

    plot_beam_run(
        out / "beam.png",
        solution.structure,
        solution.final.x,
        history.column("load factor [-]"),
        history.column("curvature [1/mm]"),
        history.column("eq2 curvature [1/mm]"),
        f"composite beam, bar-and-hinge, lambda_T = {cfg.run.lambda_top:g}, lambda_B = "
        f"{cfg.run.lambda_bottom:g}, {cfg.geometry.segments} segments",
    )
    return {"eq2 inputs": reference_data.eq2_inputs_note()}


def report_fe(out, cfg, model, history) -> dict:
    """beam_fe.png (curvature along the ramp or in time, side view; collective, rank 0 writes it);
    for the lambda ramp also beam_fe_3d.png (render, serial runs only) and Eq. 2's inputs."""
    from lcefem.validation.studies.beam.beam_plots import plot_fe_side_view, render_fe_beam

    heat = cfg.heat_run
    if heat.current > 0:
        t, k = history.column("time [s]"), history.column("curvature [1/mm]")

        def curve(ax):
            ax.plot(t, k, "k.-")
            ax.set_xlabel("time [s]")
            ax.set_ylabel("curvature kappa [1/mm]")
            ax.grid(alpha=0.3)
            ax.set_title(f"{heat.current:g} A through the {heat.heated} strips", fontsize=9)

        title = (
            f"composite beam, 3D FE, {heat.current:g} A ({heat.heated} strips), "
            f"t = {heat.duration:g} s"
        )
        plot_fe_side_view(out / "beam_fe.png", model, model.u, title, curve)
        return {}
    t_hist, k_hist = history.column("load factor [-]"), history.column("curvature [1/mm]")

    def curve(ax):
        ax.plot(t_hist, k_hist, "k.-", label="3D FE (circle fit, middle stations)")
        ax.plot(t_hist, history.column("eq2 curvature [1/mm]"), "r--", label="Eq. 2 (seed 001)")
        ax.set_xlabel("load factor t [-] (lambda ramped from lambda_N to target)")
        ax.set_ylabel("curvature kappa [1/mm]")
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)

    title = (
        f"composite beam, 3D FE, lambda_T = {cfg.run.lambda_top:g}, lambda_B = "
        f"{cfg.run.lambda_bottom:g}, {cfg.geometry.segments} segments, mesh level {cfg.mesh.level}"
    )
    plot_fe_side_view(out / "beam_fe.png", model, model.u, title, curve)
    if model.tmesh.mesh.comm.size == 1:  # pyvista renders one process's mesh: serial only
        render_fe_beam(out / "beam_fe_3d.png", model, title)
    return {"eq2 inputs": reference_data.eq2_inputs_note()}


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--lambda-top",
        type=float,
        help="top strips' relative length lambda_T [-] "
        f"(isotropic 1, as built {law.PUBLISHED_LAMBDA_N:g}; default 1.33)",
    )
    p.add_argument(
        "--lambda-bottom",
        type=float,
        help="bottom strips' relative length lambda_B [-] (default 1.05)",
    )
    p.add_argument("--segments", type=int, help="number of 30 mm segments (default 4)")
    p.add_argument(
        "--model",
        choices=MODELS,
        default="bar-hinge",
        help="bar-and-hinge model or 3D FE (default bar-hinge)",
    )
    p.add_argument(
        "--mesh-level", type=int, help="FE refinement level (element size 2 mm/(level+1))"
    )
    p.add_argument(
        "--current",
        type=float,
        help="FE only: drive by this coil current [A] through the "
        "heat model instead of prescribing lambdas",
    )
    p.add_argument(
        "--heated",
        choices=("bottom", "top", "both"),
        help="FE only: strips carrying --current (default bottom)",
    )
    p.add_argument("--duration", type=float, help="FE only: heating time [s] (default 12)")
    p.add_argument(
        "--strip-element",
        choices=STRIP_ELEMENTS,
        help="bar-and-hinge only: how the LCE "
        "strips act on the ribbon (mesh.strip_element): bar (published, default), offset (at "
        "the strip's centroid), bending (own E I), beam (both)",
    )
    p.add_argument(
        "--config",
        help="TOML case file; sections: "
        + ", ".join(f.name for f in dataclasses.fields(BeamConfig))
        + " (bar-hinge); run, heat_run, geometry, mesh, "
        "kapton, lce, actuation, contact, path, eq2 (fe)",
    )
    add_out_arguments(p, "results/beam")


def config_from_args(args: argparse.Namespace):
    if args.model == "fe":
        from lcefem.solvers.problems.composite_beam_run import (
            BeamFEConfig,
        )  # FEniCSx only when asked

        cfg = config_from_toml(args.config, BeamFEConfig())
        cfg = override(
            cfg, "heat_run", current=args.current, heated=args.heated, duration=args.duration
        )
        cfg = override(cfg, "mesh", level=args.mesh_level)
    else:
        cfg = config_from_toml(args.config, BeamConfig())
        cfg = override(cfg, "mesh", strip_element=getattr(args, "strip_element", None))
    cfg = override(cfg, "run", lambda_top=args.lambda_top, lambda_bottom=args.lambda_bottom)
    return override(cfg, "geometry", segments=args.segments)


def prepare(args: argparse.Namespace):
    """The validated configuration of the chosen model (before the output folder is touched)."""
    if args.model == "fe" and getattr(args, "strip_element", None) is not None:
        raise InputError("--strip-element: only with --model bar-hinge")
    if args.model != "fe":
        for name in ("mesh_level", "current", "heated", "duration"):
            if getattr(args, name, None) is not None:
                raise InputError(f"--{name.replace('_', '-')}: only with --model fe")
    return config_from_args(args).validated()


def main(args: argparse.Namespace) -> int:
    cfg = args.prepared
    if args.model == "fe":
        from lcefem.solvers.problems.composite_beam_run import run_beam_fe

        summary = run_beam_fe(cfg, args.out, progress=not args.quiet, report=report_fe)
        r = summary["results"]
        if world_rank() != 0:  # under mpiexec: one line, rank 0's (its wall time)
            return 0
        if summary.get("drive") == "current":
            print(
                f"lcefem: beam (fe) {cfg.heat_run.current:g} A through the {cfg.heat_run.heated} "
                f"strips for {cfg.heat_run.duration:g} s: curvature {r['curvature [1/mm]']:.5f} "
                "1/mm; "
                f"{summary['wall_time [s]']:.1f} s; results in {args.out}"
            )
            return 0
        print(
            f"lcefem: beam (fe) lambda_T = {cfg.run.lambda_top:g}, lambda_B = "
            f"{cfg.run.lambda_bottom:g}, "
            f"{cfg.geometry.segments} segments, mesh level {cfg.mesh.level} ({summary['dofs']} "
            "DOFs): "
            f"curvature {r['curvature [1/mm]']:.5f} 1/mm (Eq. 2: {r['eq2 curvature [1/mm]']:.5f} "
            "1/mm); "
            f"{summary['steps']} steps, {summary['newton_iterations']} Newton iterations, "
            f"{summary['wall_time [s]']:.1f} s; results in {args.out}"
        )
        return 0
    summary = run_beam(cfg, args.out, progress=not args.quiet, report=report_bar_hinge)
    r = summary["results"]
    print(
        f"lcefem: beam ({args.model}) lambda_T = {cfg.run.lambda_top:g}, lambda_B = "
        f"{cfg.run.lambda_bottom:g}, {cfg.geometry.segments} segments: curvature "
        f"{r['curvature [1/mm]']:.5f} 1/mm (Eq. 2: {r['eq2 curvature [1/mm]']:.5f} 1/mm); "
        f"{summary['increments']} increments, {summary['newton_iterations']} Newton iterations, "
        f"{summary['wall_time [s]']:.1f} s; results in {args.out}"
    )
    return 0
