"""The passive Kapton ribbon's buckling test (seed 001, Fig. 2G): a 36 x 7 x 0.127 mm specimen,
fixed-fixed, shortened by a prescribed end displacement.

``lcefem run ribbon-buckling [--compression 0.5] [--out DIR] [--config FILE.toml] [--quiet]
[--model bar-hinge]``

The run follows the force-compression path of the slightly imperfect specimen (first fixed-fixed
mode, amplitude 1e-3 of the length), and finds the critical load of the perfect specimen as the
end shortening where the tangent stiffness of the straight state loses positive definiteness. It
compares them with the measured 0.18 N, with the Euler load 4 pi^2 EI/L^2 of the same specimen
(datasheet E), with the Euler load of the bar-and-hinge chain's own bending stiffness (closed form,
lcefem.validation.bar_hinge_studies.n5b8_ribbon_bending_stiffness), and the post-buckling force
with the inextensible elastica.

Outputs in --out DIR: ribbon.pvd + ribbon_steps/*.vtp, history.csv (compression [-], end
shortening [mm], force [N], Newton iterations), ribbon_buckling.png, summary.json. Files carry
.part names until complete; a failed run leaves *.partial.* files, last_converged.vtp and
failure.json.
"""

from __future__ import annotations

import argparse
import dataclasses
import pathlib
import sys
import time
from dataclasses import dataclass, field

import numpy as np

from lcefem.meshes.kapton_ribbon import RibbonBarHingeMesh, RibbonSpecimen
from lcefem.models import bar_hinge as law
from lcefem.models.errors import ConvergenceError
from lcefem.models.parameters import check, describe, param, with_overrides
from lcefem.solvers.bar_hinge import NewtonOptions, PathOptions
from lcefem.validation import bar_hinge_studies as studies
from lcefem.validation import plots
from lcefem.validation.bar_hinge_io import BarHingeVTK, CSVHistory, write_json
from lcefem.validation.config import load_toml
from lcefem.validation.reference_data import reference
from lcefem.validation.runs.beam import MODELS, prepare_out

COLUMNS = ["compression [-]", "end shortening [mm]", "force [N]", "newton iterations [-]"]


@dataclass(frozen=True)
class RibbonRun:
    """What the experimenter sets: how far to shorten the specimen."""

    compression: float = param(0.5, "-", "seed 001 Fig. 2G: compression up to 50 % (end shortening "
                               "over length)", positive=True, maximum=0.9)


@dataclass(frozen=True)
class RibbonConfig:
    run: RibbonRun = field(default_factory=RibbonRun)
    specimen: RibbonSpecimen = field(default_factory=RibbonSpecimen)
    mesh: RibbonBarHingeMesh = field(default_factory=RibbonBarHingeMesh)
    kapton: law.KaptonBarHinge = field(default_factory=law.KaptonBarHinge)
    solver: NewtonOptions = field(default_factory=NewtonOptions)
    path: PathOptions = field(default_factory=lambda: studies.RIBBON_PATH)

    def validated(self) -> "RibbonConfig":
        for f in dataclasses.fields(self):
            check(getattr(self, f.name), f.name)
        self.specimen.checked()
        self.mesh.checked()
        return self

    @property
    def materials(self) -> studies.BarHingeMaterials:
        return studies.BarHingeMaterials(kapton=self.kapton)

    def resolved(self) -> dict:
        return {f.name: describe(getattr(self, f.name)) for f in dataclasses.fields(self)}


def config_from_toml(path, base: RibbonConfig = RibbonConfig()) -> RibbonConfig:
    data = load_toml(path, {f.name for f in dataclasses.fields(RibbonConfig)})
    return dataclasses.replace(base, **{name: with_overrides(getattr(base, name), table, name)
                                        for name, table in data.items()})


def closed_forms(cfg: RibbonConfig) -> dict[str, float]:
    """Euler loads [N] of the specimen: datasheet EI, with the 5.5 factor, and the chain's own EI."""
    spec, kap = cfg.specimen, cfg.kapton
    ei = kap.youngs_modulus * spec.second_moment
    k = kap.hinge_stiffness(spec.thickness)
    ei_chain = studies.n5b8_ribbon_bending_stiffness(k, spec.length / cfg.mesh.panels, spec.width)
    return {"Euler, E I (datasheet E)": studies.euler_fixed_fixed(ei, spec.length),
            f"Euler, {kap.bending_factor:g} E I": studies.euler_fixed_fixed(kap.bending_factor * ei,
                                                                           spec.length),
            "Euler, bar-and-hinge chain EI": studies.euler_fixed_fixed(ei_chain, spec.length)}


def run_ribbon(config: RibbonConfig, out: pathlib.Path, progress: bool = True) -> dict:
    """Run the bar-and-hinge buckling test and write its outputs; returns the summary."""
    cfg = config.validated()
    out = prepare_out(out)
    setup = studies.setup_ribbon(cfg.run.compression, cfg.specimen, cfg.mesh, cfg.materials)
    model, length = setup.model, cfg.specimen.length
    vtk = BarHingeVTK(out, "ribbon", setup.structure)
    history = CSVHistory(out / "history.csv", COLUMNS)
    holder: dict = {}

    def on_step(state) -> None:
        c = state.t * cfg.run.compression
        history.append({"compression [-]": c, "end shortening [mm]": c * length,
                        "force [N]": setup.force(state), "newton iterations [-]": state.iterations})
        vtk.write(state.t, state.x, model.bar_forces(state.x))
        holder["last"] = state

    bar = None
    if progress:
        from tqdm import tqdm
        bar = tqdm(total=100 * cfg.run.compression, desc="ribbon buckling", unit="%",
                   bar_format="{l_bar}{bar}| {n:.1f}/{total:.0f} % [{elapsed}<{remaining}]",
                   file=sys.stderr)

    def advance(t: float) -> None:
        if bar is not None:
            bar.update(100 * t * cfg.run.compression - bar.n)

    started = time.perf_counter()
    try:
        solution = studies.solve_ribbon_buckling(newton_options=cfg.solver, path=cfg.path,
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
            "last_converged_compression [-]": None if last is None else last.t * cfg.run.compression,
            "note": "history.partial.csv and ribbon_steps.partial/ hold the converged steps; "
                    "last_converged.vtp the last one", "config": cfg.resolved()})
        raise
    except BaseException:
        if bar is not None:
            bar.close()
        raise
    if bar is not None:
        bar.close()
    p_cr, shortening_cr = studies.critical_load(cfg.specimen, cfg.mesh, cfg.materials)
    wall = time.perf_counter() - started
    vtk.finalize()
    history.finalize()
    measured = reference("ribbon.buckling_load")
    euler = closed_forms(cfg)
    compression, force = solution.compression, solution.force
    c_el = np.linspace(0.0, compression[-1], 60)
    elastica = np.array([studies.elastica_force_ratio(c) for c in c_el])
    src = [measured.cite, "Euler: 4 pi^2 EI/L^2, fixed-fixed", "elastica: Timoshenko & Gere 1961"]
    plots.comparison_plot(
        out / "ribbon_buckling.png",
        [plots.Series(100 * compression, force, f"bar-and-hinge ({cfg.mesh.panels} panels)", "model"),
         plots.Series(100 * c_el, p_cr * elastica, "elastica x P_cr (bar-and-hinge)", "closed form")],
        xlabel="compression (end shortening / length) [%]", ylabel="compressive force [N]",
        hlines=[plots.Line(measured.value, f"measured critical load {measured.value:g} N", "experiment"),
                plots.Line(p_cr, f"P_cr bar-and-hinge {p_cr:.3f} N", "model"),
                *(plots.Line(v, f"{k} = {v:.3f} N", "closed form") for k, v in euler.items())],
        title="Fixed-fixed Kapton ribbon 36 x 7 x 0.127 mm", sources=src)
    final_ratio = float(force[-1] / p_cr)
    summary = {
        "status": "completed", "model": "bar-hinge", "config": cfg.resolved(),
        "results": {
            "critical load [N]": p_cr, "critical end shortening [mm]": shortening_cr,
            "measured critical load [N]": measured.value,
            **{f"{k} [N]": v for k, v in euler.items()},
            "force at final compression [N]": float(force[-1]),
            "final compression [-]": float(compression[-1]),
            "force ratio final / critical [-]": final_ratio,
            "elastica force ratio at final compression [-]":
                studies.elastica_force_ratio(float(compression[-1])),
        },
        "dofs": int(model.ndof), "increments": len(solution.path.states) - 1,
        "newton_iterations": int(sum(solution.path.newton_iterations)),
        "failed_increments": solution.path.failed_increments, "wall_time [s]": wall,
    }
    write_json(out / "summary.json", summary)
    return summary


# -- command line -------------------------------------------------------------------------------
def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--compression", type=float, help="final end shortening / length [-] (default 0.5)")
    p.add_argument("--model", choices=MODELS, default="bar-hinge", help="reduced-order model "
                   "(default bar-hinge)")
    p.add_argument("--config", help="TOML case file; sections: " + ", ".join(
        f.name for f in dataclasses.fields(RibbonConfig)))
    p.add_argument("--out", default="results/ribbon-buckling",
                   help="output folder (default results/ribbon-buckling)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")


def config_from_args(args: argparse.Namespace) -> RibbonConfig:
    cfg = config_from_toml(args.config)
    run = {"compression": args.compression} if args.compression is not None else {}
    return dataclasses.replace(cfg, run=with_overrides(cfg.run, run, "run"))


def main(args: argparse.Namespace) -> int:
    cfg = config_from_args(args)
    summary = run_ribbon(cfg, pathlib.Path(args.out), progress=not args.quiet)
    r = summary["results"]
    print(f"lcefem: ribbon buckling ({args.model}): critical load {r['critical load [N]']:.4f} N "
          f"(measured {r['measured critical load [N]']:g} N; Euler E I "
          f"{r['Euler, E I (datasheet E) [N]']:.4f} N); force at {100 * r['final compression [-]']:.0f} % "
          f"compression {r['force at final compression [N]']:.4f} N; {summary['wall_time [s]']:.1f} s; "
          f"results in {args.out}")
    return 0
