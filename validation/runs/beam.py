"""A composite beam (seed 001, Fig. 3) actuated by prescribing its strips' relative lengths.

``lcefem run beam --lambda-top 1.33 --lambda-bottom 1.05 [--segments N] [--out DIR] [--config FILE.toml]
[--quiet] [--model bar-hinge]``

lambda_T and lambda_B are the top and bottom strips' lengths relative to their isotropic length, as
the paper's lambda (as built: lambda_N = 1.4). The rest lengths are ramped linearly from the as-built
(nematic) lengths to the target (the paper's quasi-static route); the curvature is the signed
curvature of the circle through the middle stations (junction centres), positive when the beam
bends towards its bottom strips, as Eq. 2 (lcefem.meshes.composite_beam.beam_curvature).

Outputs in --out DIR: beam.pvd + beam_steps/*.vtp (ParaView: ribbon triangles, strips and glue as
lines; displacement and bar forces), history.csv (one row per converged step), beam.png (curvature
along the ramp vs Eq. 2, and the final side view), summary.json (resolved configuration and
results). Files carry .part names until the run completes; a failed run leaves *.partial.* files,
last_converged.vtp and failure.json.

Models: ``bar-hinge`` (our MERLIN-type model, solvers/bar_hinge). The 3D FE beam will be added as ``fe``.
"""

from __future__ import annotations

import argparse
import dataclasses
import pathlib
import sys
import time
from dataclasses import dataclass, field

import numpy as np

from lcefem.meshes.composite_beam import BeamBarHingeMesh, CompositeBeamGeometry, beam_curvature
from lcefem.models import bar_hinge as law
from lcefem.models.empirical import Eq2, eq2_curvature
from lcefem.models.errors import ConvergenceError, InputError
from lcefem.models.parameters import check, describe, param, with_overrides
from lcefem.solvers.bar_hinge import NewtonOptions, PathOptions
from lcefem.validation import bar_hinge_studies as studies
from lcefem.validation.bar_hinge_io import BarHingeVTK, CSVHistory, write_json
from lcefem.validation.config import load_toml

MODELS = ("bar-hinge",)
COLUMNS = ["load factor [-]", "lambda_top [-]", "lambda_bottom [-]", "curvature [1/mm]",
           "eq2 curvature [1/mm]", "bottom strip force [N]", "top strip force [N]",
           "newton iterations [-]"]


@dataclass(frozen=True)
class BeamRun:
    """What the experimenter sets: the strips' relative lengths."""

    lambda_top: float = param(1.33, "-", "seed 001 Fig. 4C (dome): lambda_T = 1.33", minimum=1.0)
    lambda_bottom: float = param(1.05, "-", "seed 001 Fig. 4C (dome): lambda_B = 1.05", minimum=1.0)


@dataclass(frozen=True)
class BeamConfig:
    run: BeamRun = field(default_factory=BeamRun)
    geometry: CompositeBeamGeometry = field(default_factory=CompositeBeamGeometry)
    mesh: BeamBarHingeMesh = field(default_factory=BeamBarHingeMesh)
    kapton: law.KaptonBarHinge = field(default_factory=law.KaptonBarHinge)
    lce: law.LCEStripBars = field(default_factory=law.LCEStripBars)
    glue: law.GlueBars = field(default_factory=law.GlueBars)
    strip_contact: law.StripContactSprings = field(default_factory=law.StripContactSprings)
    contact: law.StripContact = field(default_factory=law.StripContact)
    eq2: Eq2 = field(default_factory=Eq2)
    solver: NewtonOptions = field(default_factory=NewtonOptions)
    path: PathOptions = field(default_factory=lambda: studies.BEAM_PATH)

    def validated(self) -> "BeamConfig":
        for f in dataclasses.fields(self):
            check(getattr(self, f.name), f.name)
        self.geometry.checked()
        self.mesh.checked()
        for name in ("lambda_top", "lambda_bottom"):
            studies.check_lambda(f"run.{name}", getattr(self.run, name), self.lce.lambda_N)
        return self

    @property
    def materials(self) -> studies.BarHingeMaterials:
        return studies.BarHingeMaterials(self.kapton, self.lce, self.glue, self.strip_contact,
                                         self.contact)

    def resolved(self) -> dict:
        return {f.name: describe(getattr(self, f.name)) for f in dataclasses.fields(self)}


def config_from_toml(path, base: BeamConfig = BeamConfig()) -> BeamConfig:
    data = load_toml(path, {f.name for f in dataclasses.fields(BeamConfig)})
    return dataclasses.replace(base, **{name: with_overrides(getattr(base, name), table, name)
                                        for name, table in data.items()})


def prepare_out(out: pathlib.Path) -> pathlib.Path:
    out = pathlib.Path(out)
    if out.exists() and not out.is_dir():
        raise InputError(f"out = {str(out)!r}: exists and is not a directory")
    out.mkdir(parents=True, exist_ok=True)
    return out


def run_beam(config: BeamConfig, out: pathlib.Path, progress: bool = True) -> dict:
    """Run the bar-and-hinge beam and write its outputs (see module docstring); returns the summary."""
    cfg = config.validated()
    out = prepare_out(out)
    lam_t, lam_b, lam_n = cfg.run.lambda_top, cfg.run.lambda_bottom, cfg.lce.lambda_N
    setup = studies.setup_beam(lam_t, lam_b, cfg.geometry, cfg.mesh, cfg.materials)
    structure, model = setup.structure, setup.model
    vtk = BarHingeVTK(out, "beam", structure)
    history = CSVHistory(out / "history.csv", COLUMNS)
    holder: dict = {}

    def on_step(state) -> None:
        forces = model.bar_forces(state.x)
        lt, lb = studies.lambdas_at(state.t, lam_t, lam_b, lam_n)
        history.append({"load factor [-]": state.t, "lambda_top [-]": lt, "lambda_bottom [-]": lb,
                        "curvature [1/mm]": beam_curvature(structure, state.x),
                        "eq2 curvature [1/mm]": float(eq2_curvature(lt, lb, cfg.eq2)),
                        "bottom strip force [N]": 2.0 * float(np.mean(forces["bottom_strips"])),
                        "top strip force [N]": 2.0 * float(np.mean(forces["top_strips"]))
                        if "top_strips" in forces else 0.0,
                        "newton iterations [-]": state.iterations})
        vtk.write(state.t, state.x, forces)
        holder["last"] = state

    bar = None
    if progress:
        from tqdm import tqdm
        bar = tqdm(total=1.0, desc=f"beam lambda_T={lam_t:g} lambda_B={lam_b:g}", unit="load",
                   bar_format="{l_bar}{bar}| {n:.3f}/{total:.0f} [{elapsed}<{remaining}]",
                   file=sys.stderr)

    def advance(t: float) -> None:
        if bar is not None:
            bar.update(t - bar.n)

    started = time.perf_counter()
    try:
        solution = studies.solve_beam(lam_t, lam_b, newton_options=cfg.solver, path=cfg.path,
                                      on_step=on_step, progress=advance, setup=setup)
    except ConvergenceError as exc:
        if bar is not None:
            bar.close()
        last = holder.get("last")
        if last is not None:
            vtk.write_single(out / "last_converged.vtp", last.x, model.bar_forces(last.x))
        vtk.finalize(complete=False)
        history.finalize(complete=False)
        write_json(out / "failure.json", {
            "status": "failed", "where": exc.where, "reason": exc.reason,
            "last_converged_load_factor [-]": None if last is None else last.t,
            "note": "history.partial.csv and beam_steps.partial/ hold the converged steps; "
                    "last_converged.vtp the last one", "config": cfg.resolved()})
        raise
    except BaseException:
        if bar is not None:
            bar.close()
        raise
    if bar is not None:
        bar.close()
    wall = time.perf_counter() - started
    vtk.finalize()
    history.finalize()
    kappa_eq2 = float(eq2_curvature(lam_t, lam_b, cfg.eq2))
    from lcefem.validation.beam_plots import plot_beam_run
    plot_beam_run(out / "beam.png", structure, solution.final.x, history.column("load factor [-]"),
                  history.column("curvature [1/mm]"), history.column("eq2 curvature [1/mm]"),
                  f"composite beam, bar-and-hinge, lambda_T = {lam_t:g}, lambda_B = {lam_b:g}, "
                  f"{cfg.geometry.segments} segments")
    summary = {
        "status": "completed", "model": "bar-hinge", "config": cfg.resolved(),
        "results": {
            "curvature [1/mm]": solution.curvature,
            "eq2 curvature [1/mm]": kappa_eq2,
            "eq2 inputs": studies.eq2_inputs_note(),
            "sign convention": "positive when the beam bends towards its bottom strips (top strips "
                               "longer), as Eq. 2; circle fit through the middle stations",
            "bottom strip force [N]": float(history.column("bottom strip force [N]")[-1]),
            "top strip force [N]": float(history.column("top strip force [N]")[-1]),
        },
        "dofs": int(solution.model.ndof), "nodes": int(structure.num_nodes),
        "increments": len(solution.path.states) - 1,
        "newton_iterations": int(sum(solution.path.newton_iterations)),
        "failed_increments": solution.path.failed_increments,
        "wall_time [s]": wall,
    }
    write_json(out / "summary.json", summary)
    return summary


# -- command line -------------------------------------------------------------------------------
def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--lambda-top", type=float, help="top strips' relative length lambda_T [-] "
                   "(isotropic 1, as built 1.4; default 1.33)")
    p.add_argument("--lambda-bottom", type=float, help="bottom strips' relative length lambda_B [-] "
                   "(default 1.05)")
    p.add_argument("--segments", type=int, help="number of 30 mm segments (default 4)")
    p.add_argument("--model", choices=MODELS, default="bar-hinge", help="reduced-order model "
                   "(default bar-hinge)")
    p.add_argument("--config", help="TOML case file; sections: " + ", ".join(
        f.name for f in dataclasses.fields(BeamConfig)))
    p.add_argument("--out", default="results/beam", help="output folder (default results/beam)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")


def config_from_args(args: argparse.Namespace) -> BeamConfig:
    cfg = config_from_toml(args.config)
    run = {k: v for k, v in {"lambda_top": args.lambda_top,
                             "lambda_bottom": args.lambda_bottom}.items() if v is not None}
    geometry = {"segments": args.segments} if args.segments is not None else {}
    return dataclasses.replace(cfg, run=with_overrides(cfg.run, run, "run"),
                               geometry=with_overrides(cfg.geometry, geometry, "geometry"))


def main(args: argparse.Namespace) -> int:
    cfg = config_from_args(args)
    summary = run_beam(cfg, pathlib.Path(args.out), progress=not args.quiet)
    r = summary["results"]
    print(f"lcefem: beam ({args.model}) lambda_T = {cfg.run.lambda_top:g}, lambda_B = "
          f"{cfg.run.lambda_bottom:g}, {cfg.geometry.segments} segments: curvature "
          f"{r['curvature [1/mm]']:.5f} 1/mm (Eq. 2: {r['eq2 curvature [1/mm]']:.5f} 1/mm); "
          f"{summary['increments']} increments, {summary['newton_iterations']} Newton iterations, "
          f"{summary['wall_time [s]']:.1f} s; results in {args.out}")
    return 0
