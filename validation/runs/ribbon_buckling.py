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

With ``--model fe`` the specimen is a 3D neo-Hookean solid (datasheet E and nu) meshed with quadratic
hexahedra (one through the thickness; half model about y = W/2); the critical load comes from the
linearised buckling eigenproblem about the straight state (SLEPc), the path is seeded with the first
eigenmode (amplitude 1e-3 of the length); outputs: displacement.bp (VTX), history.csv,
ribbon_buckling.png, summary.json (also the plate-strip Euler load with E/(1 - nu^2) and the free
length and modulus that would give the measured 0.18 N).

Outputs in --out DIR (bar-hinge): ribbon.pvd + ribbon_steps/*.vtp, history.csv (compression [-], end
shortening [mm], force [N], Newton iterations), ribbon_buckling.png, summary.json. Files carry
.part names until complete; a failed run leaves *.partial.* files, last_converged.vtp and
failure.json.
"""

from __future__ import annotations

import argparse
import dataclasses
import pathlib
import time
from dataclasses import dataclass, field

import numpy as np

from lcefem.meshes.kapton_ribbon import KaptonBarHingeMesh, KaptonSpecimenGeometry
from lcefem.models import bar_hinge as law
from lcefem.models import buckling
from lcefem.models.errors import InputError
from lcefem.models.parameters import param
from lcefem.solvers.bar_hinge import NewtonOptions, PathOptions
from lcefem.solvers.run import Progress, Run, add_out_arguments, check_config, resolved
from lcefem.solvers.problems import kapton_specimen_bh as kapton_bh
from lcefem.validation import plots
from lcefem.solvers.exports import bar_hinge_run
from lcefem.validation.config import config_from_toml, override
from lcefem.validation.runs import parallel_if_fe
from lcefem.validation.reference_data import reference
from lcefem.validation.commands import MODELS

COLUMNS = ["compression [-]", "end shortening [mm]", "force [N]", "newton iterations [-]"]


@dataclass(frozen=True)
class KaptonSpecimenRun:
    """What the experimenter sets: how far to shorten the specimen."""

    compression: float = param(0.5, "-", "seed 001 Fig. 2G: compression up to 50 % (end shortening "
                               "over length)", positive=True, maximum=0.9)


@dataclass(frozen=True)
class KaptonSpecimenConfig:
    run: KaptonSpecimenRun = field(default_factory=KaptonSpecimenRun)
    specimen: KaptonSpecimenGeometry = field(default_factory=KaptonSpecimenGeometry)
    mesh: KaptonBarHingeMesh = field(default_factory=KaptonBarHingeMesh)
    kapton: law.KaptonBarHinge = field(default_factory=law.KaptonBarHinge)
    solver: NewtonOptions = field(default_factory=NewtonOptions)
    path: PathOptions = field(default_factory=lambda: kapton_bh.SPECIMEN_PATH)

    def validated(self) -> "KaptonSpecimenConfig":
        check_config(self)
        self.specimen.checked()
        self.mesh.checked()
        return self

    @property
    def materials(self) -> law.BarHingeMaterials:
        return law.BarHingeMaterials(kapton=self.kapton)

    def resolved(self) -> dict:
        return resolved(self)


def closed_forms(cfg: KaptonSpecimenConfig) -> dict[str, float]:
    """Euler loads [N] of the specimen: datasheet EI, with the 5.5 factor, and the chain's own EI."""
    spec, kap = cfg.specimen, cfg.kapton
    ei = kap.youngs_modulus * spec.second_moment
    k = kap.hinge_stiffness(spec.thickness)
    ei_chain = law.n5b8_ribbon_bending_stiffness(k, spec.length / cfg.mesh.panels, spec.width)
    return {"Euler, E I (datasheet E)": buckling.euler_fixed_fixed(ei, spec.length),
            f"Euler, {kap.bending_factor:g} E I": buckling.euler_fixed_fixed(kap.bending_factor * ei,
                                                                           spec.length),
            "Euler, bar-and-hinge chain EI": buckling.euler_fixed_fixed(ei_chain, spec.length)}


def run_ribbon(config: KaptonSpecimenConfig, out: pathlib.Path, progress: bool = True) -> dict:
    """Run the bar-and-hinge buckling test and write its outputs; returns the summary."""
    cfg = config.validated()
    out = pathlib.Path(out)
    setup = kapton_bh.setup_specimen(cfg.run.compression, cfg.specimen, cfg.mesh, cfg.materials)
    model, length = setup.model, cfg.specimen.length

    def row(state) -> dict:
        c = state.t * cfg.run.compression
        return {"compression [-]": c, "end shortening [mm]": c * length, "force [N]": setup.force(state),
                "newton iterations [-]": state.iterations}

    bar = Progress(100 * cfg.run.compression, "ribbon buckling", "%", enabled=progress)
    started = time.perf_counter()
    with bar_hinge_run(out, "ribbon", setup.structure, model, config=cfg.resolved(), columns=COLUMNS,
                       row=row, progress=bar) as (run, on_step):
        solution = kapton_bh.solve_specimen_buckling(
            newton_options=cfg.solver, path=cfg.path, on_step=on_step,
            progress=lambda t: bar.to(100 * t * cfg.run.compression), setup=setup)
        return run.complete(_bar_hinge_results(cfg, out, solution, model, started))


def _bar_hinge_results(cfg, out, solution, model, started) -> dict:
    p_cr, shortening_cr = kapton_bh.critical_load(cfg.specimen, cfg.mesh, cfg.materials)
    wall = time.perf_counter() - started
    measured = reference("ribbon.buckling_load")
    euler = closed_forms(cfg)
    compression, force = solution.compression, solution.force
    c_el = np.linspace(0.0, compression[-1], 60)
    elastica = np.array([buckling.elastica_force_ratio(c) for c in c_el])
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
    return {
        "model": "bar-hinge",
        "results": {
            "critical load [N]": p_cr, "critical end shortening [mm]": shortening_cr,
            "measured critical load [N]": measured.value,
            **{f"{k} [N]": v for k, v in euler.items()},
            "force at final compression [N]": float(force[-1]),
            "final compression [-]": float(compression[-1]),
            "force ratio final / critical [-]": final_ratio,
            "elastica force ratio at final compression [-]":
                buckling.elastica_force_ratio(float(compression[-1])),
        },
        "dofs": int(model.ndof), "increments": len(solution.path.states) - 1,
        "newton_iterations": int(sum(solution.path.newton_iterations)),
        "failed_increments": solution.path.failed_increments, "wall_time [s]": wall,
    }


# -- FE model ------------------------------------------------------------------------------------
FE_COLUMNS = ["compression [-]", "end shortening [mm]", "force [N]", "mid-span deflection [mm]",
              "newton iterations [-]"]


def _fe_config_class():
    from lcefem.meshes.kapton_ribbon import KaptonFEMesh
    from lcefem.models.hyperelastic import NeoHookeanSolid
    from lcefem.solvers.problems import kapton_specimen

    @dataclass(frozen=True)
    class KaptonSpecimenFEConfig:
        run: KaptonSpecimenRun = field(default_factory=KaptonSpecimenRun)
        specimen: KaptonSpecimenGeometry = field(default_factory=KaptonSpecimenGeometry)
        mesh: KaptonFEMesh = field(default_factory=KaptonFEMesh)
        kapton: NeoHookeanSolid = field(default_factory=NeoHookeanSolid)
        path: kapton_specimen.KaptonSpecimenFEPath = field(default_factory=kapton_specimen.KaptonSpecimenFEPath)

        def validated(self):
            check_config(self)
            self.specimen.checked()
            self.mesh.checked()
            return self

        def resolved(self) -> dict:
            return resolved(self)

    return KaptonSpecimenFEConfig


def run_ribbon_fe(cfg, out: pathlib.Path, progress: bool = True) -> dict:
    """The FE buckling test (critical load, imperfect path to the final compression)."""
    from lcefem.solvers.exports import FieldExport
    from lcefem.solvers.problems import kapton_specimen

    cfg = cfg.validated()
    out = pathlib.Path(out)
    started = time.perf_counter()
    model = kapton_specimen.KaptonSpecimenFE(cfg.specimen, cfg.mesh, cfg.kapton)
    critical = model.critical_load()
    length = cfg.specimen.length
    model.add_imperfection(critical.mode, cfg.path.imperfection * length)
    schedule = model.compression_schedule(critical.shortening / length, cfg.run.compression, cfg.path)
    bar = Progress(100 * cfg.run.compression, "ribbon buckling (FE)", "%", enabled=progress)
    with Run(out, config=cfg.resolved(), columns=FE_COLUMNS, progress=bar) as run:
        fields = run.output(FieldExport(out / "displacement.bp", [model.u], model.tmesh.mesh.comm))

        def on_step(c: float, its: int) -> None:
            run.record({"compression [-]": c, "end shortening [mm]": c * length, "force [N]": model.force(),
                        "mid-span deflection [mm]": model.mid_deflection(), "newton iterations [-]": its},
                       where=f"compression {c:.4g}", at=100 * c)
            fields.write(c)

        on_step(0.0, 0)
        follower = model.follow(schedule, on_step=on_step)
        return run.complete(_fe_results(cfg, out, model, critical, run.history, schedule, follower, started))


def _fe_results(cfg, out, model, critical, history, schedule, follower, started) -> dict:
    wall = time.perf_counter() - started
    measured = reference("ribbon.buckling_load")
    closed = buckling.specimen_closed_forms(cfg.specimen, cfg.kapton.youngs_modulus,
                                            cfg.kapton.poisson_ratio, measured.value)
    c, f = history.column("compression [-]"), history.column("force [N]")
    c_el = np.linspace(0.0, c[-1], 60)
    elastica = np.array([buckling.elastica_force_ratio(x) for x in c_el])
    euler = closed["Euler, E I (datasheet E) [N]"]
    plate = closed["Euler, plate strip E I/(1 - nu^2) [N]"]
    plots.comparison_plot(
        out / "ribbon_buckling.png",
        [plots.Series(100 * c, f, f"3D FE (Q2, {model.ndofs} DOFs, mode imperfection)", "model"),
         plots.Series(100 * c_el, critical.force * elastica, "elastica x P_cr (FE)", "closed form")],
        xlabel="compression (end shortening / length) [%]", ylabel="compressive force [N]",
        hlines=[plots.Line(measured.value, f"measured critical load {measured.value:g} N", "experiment"),
                plots.Line(critical.force, f"P_cr FE {critical.force:.4f} N", "model"),
                plots.Line(euler, f"Euler E I = {euler:.4f} N", "closed form"),
                plots.Line(plate, f"Euler E I/(1-nu^2) = {plate:.4f} N", "reference")],
        title="Fixed-fixed Kapton ribbon 36 x 7 x 0.127 mm (3D FE)",
        sources=[measured.cite, "Euler: 4 pi^2 EI/L^2, fixed-fixed", "elastica: Timoshenko & Gere 1961"])
    at = {p: float(np.interp(p, c, f)) for p in (0.1, 0.25, 0.5) if p <= c[-1] + 1e-12}
    return {
        "model": "fe",
        "results": {
            "critical load [N]": critical.force, "critical end shortening [mm]": critical.shortening,
            "measured critical load [N]": measured.value, **closed,
            **{f"force at {100 * p:g} % compression [N]": v for p, v in at.items()},
            "force at final compression [N]": float(f[-1]), "final compression [-]": float(c[-1]),
            "force ratio final / critical [-]": float(f[-1] / critical.force),
            "elastica force ratio at final compression [-]": buckling.elastica_force_ratio(float(c[-1])),
        },
        "dofs": model.ndofs, "increments": len(schedule), "newton_iterations": follower.iterations,
        "cut_steps": follower.cuts, "wall_time [s]": wall,
    }


def fe_config_from_args(args: argparse.Namespace):
    cfg = config_from_toml(args.config, _fe_config_class()())
    cfg = override(cfg, "run", compression=args.compression)
    return override(cfg, "mesh", level=args.mesh_level)


# -- command line -------------------------------------------------------------------------------
def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--compression", type=float, help="final end shortening / length [-] (default 0.5)")
    p.add_argument("--model", choices=MODELS, default="bar-hinge", help="bar-and-hinge model or 3D FE "
                   "(default bar-hinge)")
    p.add_argument("--mesh-level", type=int, help="FE refinement level (in-plane element size "
                   "1 mm/(level+1))")
    p.add_argument("--config", help="TOML case file; sections: " + ", ".join(
        f.name for f in dataclasses.fields(KaptonSpecimenConfig)) + " (bar-hinge); run, specimen, mesh, kapton, "
        "path (fe)")
    add_out_arguments(p, "results/ribbon-buckling")


def config_from_args(args: argparse.Namespace) -> KaptonSpecimenConfig:
    return override(config_from_toml(args.config, KaptonSpecimenConfig()), "run", compression=args.compression)


PARALLEL = parallel_if_fe


def prepare(args: argparse.Namespace):
    """The validated configuration of the chosen model (before the output folder is touched)."""
    if args.model == "fe":
        return fe_config_from_args(args).validated()
    if getattr(args, "mesh_level", None) is not None:
        raise InputError("--mesh-level: only with --model fe")
    return config_from_args(args).validated()


def main(args: argparse.Namespace) -> int:
    cfg = args.prepared
    if args.model == "fe":
        summary = run_ribbon_fe(cfg, args.out, progress=not args.quiet)
        r = summary["results"]
        print(f"lcefem: ribbon buckling (fe, {summary['dofs']} DOFs): critical load "
              f"{r['critical load [N]']:.4f} N (measured {r['measured critical load [N]']:g} N; Euler E I "
              f"{r['Euler, E I (datasheet E) [N]']:.4f} N, plate strip "
              f"{r['Euler, plate strip E I/(1 - nu^2) [N]']:.4f} N); force at "
              f"{100 * r['final compression [-]']:.0f} % compression {r['force at final compression [N]']:.4f} N; "
              f"{summary['wall_time [s]']:.1f} s; results in {args.out}")
        return 0
    summary = run_ribbon(cfg, args.out, progress=not args.quiet)
    r = summary["results"]
    print(f"lcefem: ribbon buckling ({args.model}): critical load {r['critical load [N]']:.4f} N "
          f"(measured {r['measured critical load [N]']:g} N; Euler E I "
          f"{r['Euler, E I (datasheet E) [N]']:.4f} N); force at {100 * r['final compression [-]']:.0f} % "
          f"compression {r['force at final compression [N]']:.4f} N; {summary['wall_time [s]']:.1f} s; "
          f"results in {args.out}")
    return 0
