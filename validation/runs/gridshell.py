"""The robotic surface (seed 001, Fig. 4, 5): the n x n gridshell in the bar-and-hinge model, driven
by strip lambdas, a published recipe or coil currents.

``lcefem run gridshell [--shape dome|saddle|cylinder|table | --recipe NAME | --lambda Tx=1.33,...
| --current Tx=0.04,...] [--support clamp|rollers|table] [--thermal-model segment|eq1]
[--ribbons N] [--config FILE.toml] [--out DIR] [--quiet]``

Selections (``--lambda``/``--current`` keys, applied in order): channels Tx, Ty, Bx, By (seed 001,
Fig. 4A), T / B (a layer), families XD, YD, XU, YU, groups XD1..YU3, half planes like XD:x<70.5,
or strip ids (see lcefem.meshes.gridshell). Unnamed strips stay as built (lambda_N = 1.4; current 0).
``--shape`` takes the paper's Fig. 4 lambdas (with ``--current``-route twins in the case
``gridshell_shapes_bh``); ``--recipe`` a published recipe (rest fractions P0) with its published
support. Case file sections: run (shape, recipe, support), lambda, current (tables of selection =
value), and the parameter sections geometry, layout, mesh, kapton, lce, glue, strip_contact, contact,
weight, current_route, solver, path.

Outputs in --out DIR: summary.json (resolved configuration, per-strip lambdas, centre curvatures by
both measures with their sign convention, z range, increments, Newton iterations, wall time),
nodes.csv (node id, as-built and final coordinates [mm]), gridshell.png (3D render, junction centres
marked), history.csv (one row per converged
increment), gridshell.pvd + gridshell_steps/*.vtp (ParaView: N5B8 ribbon triangles, strip and glue
bars; displacement, element kind, axial force). Files carry .part names until the run completes; a
run that stops leaves *.partial.* files, last_converged.vtp and failure.json (exit code 3).
"""

from __future__ import annotations

import argparse
import dataclasses
import pathlib
import sys
import time
from dataclasses import dataclass, field

import numpy as np

from lcefem.meshes.composite_beam import BeamBarHingeMesh, CompositeBeamGeometry
from lcefem.meshes.gridshell import GridshellLayout, build_gridshell_bar_hinge
from lcefem.models import bar_hinge as law
from lcefem.models.errors import ConvergenceError, InputError
from lcefem.models.parameters import check, describe, param, with_overrides
from lcefem.solvers.bar_hinge import NewtonOptions, PathOptions
from lcefem.validation import gridshell_bh as gs
from lcefem.validation.bar_hinge_io import BarHingeVTK, CSVHistory, write_json
from lcefem.validation.config import load_toml

COLUMNS = ["load factor [-]", "circle kappa_x [1/mm]", "circle kappa_y [1/mm]", "quad kappa_x [1/mm]",
           "quad kappa_y [1/mm]", "z range [mm]", "newton iterations [-]"]
SIGN = ("kappa = d^2 w/ds^2 with w along the centre junction's normal on the top strips' side: "
        "negative for a dome (cap), positive for a bowl (seed 001: dome negative)")


@dataclass(frozen=True)
class GridshellRun:
    """What the experimenter chooses: a named shape or recipe, and the support."""

    shape: str = param("", "-", "one of the paper's Fig. 4 shapes: " + ", ".join(gs.SHAPES)
                       + " (seed 001; lambdas per channel)")
    recipe: str = param("", "-", "one of the published recipes: " + ", ".join(gs.RECIPES)
                        + " (" + gs.RECIPE_SOURCE + ")")
    support: str = param("", "-", "clamp, rollers or table (default: the published support of the "
                         "shape/recipe, rollers otherwise)")

    def checked(self) -> "GridshellRun":
        if self.shape and self.shape not in gs.SHAPES:
            raise InputError(f"run.shape = {self.shape!r}: allowed {', '.join(gs.SHAPES)}")
        if self.recipe and self.recipe not in gs.RECIPES:
            raise InputError(f"run.recipe = {self.recipe!r}: allowed {', '.join(gs.RECIPES)}")
        if self.shape and self.recipe:
            raise InputError("run.shape and run.recipe: give one of them")
        if self.support and self.support not in gs.SUPPORTS:
            raise InputError(f"run.support = {self.support!r}: allowed {', '.join(gs.SUPPORTS)}")
        return self


@dataclass(frozen=True)
class GridshellConfig:
    run: GridshellRun = field(default_factory=GridshellRun)
    geometry: CompositeBeamGeometry = field(default_factory=CompositeBeamGeometry)
    layout: GridshellLayout = field(default_factory=GridshellLayout)
    mesh: BeamBarHingeMesh = field(default_factory=BeamBarHingeMesh)
    kapton: law.KaptonBarHinge = field(default_factory=law.KaptonBarHinge)
    lce: law.LCEStripBars = field(default_factory=law.LCEStripBars)
    glue: law.GlueBars = field(default_factory=law.GlueBars)
    strip_contact: law.StripContactSprings = field(default_factory=law.StripContactSprings)
    contact: law.StripContact = field(default_factory=law.StripContact)
    weight: gs.SurfaceWeight = field(default_factory=gs.SurfaceWeight)
    current_route: gs.CurrentRoute = field(default_factory=gs.CurrentRoute)
    solver: NewtonOptions = field(default_factory=lambda: gs.GRIDSHELL_NEWTON)
    path: PathOptions = field(default_factory=lambda: gs.GRIDSHELL_PATH)
    lambdas: dict = field(default_factory=dict)  # selection -> lambda [-]
    currents: dict = field(default_factory=dict)  # selection -> current [A]

    PARAM_SECTIONS = ("run", "geometry", "layout", "mesh", "kapton", "lce", "glue", "strip_contact",
                      "contact", "weight", "current_route", "solver", "path")

    def validated(self) -> "GridshellConfig":
        for name in self.PARAM_SECTIONS:
            check(getattr(self, name), name)
        self.run.checked()
        self.layout.checked()
        self.mesh.checked()
        self.current_route.checked()
        named = bool(self.run.shape or self.run.recipe)
        if named and (self.lambdas or self.currents):
            raise InputError("--lambda/--current: not with --shape or --recipe (they set the strips)")
        if self.lambdas and self.currents:
            raise InputError("--lambda and --current: give one of them")
        for sel, v in {**self.lambdas, **self.currents}.items():
            if not isinstance(v, (int, float)) or isinstance(v, bool):
                raise InputError(f"{sel} = {v!r}: must be a number")
        for sel, v in self.currents.items():
            if not 0.0 <= v <= 1.0:
                raise InputError(f"current {sel} = {v}: must be between 0 and 1 A")
        return self

    @property
    def materials(self) -> gs.BarHingeMaterials:
        return gs.BarHingeMaterials(self.kapton, self.lce, self.glue, self.strip_contact, self.contact)

    @property
    def support(self) -> str:
        if self.run.support:
            return self.run.support
        if self.run.shape:
            return gs.SHAPES[self.run.shape]["support"]
        if self.run.recipe:
            return gs.RECIPES[self.run.recipe][1]
        return "rollers"

    def resolved(self) -> dict:
        out = {name: describe(getattr(self, name)) for name in self.PARAM_SECTIONS}
        out["current_route"]["segment"]["value"] = describe(self.current_route.segment)
        out["lambda"] = dict(self.lambdas)
        out["current"] = dict(self.currents)
        out["support (resolved)"] = self.support
        return out


def config_from_toml(path, base: GridshellConfig | None = None) -> GridshellConfig:
    base = base or GridshellConfig()
    data = load_toml(path, {*GridshellConfig.PARAM_SECTIONS, "lambda", "current"})
    kw = {name: with_overrides(getattr(base, name), table, name) for name, table in data.items()
          if name in GridshellConfig.PARAM_SECTIONS}
    if "lambda" in data:
        kw["lambdas"] = dict(data["lambda"])
    if "current" in data:
        kw["currents"] = dict(data["current"])
    return dataclasses.replace(base, **kw)


def parse_assignments(text: str | None, name: str) -> dict:
    """'Tx=1.33,Ty=1.05' -> {'Tx': 1.33, 'Ty': 1.05} (integer keys are strip ids)."""
    if not text:
        return {}
    out = {}
    for item in text.split(","):
        if "=" not in item:
            raise InputError(f"--{name} {text!r}: expected KEY=VALUE[,KEY=VALUE...], e.g. Tx=1.33")
        key, value = (s.strip() for s in item.split("=", 1))
        try:
            val = float(value)
        except ValueError:
            raise InputError(f"--{name} {key}={value!r}: not a number") from None
        out[int(key) if key.isdigit() else key] = val
    return out


def strip_targets(cfg: GridshellConfig, structure) -> tuple[dict, dict]:
    """(rest fractions per bar by group, description of the drive) for the configuration."""
    lam_n = cfg.lce.lambda_N
    if cfg.run.recipe:
        recipe = gs.RECIPES[cfg.run.recipe][0]
        return gs.targets_from_recipe(structure, recipe), {"recipe": cfg.run.recipe, "P0": recipe}
    if cfg.run.shape:
        lambdas = gs.SHAPES[cfg.run.shape]["lambdas"]
        return gs.targets_from_lambdas(structure, lambdas, lam_n), {"shape": cfg.run.shape,
                                                                   "lambda": lambdas}
    if cfg.currents:
        lambdas = gs.lambda_assignments_from_currents(cfg.currents, cfg.current_route, lam_n)
        return gs.targets_from_lambdas(structure, lambdas, lam_n, "current"), {
            "current [A]": cfg.currents, "lambda (from current)": lambdas,
            "thermal model": cfg.current_route.thermal_model}
    return gs.targets_from_lambdas(structure, cfg.lambdas, lam_n), {"lambda": cfg.lambdas}


def write_nodes_csv(path: pathlib.Path, reference: np.ndarray, x: np.ndarray) -> None:
    """Node table with units: id, as-built x0, y0, z0 and final x, y, z [mm] (atomic)."""
    path = pathlib.Path(path)
    tmp = path.with_name(path.name + ".part")
    data = np.column_stack([np.arange(reference.shape[0]), reference, x])
    np.savetxt(tmp, data, delimiter=",", fmt=["%d"] + ["%.9g"] * 6, comments="",
               header="node id [-],x0 [mm],y0 [mm],z0 [mm],x [mm],y [mm],z [mm]")
    tmp.replace(path)


def run_gridshell(cfg: GridshellConfig, out: pathlib.Path, progress: bool = True) -> dict:
    """Run and write the outputs (module docstring); returns the summary."""
    cfg = cfg.validated()
    out = pathlib.Path(out)
    if out.exists() and not out.is_dir():
        raise InputError(f"out = {str(out)!r}: exists and is not a directory")
    out.mkdir(parents=True, exist_ok=True)
    structure = build_gridshell_bar_hinge(cfg.geometry, cfg.layout, cfg.mesh)
    targets, drive = strip_targets(cfg, structure)
    setup = gs.setup_gridshell(targets, cfg.support, cfg.geometry, cfg.layout, cfg.mesh, cfg.materials,
                               cfg.weight, structure=structure)
    model = setup.model
    vtk = BarHingeVTK(out, "gridshell", structure)
    history = CSVHistory(out / "history.csv", COLUMNS)
    holder: dict = {}

    def on_step(state) -> None:
        summ = gs.shape_summary(structure, state.x)
        history.append({"load factor [-]": state.t, "circle kappa_x [1/mm]": summ["circle_x"],
                        "circle kappa_y [1/mm]": summ["circle_y"],
                        "quad kappa_x [1/mm]": summ.get("quad_kx", float("nan")),
                        "quad kappa_y [1/mm]": summ.get("quad_ky", float("nan")),
                        "z range [mm]": summ["z_range [mm]"], "newton iterations [-]": state.iterations})
        vtk.write(state.t, state.x, model.bar_forces(state.x))
        holder["last"] = state

    bar = None
    if progress:
        from tqdm import tqdm
        bar = tqdm(total=1.0, desc="gridshell", unit="load", file=sys.stderr,
                   bar_format="{l_bar}{bar}| {n:.3f}/{total:.0f} [{elapsed}<{remaining}]")
    started = time.perf_counter()
    try:
        solution = gs.solve_gridshell(setup, newton_options=cfg.solver, path=cfg.path, on_step=on_step,
                                      progress=(lambda t: bar.update(t - bar.n)) if bar else None)
    except ConvergenceError as exc:
        last = holder.get("last")
        if last is not None:
            vtk.write_single(out / "last_converged.vtp", last.x, model.bar_forces(last.x))
        vtk.finalize(complete=False)
        history.finalize(complete=False)
        write_json(out / "failure.json", {
            "status": "failed", "where": exc.where, "reason": exc.reason,
            "last_converged_load_factor [-]": None if last is None else last.t,
            "note": "history.partial.csv and gridshell_steps.partial/ hold the converged steps; "
                    "last_converged.vtp the last one", "config": cfg.resolved()})
        raise
    finally:
        if bar is not None:
            bar.close()
    wall = time.perf_counter() - started
    vtk.finalize()
    history.finalize()
    x = solution.final.x
    write_nodes_csv(out / "nodes.csv", structure.nodes, x)
    final_fraction = model.rest_fractions()
    reached = all(np.array_equal(final_fraction[g], setup.targets[g]) for g in setup.targets)
    lam_n = cfg.lce.lambda_N
    strips = structure.info["strips"]
    per_strip = {}
    for g, ids in structure.info["strip_of_bar"].items():
        for sid, f in zip(ids, setup.targets[g]):
            per_strip.setdefault(int(sid), []).append(float(f) * lam_n)
    summary = {
        "status": "completed", "model": "bar-hinge gridshell", "drive": drive, "config": cfg.resolved(),
        "support": cfg.support,
        "strips": [{"id": s.id, "group": s.group, "channel": s.channel, "midpoint [mm]": s.midpoint,
                    "lambda [-]": float(np.mean(per_strip[s.id]))} for s in strips],
        "results": {**gs.shape_summary(structure, x), "sign convention": SIGN,
                    "target reached exactly": bool(reached)},
        "dofs": int(model.ndof), "nodes": int(structure.num_nodes),
        "increments": len(solution.path.states) - 1,
        "newton_iterations": int(sum(solution.path.newton_iterations)),
        "failed_increments": solution.path.failed_increments, "wall_time [s]": wall,
    }
    from lcefem.validation.gridshell_plots import render_gridshell
    render_gridshell(out / "gridshell.png", structure, x,
                     f"gridshell {drive.get('shape') or drive.get('recipe') or ''} ({cfg.support})")
    write_json(out / "summary.json", summary)
    return summary


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--shape", help="the paper's Fig. 4 shape: " + ", ".join(gs.SHAPES))
    p.add_argument("--recipe", help="a published recipe: " + ", ".join(gs.RECIPES))
    p.add_argument("--lambda", dest="lambdas", help="lambdas [-] per selection, e.g. "
                   "Tx=1.33,Ty=1.33,Bx=1.05,By=1.05 (1 isotropic .. 1.4 as built)")
    p.add_argument("--current", dest="currents", help="currents [A] per selection, e.g. "
                   "Tx=0.04,Ty=0.04,Bx=0.07,By=0.07")
    p.add_argument("--thermal-model", choices=gs.THERMAL_MODELS, help="current -> lambda: 'segment' "
                   "(our lumped 25 ohm segment, default) or 'eq1' (the paper's Eq. 1 estimate)")
    p.add_argument("--support", choices=gs.SUPPORTS, help="supports (default: the published ones)")
    p.add_argument("--ribbons", type=int, help="ribbons per direction (default 3)")
    p.add_argument("--config", help="TOML case file (sections: run, lambda, current, "
                   + ", ".join(GridshellConfig.PARAM_SECTIONS[1:]) + ")")
    p.add_argument("--out", default="results/gridshell", help="output folder (default results/gridshell)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")


def config_from_args(args: argparse.Namespace) -> GridshellConfig:
    cfg = config_from_toml(args.config)
    run = {k: v for k, v in {"shape": args.shape, "recipe": args.recipe,
                             "support": args.support}.items() if v is not None}
    kw = {"run": with_overrides(cfg.run, run, "run")}
    if args.lambdas is not None:
        kw["lambdas"] = parse_assignments(args.lambdas, "lambda")
    if args.currents is not None:
        kw["currents"] = parse_assignments(args.currents, "current")
    if args.thermal_model is not None:
        kw["current_route"] = dataclasses.replace(cfg.current_route, thermal_model=args.thermal_model)
    if args.ribbons is not None:
        kw["layout"] = with_overrides(cfg.layout, {"ribbons": args.ribbons}, "layout")
    return dataclasses.replace(cfg, **kw)


def main(args: argparse.Namespace) -> int:
    cfg = config_from_args(args)
    summary = run_gridshell(cfg, pathlib.Path(args.out), progress=not args.quiet)
    r = summary["results"]
    quad = (f", quadratic fit {r['quad_kx']:.4f}/{r['quad_ky']:.4f}" if "quad_kx" in r else "")
    print(f"lcefem: gridshell ({summary['support']}): centre curvature x/y [1/mm]: circle "
          f"{r['circle_x']:.4f}/{r['circle_y']:.4f}{quad}; z range {r['z_range [mm]']:.2f} mm; "
          f"{summary['increments']} increments, {summary['newton_iterations']} Newton iterations, "
          f"{summary['wall_time [s]']:.1f} s; results in {args.out}")
    return 0
