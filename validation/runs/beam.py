"""A composite beam (seed 001, Fig. 3) actuated by prescribing its strips' relative lengths.

``lcefem run beam --lambda-top 1.33 --lambda-bottom 1.05 [--segments N] [--out DIR] [--config FILE.toml]
[--quiet] [--model bar-hinge|fe] [--mesh-level L] [--current A --heated bottom|top|both --duration S]``

lambda_T and lambda_B are the top and bottom strips' lengths relative to their isotropic length, as
the paper's lambda (as built: lambda_N = 1.4). The rest lengths are ramped linearly from the as-built
(nematic) lengths to the target (the paper's quasi-static route); the curvature is the signed
curvature of the circle through the middle stations (junction centres), positive when the beam
bends towards its bottom strips, as Eq. 2 (lcefem.solvers.analysis.curvature.beam_curvature).

Outputs in --out DIR: beam.pvd + beam_steps/*.vtp (ParaView: ribbon triangles, strips and glue as
lines; displacement and bar forces), history.csv (one row per converged step), beam.png (curvature
along the ramp vs Eq. 2, and the final side view), summary.json (resolved configuration and
results). Files carry .part names until the run completes; a failed run leaves *.partial.* files,
last_converged.vtp and failure.json.

Models: ``bar-hinge`` (our MERLIN-type model, solvers/bar_hinge) and ``fe`` (the 3D FEniCSx beam of
lcefem.solvers.problems.composite_beam: Kapton neo-Hookean, LCE strips with a prescribed spontaneous stretch,
strip-ribbon penalty contact; quarter model by default). With ``--model fe`` the outputs are
displacement.bp (VTX, ParaView; the mesh is the quarter x >= L_tot/2, y <= W/2), history.csv,
beam_fe.png (curvature along the ramp, side view), beam_fe_3d.png (render) and summary.json.
``--current`` drives the FE beam by a coil current through the heat model instead (one strip group,
``--heated``), for ``--duration`` seconds; history.csv then has time, temperatures and curvature.
"""

from __future__ import annotations

import argparse
import dataclasses
import pathlib
import time
from dataclasses import dataclass, field

import numpy as np

from lcefem.meshes.composite_beam import BeamBarHingeMesh, CompositeBeamGeometry
from lcefem.models import bar_hinge as law
from lcefem.models.empirical import Eq2, eq2_curvature
from lcefem.models.errors import InputError
from lcefem.models.heat import GridSegmentCoil
from lcefem.models.limits import check_lambda
from lcefem.models.parameters import param
from lcefem.solvers.analysis.curvature import beam_curvature
from lcefem.solvers.bar_hinge import NewtonOptions, PathOptions
from lcefem.solvers.run import Progress, Run, add_out_arguments, check_config, resolved
from lcefem.solvers.problems import composite_beam_bh as beam_bh
from lcefem.validation import reference_data
from lcefem.validation.bar_hinge_io import bar_hinge_run
from lcefem.validation.config import config_from_toml, override
from lcefem.validation.runs import parallel_if_fe

MODELS = ("bar-hinge", "fe")
COLUMNS = ["load factor [-]", "lambda_top [-]", "lambda_bottom [-]", "curvature [1/mm]",
           "eq2 curvature [1/mm]", "bottom strip force [N]", "top strip force [N]",
           "newton iterations [-]"]


@dataclass(frozen=True)
class BeamRun:
    """What the experimenter sets: the strips' relative lengths."""

    lambda_top: float = param(1.33, "-", "seed 001 Fig. 4C (dome): lambda_T = 1.33", minimum=1.0)
    lambda_bottom: float = param(1.05, "-", "seed 001 Fig. 4C (dome): lambda_B = 1.05", minimum=1.0)


@dataclass(frozen=True)
class BeamConfig(law.BarHingeMaterials):
    """The bar-and-hinge beam's sections: its materials (kapton, lce, glue, strip_contact, contact,
    ogden: inherited from the one definition, :class:`lcefem.models.bar_hinge.BarHingeMaterials`)
    plus the run, geometry, mesh, Eq. 2 and solver sections."""

    run: BeamRun = field(default_factory=BeamRun)
    geometry: CompositeBeamGeometry = field(default_factory=CompositeBeamGeometry)
    mesh: BeamBarHingeMesh = field(default_factory=BeamBarHingeMesh)
    eq2: Eq2 = field(default_factory=Eq2)
    solver: NewtonOptions = field(default_factory=NewtonOptions)
    path: PathOptions = field(default_factory=lambda: beam_bh.BEAM_PATH)

    def validated(self) -> "BeamConfig":
        check_config(self)
        self.geometry.checked()
        self.mesh.checked()
        for name in ("lambda_top", "lambda_bottom"):
            check_lambda(f"run.{name}", getattr(self.run, name), self.lce.lambda_N)
        return self


    def resolved(self) -> dict:
        return resolved(self)


def run_beam(config: BeamConfig, out: pathlib.Path, progress: bool = True) -> dict:
    """Run the bar-and-hinge beam and write its outputs (see module docstring); returns the summary."""
    cfg = config.validated()
    out = pathlib.Path(out)
    lam_t, lam_b, lam_n = cfg.run.lambda_top, cfg.run.lambda_bottom, cfg.lce.lambda_N
    setup = beam_bh.setup_beam(lam_t, lam_b, cfg.geometry, cfg.mesh, cfg.materials)
    structure, model = setup.structure, setup.model

    def row(state) -> dict:
        forces = model.bar_forces(state.x)
        lt, lb = beam_bh.lambdas_at(state.t, lam_t, lam_b, lam_n)
        return {"load factor [-]": state.t, "lambda_top [-]": lt, "lambda_bottom [-]": lb,
                "curvature [1/mm]": beam_curvature(structure, state.x),
                "eq2 curvature [1/mm]": float(eq2_curvature(lt, lb, cfg.eq2)),
                "bottom strip force [N]": 2.0 * float(np.mean(forces["bottom_strips"])),
                "top strip force [N]": 2.0 * float(np.mean(forces["top_strips"]))
                if "top_strips" in forces else 0.0,
                "newton iterations [-]": state.iterations}

    bar = Progress(1.0, f"beam lambda_T={lam_t:g} lambda_B={lam_b:g}", "load", ".3f", progress)
    started = time.perf_counter()
    with bar_hinge_run(out, "beam", structure, model, config=cfg.resolved(), columns=COLUMNS, row=row,
                       progress=bar) as (run, on_step):
        solution = beam_bh.solve_beam(lam_t, lam_b, newton_options=cfg.solver, path=cfg.path,
                                      on_step=on_step, progress=bar.to, setup=setup)
        history = run.history
        kappa_eq2 = float(eq2_curvature(lam_t, lam_b, cfg.eq2))
        from lcefem.validation.beam_plots import plot_beam_run
        plot_beam_run(out / "beam.png", structure, solution.final.x, history.column("load factor [-]"),
                      history.column("curvature [1/mm]"), history.column("eq2 curvature [1/mm]"),
                      f"composite beam, bar-and-hinge, lambda_T = {lam_t:g}, lambda_B = {lam_b:g}, "
                      f"{cfg.geometry.segments} segments")
        return run.complete({
            "model": "bar-hinge",
            "results": {
                "curvature [1/mm]": solution.curvature,
                "eq2 curvature [1/mm]": kappa_eq2,
                "eq2 inputs": reference_data.eq2_inputs_note(),
                "sign convention": SIGN_CONVENTION,
                "bottom strip force [N]": float(history.column("bottom strip force [N]")[-1]),
                "top strip force [N]": float(history.column("top strip force [N]")[-1]),
            },
            "dofs": int(solution.model.ndof), "nodes": int(structure.num_nodes),
            "increments": len(solution.path.states) - 1,
            "newton_iterations": int(sum(solution.path.newton_iterations)),
            "failed_increments": solution.path.failed_increments,
            "wall_time [s]": time.perf_counter() - started,
        })


SIGN_CONVENTION = ("positive when the beam bends towards its bottom strips (top strips longer), as Eq. 2; "
                   "circle fit through the middle stations")


# -- FE model ------------------------------------------------------------------------------------
FE_COLUMNS = ["load factor [-]", "lambda_top [-]", "lambda_bottom [-]", "curvature [1/mm]",
              "eq2 curvature [1/mm]", "contact force [N]", "min gap [mm]", "newton iterations [-]"]
HEAT_COLUMNS = ["time [s]", "curvature [1/mm]", "T_mean bottom_strips [C]", "T_mean top_strips [C]",
                "T_mean kapton [C]", "contact force [N]", "newton iterations [-]"]


def _fe_config_class():
    """The FE beam's configuration (built lazily: its sections import FEniCSx-side modules)."""
    from lcefem.models.hyperelastic import LCEElasticity, NeoHookeanSolid
    from lcefem.meshes.composite_beam import BeamFEMesh
    from lcefem.solvers.contact import PenaltyContact
    from lcefem.solvers.problems import composite_beam as beam_fe

    @dataclass(frozen=True)
    class BeamFEConfig:
        run: BeamRun = field(default_factory=BeamRun)
        heat_run: beam_fe.HeatedBeamRun = field(default_factory=beam_fe.HeatedBeamRun)
        geometry: CompositeBeamGeometry = field(default_factory=CompositeBeamGeometry)
        mesh: BeamFEMesh = field(default_factory=BeamFEMesh)
        kapton: NeoHookeanSolid = field(default_factory=NeoHookeanSolid)
        lce: LCEElasticity = field(default_factory=LCEElasticity)
        actuation: beam_fe.BeamActuation = field(default_factory=beam_fe.BeamActuation)
        contact: PenaltyContact = field(default_factory=PenaltyContact)
        path: beam_fe.PathControl = field(default_factory=beam_fe.PathControl)
        eq2: Eq2 = field(default_factory=Eq2)

        def validated(self) -> "BeamFEConfig":
            check_config(self)
            self.geometry.checked()
            self.mesh.checked()
            self.heat_run.checked()
            for name in ("lambda_top", "lambda_bottom"):
                check_lambda(f"run.{name}", getattr(self.run, name), self.actuation.lambda_N)
            return self

        @property
        def materials(self):
            return beam_fe.FEMaterials(self.kapton, self.lce)

        def resolved(self) -> dict:
            return resolved(self)

    return BeamFEConfig


def fe_config_from_args(args: argparse.Namespace):
    cfg = config_from_toml(args.config, _fe_config_class()())
    cfg = override(cfg, "run", lambda_top=args.lambda_top, lambda_bottom=args.lambda_bottom)
    cfg = override(cfg, "heat_run", current=args.current, heated=args.heated, duration=args.duration)
    cfg = override(cfg, "mesh", level=args.mesh_level)
    return override(cfg, "geometry", segments=args.segments)


def run_beam_fe(cfg, out: pathlib.Path, progress: bool = True) -> dict:
    """Run the FE beam (prescribed lambdas, or a coil current) and write its outputs."""
    from lcefem.solvers.exports import FieldExport
    from lcefem.solvers.problems import composite_beam as beam_fe
    from lcefem.validation.beam_plots import plot_fe_side_view, render_fe_beam

    cfg = cfg.validated()
    out = pathlib.Path(out)
    if cfg.heat_run.current > 0:
        return _run_beam_fe_heated(cfg, out, progress)
    lam_t, lam_b = cfg.run.lambda_top, cfg.run.lambda_bottom
    started = time.perf_counter()
    model = beam_fe.BeamFE(cfg.geometry, cfg.mesh, cfg.materials, cfg.actuation, cfg.contact, cfg.path)
    bar = Progress(1.0, f"beam (FE) lambda_T={lam_t:g} lambda_B={lam_b:g}", "load", ".3f", progress)
    with Run(out, config=cfg.resolved(), columns=FE_COLUMNS, progress=bar) as run:
        fields = run.output(FieldExport(out / "displacement.bp", [model.u], model.tmesh.mesh.comm))
        fields.write(0.0)

        def on_step(state) -> None:
            run.record({"load factor [-]": state.load_factor, "lambda_top [-]": state.lambda_top,
                        "lambda_bottom [-]": state.lambda_bottom, "curvature [1/mm]": state.curvature,
                        "eq2 curvature [1/mm]": float(eq2_curvature(state.lambda_top, state.lambda_bottom,
                                                                    cfg.eq2)),
                        "contact force [N]": state.contact_force, "min gap [mm]": state.min_gap,
                        "newton iterations [-]": state.iterations},
                       where=f"lambda = ({state.lambda_top:.5g}, {state.lambda_bottom:.5g})",
                       at=state.load_factor)
            fields.write(state.load_factor)

        model.ramp(lam_t, lam_b, on_step=on_step)
        history = run.history
        kappa_eq2 = float(eq2_curvature(lam_t, lam_b, cfg.eq2))
        t_hist, k_hist = history.column("load factor [-]"), history.column("curvature [1/mm]")

        def curve(ax):
            ax.plot(t_hist, k_hist, "k.-", label="3D FE (circle fit, middle stations)")
            ax.plot(t_hist, history.column("eq2 curvature [1/mm]"), "r--", label="Eq. 2 (seed 001)")
            ax.set_xlabel("load factor t [-] (lambda ramped from lambda_N to target)")
            ax.set_ylabel("curvature kappa [1/mm]")
            ax.legend(fontsize=8)
            ax.grid(alpha=0.3)

        title = (f"composite beam, 3D FE, lambda_T = {lam_t:g}, lambda_B = {lam_b:g}, "
                 f"{cfg.geometry.segments} segments, mesh level {cfg.mesh.level}")
        plot_fe_side_view(out / "beam_fe.png", model, model.u, title, curve)
        render_fe_beam(out / "beam_fe_3d.png", model, title)
        follower = model.last_follower
        return run.complete({
            "model": "fe",
            "results": {
                "curvature [1/mm]": model.curvature(), "eq2 curvature [1/mm]": kappa_eq2,
                "eq2 inputs": reference_data.eq2_inputs_note(), "sign convention": SIGN_CONVENTION,
                "contact force [N]": model.contact_force(), "min gap [mm]": model.min_gap(),
                "folds crossed": follower.snaps,
            },
            "dofs": model.ndofs, "cells": model.tmesh.info["cells"], "symmetry": model.tmesh.info["symmetry"],
            "steps": len(history.rows), "newton_iterations": follower.iterations,
            "cut_steps": follower.cuts, "wall_time [s]": time.perf_counter() - started,
        })


def _run_beam_fe_heated(cfg, out: pathlib.Path, progress: bool) -> dict:
    from lcefem.solvers.problems import composite_beam as beam_fe
    from lcefem.validation.beam_plots import plot_fe_side_view

    run_cfg = cfg.heat_run
    bar = Progress(run_cfg.duration, f"beam (FE) {run_cfg.current:g} A {run_cfg.heated} strips", "s",
                   enabled=progress)
    started = time.perf_counter()
    coil = GridSegmentCoil()
    with Run(out, config=cfg.resolved(), columns=HEAT_COLUMNS, progress=bar) as run:
        model, rows, _ = beam_fe.beam_fe_heated(
            run_cfg, cfg.geometry, cfg.mesh, cfg.materials, cfg.contact, coil=coil,
            on_step=lambda row: run.record(row, where=f"t = {row['time [s]']:.4g} s", at=row["time [s]"]))
        t, k = run.history.column("time [s]"), run.history.column("curvature [1/mm]")

        def curve(ax):
            ax.plot(t, k, "k.-")
            ax.set_xlabel("time [s]")
            ax.set_ylabel("curvature kappa [1/mm]")
            ax.grid(alpha=0.3)
            ax.set_title(f"{run_cfg.current:g} A through the {run_cfg.heated} strips", fontsize=9)

        title = (f"composite beam, 3D FE, {run_cfg.current:g} A ({run_cfg.heated} strips), "
                 f"t = {run_cfg.duration:g} s")
        plot_fe_side_view(out / "beam_fe.png", model, model.u, title, curve)
        return run.complete({
            "model": "fe", "drive": "current",
            "results": {"curvature [1/mm]": float(k[-1]),
                        "T_mean bottom strips [C]": float(run.history.column("T_mean bottom_strips [C]")[-1]),
                        "coil resistance per strip [ohm]": coil.resistance},
            "steps": len(rows) - 1, "wall_time [s]": time.perf_counter() - started})


# -- command line -------------------------------------------------------------------------------
def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--lambda-top", type=float, help="top strips' relative length lambda_T [-] "
                   f"(isotropic 1, as built {law.PUBLISHED_LAMBDA_N:g}; default 1.33)")
    p.add_argument("--lambda-bottom", type=float, help="bottom strips' relative length lambda_B [-] "
                   "(default 1.05)")
    p.add_argument("--segments", type=int, help="number of 30 mm segments (default 4)")
    p.add_argument("--model", choices=MODELS, default="bar-hinge", help="bar-and-hinge model or 3D FE "
                   "(default bar-hinge)")
    p.add_argument("--mesh-level", type=int, help="FE refinement level (element size 2 mm/(level+1))")
    p.add_argument("--current", type=float, help="FE only: drive by this coil current [A] through the "
                   "heat model instead of prescribing lambdas")
    p.add_argument("--heated", choices=("bottom", "top", "both"), help="FE only: strips carrying "
                   "--current (default bottom)")
    p.add_argument("--duration", type=float, help="FE only: heating time [s] (default 12)")
    p.add_argument("--config", help="TOML case file; sections: " + ", ".join(
        f.name for f in dataclasses.fields(BeamConfig)) + " (bar-hinge); run, heat_run, geometry, mesh, "
        "kapton, lce, actuation, contact, path, eq2 (fe)")
    add_out_arguments(p, "results/beam")


def config_from_args(args: argparse.Namespace) -> BeamConfig:
    cfg = config_from_toml(args.config, BeamConfig())
    cfg = override(cfg, "run", lambda_top=args.lambda_top, lambda_bottom=args.lambda_bottom)
    return override(cfg, "geometry", segments=args.segments)


PARALLEL = parallel_if_fe


def prepare(args: argparse.Namespace):
    """The validated configuration of the chosen model (before the output folder is touched)."""
    if args.model == "fe":
        return fe_config_from_args(args).validated()
    for name in ("mesh_level", "current", "heated", "duration"):
        if getattr(args, name, None) is not None:
            raise InputError(f"--{name.replace('_', '-')}: only with --model fe")
    return config_from_args(args).validated()


def main(args: argparse.Namespace) -> int:
    cfg = args.prepared
    if args.model == "fe":
        summary = run_beam_fe(cfg, args.out, progress=not args.quiet)
        r = summary["results"]
        if summary.get("drive") == "current":
            print(f"lcefem: beam (fe) {cfg.heat_run.current:g} A through the {cfg.heat_run.heated} "
                  f"strips for {cfg.heat_run.duration:g} s: curvature {r['curvature [1/mm]']:.5f} 1/mm; "
                  f"{summary['wall_time [s]']:.1f} s; results in {args.out}")
            return 0
        print(f"lcefem: beam (fe) lambda_T = {cfg.run.lambda_top:g}, lambda_B = {cfg.run.lambda_bottom:g}, "
              f"{cfg.geometry.segments} segments, mesh level {cfg.mesh.level} ({summary['dofs']} DOFs): "
              f"curvature {r['curvature [1/mm]']:.5f} 1/mm (Eq. 2: {r['eq2 curvature [1/mm]']:.5f} 1/mm); "
              f"{summary['steps']} steps, {summary['newton_iterations']} Newton iterations, "
              f"{summary['wall_time [s]']:.1f} s; results in {args.out}")
        return 0
    summary = run_beam(cfg, args.out, progress=not args.quiet)
    r = summary["results"]
    print(f"lcefem: beam ({args.model}) lambda_T = {cfg.run.lambda_top:g}, lambda_B = "
          f"{cfg.run.lambda_bottom:g}, {cfg.geometry.segments} segments: curvature "
          f"{r['curvature [1/mm]']:.5f} 1/mm (Eq. 2: {r['eq2 curvature [1/mm]']:.5f} 1/mm); "
          f"{summary['increments']} increments, {summary['newton_iterations']} Newton iterations, "
          f"{summary['wall_time [s]']:.1f} s; results in {args.out}")
    return 0
