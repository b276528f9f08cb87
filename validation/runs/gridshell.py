"""The robotic surface (seed 001, Fig. 4, 5): the n x n gridshell in the bar-and-hinge model, driven
by strip lambdas, a published recipe or coil currents.

``lcefem run gridshell [--shape dome|saddle|cylinder|table | --recipe NAME | --lambda Tx=1.33,...
| --current Tx=0.04,...] [--support clamp|rollers|table] [--thermal-model segment|eq1]
[--ribbons N] [--config FILE.toml] [--out DIR] [--quiet]``; a programmed sequence of currents:
``lcefem run gridshell --schedule FILE.toml`` (lcefem.validation.gridshell_sequence).

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
run that stops leaves *.partial.* files, last_converged.vtp and failure.json (exit code 3), through
the run skeleton (lcefem.solvers.run.Run).
"""

from __future__ import annotations

import argparse
import dataclasses
import pathlib
import time
from dataclasses import dataclass, field

import numpy as np

from lcefem.meshes.composite_beam import BeamBarHingeMesh, CompositeBeamGeometry
from lcefem.meshes.gridshell import GridshellLayout, build_gridshell_bar_hinge
from lcefem.models import bar_hinge as law
from lcefem.models.errors import InputError
from lcefem.models.loads import SurfaceWeight
from lcefem.models.parameters import check, describe, param, with_overrides
from lcefem.solvers.bar_hinge import NewtonOptions, PathOptions
from lcefem.validation import gridshell_bh as gs
from lcefem.solvers.run import Progress, add_out_arguments
from lcefem.solvers.exports import bar_hinge_run
from lcefem.validation.config import load_toml

PARALLEL = False  # a serial (numpy/scipy) model: ranks would race on one folder

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
class GridshellConfig(law.BarHingeMaterials):
    """The bar-and-hinge gridshell's sections: its materials (kapton, lce, glue, strip_contact,
    contact, ogden: inherited from the one definition, :class:`lcefem.models.bar_hinge.BarHingeMaterials`)
    plus the run, geometry, layout, mesh, weight, current route, solver and path sections."""

    run: GridshellRun = field(default_factory=GridshellRun)
    geometry: CompositeBeamGeometry = field(default_factory=CompositeBeamGeometry)
    layout: GridshellLayout = field(default_factory=GridshellLayout)
    mesh: BeamBarHingeMesh = field(default_factory=BeamBarHingeMesh)
    weight: SurfaceWeight = field(default_factory=SurfaceWeight)
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
    """Run and write the outputs (module docstring) through the run skeleton; returns the summary."""
    cfg = cfg.validated()
    out = pathlib.Path(out)
    structure = build_gridshell_bar_hinge(cfg.geometry, cfg.layout, cfg.mesh)
    targets, drive = strip_targets(cfg, structure)
    setup = gs.setup_gridshell(targets, cfg.support, cfg.geometry, cfg.layout, cfg.mesh, cfg.materials,
                               cfg.weight, structure=structure)
    model = setup.model

    # the quadratic fit needs >= 6 junctions (3 x 3); a one-cell grid has the circles only
    quad = cfg.layout.ribbons >= 3
    columns = [c for c in COLUMNS if quad or not c.startswith("quad")]

    def row(state) -> dict:
        summ = gs.shape_summary(structure, state.x)
        values = {"load factor [-]": state.t, "circle kappa_x [1/mm]": summ["circle_x"],
                  "circle kappa_y [1/mm]": summ["circle_y"], "z range [mm]": summ["z_range [mm]"],
                  "newton iterations [-]": state.iterations}
        if quad:
            values.update({"quad kappa_x [1/mm]": summ["quad_kx"], "quad kappa_y [1/mm]": summ["quad_ky"]})
        return values

    bar = Progress(1.0, "gridshell", "load", ".3f", progress)
    started = time.perf_counter()
    with bar_hinge_run(out, "gridshell", structure, model, config=cfg.resolved(), columns=columns,
                       row=row, progress=bar) as (run, on_step):
        solution = gs.solve_gridshell(setup, newton_options=cfg.solver, path=cfg.path, on_step=on_step,
                                      progress=bar.to)
        wall = time.perf_counter() - started
        x = solution.final.x
        write_nodes_csv(out / "nodes.csv", structure.nodes, x)
        from lcefem.validation.gridshell_plots import render_gridshell
        render_gridshell(out / "gridshell.png", structure, x,
                         f"gridshell {drive.get('shape') or drive.get('recipe') or ''} ({cfg.support})")
        final_fraction = model.rest_fractions()
        reached = all(np.array_equal(final_fraction[g], setup.targets[g]) for g in setup.targets)
        lam_n = cfg.lce.lambda_N
        per_strip: dict[int, list[float]] = {}
        for g, ids in structure.info["strip_of_bar"].items():
            for sid, f in zip(ids, setup.targets[g]):
                per_strip.setdefault(int(sid), []).append(float(f) * lam_n)
        return run.complete({
            "model": "bar-hinge gridshell", "drive": drive, "support": cfg.support,
            "strips": [{"id": s.id, "group": s.group, "channel": s.channel, "midpoint [mm]": s.midpoint,
                        "lambda [-]": float(np.mean(per_strip[s.id]))}
                       for s in structure.info["strips"]],
            "results": {**gs.shape_summary(structure, x), "sign convention": SIGN,
                        "target reached exactly": bool(reached)},
            "dofs": int(model.ndof), "nodes": int(structure.num_nodes),
            "increments": len(solution.path.states) - 1,
            "newton_iterations": int(sum(solution.path.newton_iterations)),
            "failed_increments": solution.path.failed_increments, "wall_time [s]": wall,
        })


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
    p.add_argument("--schedule", help="TOML schedule of channel currents over time: a programmed shape "
                   "sequence (lcefem.validation.gridshell_sequence; e.g. validation/data/"
                   "gridshell_fig5a_schedule.toml)")
    p.add_argument("--config", help="TOML case file (sections: run, lambda, current, "
                   + ", ".join(GridshellConfig.PARAM_SECTIONS[1:]) + ")")
    add_out_arguments(p, "results/gridshell")


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


def prepare(args: argparse.Namespace) -> GridshellConfig:
    """The validated configuration (before the output folder is claimed)."""
    if getattr(args, "schedule", None):
        from lcefem.validation import gridshell_sequence
        return gridshell_sequence.prepare(args)
    return config_from_args(args).validated()


def main(args: argparse.Namespace) -> int:
    if getattr(args, "schedule", None):
        from lcefem.validation import gridshell_sequence
        return gridshell_sequence.main(args)
    cfg = args.prepared
    summary = run_gridshell(cfg, pathlib.Path(args.out), progress=not args.quiet)
    r = summary["results"]
    quad = (f", quadratic fit {r['quad_kx']:.4f}/{r['quad_ky']:.4f}" if "quad_kx" in r else "")
    print(f"lcefem: gridshell ({summary['support']}): centre curvature x/y [1/mm]: circle "
          f"{r['circle_x']:.4f}/{r['circle_y']:.4f}{quad}; z range {r['z_range [mm]']:.2f} mm; "
          f"{summary['increments']} increments, {summary['newton_iterations']} Newton iterations, "
          f"{summary['wall_time [s]']:.1f} s; results in {args.out}")
    return 0
