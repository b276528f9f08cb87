"""The robotic surface (seed 001, Fig. 4, 5): the n x n gridshell in the bar-and-hinge model, driven
by strip lambdas, a published recipe or coil currents.

``lcefem run gridshell [--shape dome|saddle|cylinder|table [--route lambda|current] | --recipe NAME
| --lambda Tx=1.33,... | --current Tx=0.04,...] [--support clamp|rollers|middle_rollers|table]
[--configuration published|case] [--departure NAME] [--thermal-model strip|segment|eq1]
[--ribbons N | --layout NAME|FILE] [--config FILE.toml] [--out DIR] [--quiet]``; a programmed sequence of currents:
``lcefem run gridshell --schedule FILE.toml`` (lcefem.validation.gridshell_sequence).

Selections (``--lambda``/``--current`` keys, applied in order): channels Tx, Ty, Bx, By (seed 001,
Fig. 4A), T / B (a layer), families XD, YD, XU, YU, groups XD1..YU3, half planes like XD:x<70.5,
or strip ids (see lcefem.meshes.gridshell). Unnamed strips stay as built (lambda_N = 1.4; current 0).
``--shape`` takes the paper's Fig. 4 lambdas (with ``--current``-route twins in the case
``gridshell_shapes_bh``); ``--recipe`` a published recipe (rest fractions P0) in the published
configuration (Examples2D.m: its support, glue squares, bar law A f P(p), no strip-ribbon contact),
our departures one ``--departure contact,contracting_squares,volume_law,middle_rollers`` away
(``--configuration case``: the mesh and lce sections as given; docs/gridshell_configuration.md).
Case file sections: run (shape, recipe, support, configuration, departures), lambda, current
(tables of selection = value), and the parameter sections geometry, layout, mesh, kapton, lce, glue,
strip_contact, contact, weight, current_route, solver, path.

Outputs in --out DIR: summary.json (resolved configuration, per-strip lambdas, centre curvatures by
both measures with their sign convention, z range, increments, Newton iterations, wall time),
nodes.csv (node id, as-built and final coordinates [mm]), gridshell.png (3D render, junction centres
marked), history.csv (one row per converged
increment), gridshell.pvd + gridshell_steps/*.vtp (ParaView: N5B8 ribbon triangles, strip and glue
bars; displacement, element kind, axial force). Files carry .part names until the run completes; a
run that stops leaves *.partial.* files, last_converged.vtp and failure.json (exit code 3), through
the run skeleton (lcefem.solvers.runtime.run.Run). The problem, the drives and the run:
lcefem.solvers.problems.gridshell_bh (GridshellBHRunConfig, run_gridshell); this module parses the
command line and the case file, renders gridshell.png and prints one line.
"""

from __future__ import annotations

import argparse
import dataclasses
import pathlib

from lcefem.meshes.gridshell_layout import layout_from_table
from lcefem.models.errors import InputError
from lcefem.models.lumped_heat import THERMAL_MODELS
from lcefem.models.parameters import with_overrides
from lcefem.solvers.problems.gridshell_bh import SUPPORTS
from lcefem.solvers.problems.gridshell_bh_run import (CONFIGURATIONS, DEPARTURES, ROUTES, GridshellBHRunConfig,
                                                      run_gridshell)
from lcefem.solvers.runtime.outdir import add_out_arguments
from lcefem.validation.commands import MODELS
from lcefem.validation.config import load_toml
from lcefem.validation.programs import PUBLISHED_SUPPORTS, RECIPES, SHAPE_DRIVES

PARALLEL = False  # a serial (numpy/scipy) model: ranks would race on one folder


def config_from_toml(path, base: GridshellBHRunConfig | None = None) -> GridshellBHRunConfig:
    base = base or GridshellBHRunConfig(shapes=SHAPE_DRIVES, recipes=RECIPES)
    data = load_toml(path, {*GridshellBHRunConfig.PARAM_SECTIONS, "lambda", "current"})
    kw = {name: with_overrides(getattr(base, name), table, name) for name, table in data.items()
          if name in GridshellBHRunConfig.PARAM_SECTIONS and name != "layout"}
    if "layout" in data:  # lists and tables (glued, wiring): the layout's own loader
        kw["layout"] = layout_from_table(data["layout"], base.layout)
    # TOML keys are strings: strip ids ("3") become integers as on the command line (parse_assignments)
    if "lambda" in data:
        kw["lambdas"] = {int(k) if k.isdigit() else k: v for k, v in data["lambda"].items()}
    if "current" in data:
        kw["currents"] = {int(k) if k.isdigit() else k: v for k, v in data["current"].items()}
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


def report(out, cfg: GridshellBHRunConfig, structure, x, drive: dict) -> None:
    """gridshell.png: 3D render, junction centres marked."""
    from lcefem.validation.gridshell_plots import render_gridshell

    render_gridshell(out / "gridshell.png", structure, x,
                     f"gridshell {drive.get('shape') or drive.get('recipe') or ''} ({cfg.support})")


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--model", choices=MODELS, default="bar-hinge", help="bar-and-hinge model (default) or "
                   "the 3D FE heated gridshell (quarter model; only --shape NAME --route current)")
    p.add_argument("--mesh-level", type=int, help="FE only: mesh level (default 0)")
    p.add_argument("--shape", help="the paper's Fig. 4 shape: " + ", ".join(SHAPE_DRIVES))
    p.add_argument("--route", choices=ROUTES, help="with --shape: 'lambda' (the Fig. 4 lambdas, default) "
                   "or 'current' (the paper's rule: Eq. 1 inverted at those lambdas through the grid "
                   "strip's 130 ohm coil, then the current route's thermal model)")
    p.add_argument("--recipe", help="a published recipe: " + ", ".join(RECIPES))
    p.add_argument("--lambda", dest="lambdas", help="lambdas [-] per selection, e.g. "
                   "Tx=1.33,Ty=1.33,Bx=1.05,By=1.05 (1 isotropic .. 1.4 as built)")
    p.add_argument("--current", dest="currents", help="currents [A] per selection, e.g. "
                   "Tx=0.04,Ty=0.04,Bx=0.07,By=0.07")
    p.add_argument("--thermal-model", choices=THERMAL_MODELS, help="current -> lambda: 'strip' "
                   "(our lumped grid strip, 130 ohm over 80 mm isotropic, calibrated exchange; default), "
                   "'segment' (a 25 ohm segment) or 'eq1' (the paper's Eq. 1 estimate)")
    p.add_argument("--support", choices=SUPPORTS, help="supports (default: the published ones)")
    p.add_argument("--configuration", choices=CONFIGURATIONS, help="'published' (the published "
                   "model: its supports, glue squares, bar law A f P(p), no strip-ribbon contact; "
                   "default with --recipe) or 'case' (the mesh and lce sections as given; default "
                   "otherwise)")
    p.add_argument("--departure", action="append", dest="departures", metavar="NAME",
                   help="a departure from the published configuration (repeatable or comma-separated): "
                   + "; ".join(f"{k}: {v}" for k, v in DEPARTURES.items()))
    p.add_argument("--ribbons", type=int, help="ribbons per direction (default 3)")
    p.add_argument("--layout", help="the gridshell's layout: a name (published, 5x5, 7x7, rhombic60, "
                   "rhombic60_5x5) or a TOML file with a [layout] section (docs/layouts.md)")
    p.add_argument("--schedule", help="TOML schedule of channel currents over time: a programmed shape "
                   "sequence (lcefem.solvers.problems.gridshell_bh_sequence; e.g. validation/data/"
                   "gridshell_fig5a_schedule.toml)")
    p.add_argument("--scales", action="store_true", help="cover scales on (Kapton disks, seed 001 Fig. 5; "
                   "lcefem.models.cover_scales): with --schedule the covered sequence and its movie "
                   "sequence.gif; with --task always on")
    p.add_argument("--task", choices=("sequence", "ball", "weights"), help="a Fig. 5 task of seed 001 on "
                   "the covered surface (lcefem.validation.fig5_tasks; docs/fig5_tasks.md): the Fig. 5A "
                   "schedule (or --schedule FILE), the ball manoeuvre, the weights on the table")
    p.add_argument("--config", help="TOML case file (sections: run, lambda, current, "
                   + ", ".join(GridshellBHRunConfig.PARAM_SECTIONS[1:]) + ")")
    add_out_arguments(p, "results/gridshell")


def config_from_args(args: argparse.Namespace) -> GridshellBHRunConfig:
    cfg = config_from_toml(args.config)
    departures = ",".join(args.departures) if getattr(args, "departures", None) else None
    run = {k: v for k, v in {"shape": args.shape, "recipe": args.recipe, "support": args.support,
                             "configuration": getattr(args, "configuration", None),
                             "departures": departures,
                             "route": getattr(args, "route", None)}.items() if v is not None}
    kw = {"run": with_overrides(cfg.run, run, "run")}
    if args.lambdas is not None:
        kw["lambdas"] = parse_assignments(args.lambdas, "lambda")
    if args.currents is not None:
        kw["currents"] = parse_assignments(args.currents, "current")
    if args.thermal_model is not None:
        kw["current_route"] = dataclasses.replace(cfg.current_route, thermal_model=args.thermal_model)
    if getattr(args, "layout", None):
        from lcefem.validation.layouts import load_layout

        if args.ribbons is not None:
            raise InputError("--ribbons: not with --layout (set ribbons in the layout)")
        kw["layout"] = load_layout(args.layout)
    if args.ribbons is not None:
        kw["layout"] = with_overrides(cfg.layout, {"ribbons": args.ribbons}, "layout")
    return dataclasses.replace(cfg, **kw)


def prepare(args: argparse.Namespace) -> GridshellBHRunConfig:
    """The validated configuration (before the output folder is claimed)."""
    if getattr(args, "model", "bar-hinge") == "fe":
        return prepare_fe(args)
    if getattr(args, "mesh_level", None) is not None:
        raise InputError("--mesh-level: only with --model fe")
    if getattr(args, "task", None) or getattr(args, "scales", False):
        from lcefem.validation import fig5_tasks
        return fig5_tasks.prepare(args)
    if getattr(args, "schedule", None):
        from lcefem.validation import gridshell_sequence
        return gridshell_sequence.prepare(args)
    return config_from_args(args).validated()


def prepare_fe(args: argparse.Namespace) -> dict:
    """--model fe: the heated FE gridshell held at a Fig. 4 shape's currents (the paper's rule)."""
    flags = {"recipe": "--recipe", "lambdas": "--lambda", "currents": "--current", "schedule": "--schedule",
             "config": "--config", "thermal_model": "--thermal-model", "ribbons": "--ribbons", "layout": "--layout",
             "support": "--support"}
    for name, flag in flags.items():
        if getattr(args, name, None):
            raise InputError(f"{flag}: not with --model fe (it takes --shape NAME --route current)")
    if not args.shape or args.shape not in SHAPE_DRIVES:
        raise InputError(f"--shape = {args.shape!r}: --model fe needs one of {', '.join(SHAPE_DRIVES)}")
    if getattr(args, "route", None) != "current":
        raise InputError("--route: --model fe runs the current route only (--route current); the FE "
                         "lambda route is the case gridshell_shapes_fe")
    level = 0 if args.mesh_level is None else args.mesh_level
    if not 0 <= level <= 3:
        raise InputError(f"--mesh-level = {level}: allowed 0..3")
    return {"model": "fe", "shape": args.shape, "mesh_level": level}


def run_fe_current(spec: dict, out: pathlib.Path) -> dict:
    """The heated FE gridshell (quarter, published support of the shape) held at the currents the
    paper's rule gives at the shape's Fig. 4 lambdas (models.lumped_heat.shape_currents), straight to
    the steady state (HeatedGridshellFE.steady_hold); writes summary.json; returns it."""
    import time

    from lcefem.meshes.gridshell_fe import GridshellFEMesh
    from lcefem.models.lumped_heat import GRID_STRIP_RESISTANCE, shape_currents
    from lcefem.solvers.problems.gridshell import GridshellConfig, GridshellSupports
    from lcefem.solvers.problems.gridshell_heated import HeatedGridshellFE
    from lcefem.solvers.runtime.files import write_json

    shape = spec["shape"]
    currents = shape_currents(SHAPE_DRIVES[shape]["lambdas"], GRID_STRIP_RESISTANCE)
    started = time.process_time()
    model = HeatedGridshellFE(GridshellConfig(mesh=GridshellFEMesh(level=spec["mesh_level"]),
                                              symmetry="quarter",
                                              supports=GridshellSupports(kind=PUBLISHED_SUPPORTS[shape])))
    rows = model.steady_hold(currents)
    held = {k: v for k, v in rows[-1].items() if not k.startswith("junction_")}
    summary = {"model": "3D FE heated gridshell (HeatedGridshellFE.steady_hold), quarter",
               "shape": shape, "mesh level": spec["mesh_level"], "support": PUBLISHED_SUPPORTS[shape],
               "current [A]": currents, "current rule": "Eq. 1 inverted at the Fig. 4 lambdas through "
               "the grid strip's 130 ohm coil (models.lumped_heat.eq1_current)",
               "junction_heating": model.junction_heating,
               "held": held, "sweeps": len(rows), "cpu [s]": time.process_time() - started}
    write_json(out / "summary.json", summary)
    return summary


def main(args: argparse.Namespace) -> int:
    if isinstance(getattr(args, "prepared", None), dict) and args.prepared.get("model") == "fe":
        s = run_fe_current(args.prepared, pathlib.Path(args.out))
        h = s["held"]
        print(f"lcefem: gridshell (fe, {s['support']}, level {s['mesh level']}) {s['shape']} from currents "
              + ", ".join(f"{k} {v:.4f} A" for k, v in s["current [A]"].items())
              + f": centre curvature x/y [1/mm]: circle {h['kappa_circle_x [1/mm]']:.4f}/"
              f"{h['kappa_circle_y [1/mm]']:.4f}, quadratic fit {h['kappa_quad_x [1/mm]']:.4f}/"
              f"{h['kappa_quad_y [1/mm]']:.4f}; lambda T/B "
              + "/".join(f"{h[f'lambda {c} [-]']:.3f}" for c in ("Tx", "Ty", "Bx", "By") if f"lambda {c} [-]" in h)
              + f"; {s['cpu [s]']:.0f} s CPU; results in {args.out}")
        return 0
    if getattr(args, "task", None) or getattr(args, "scales", False):
        from lcefem.validation import fig5_tasks
        return fig5_tasks.main(args)
    if getattr(args, "schedule", None):
        from lcefem.validation import gridshell_sequence
        return gridshell_sequence.main(args)
    cfg = args.prepared
    summary = run_gridshell(cfg, pathlib.Path(args.out), progress=not args.quiet, report=report)
    r = summary["results"]
    quad = (f", quadratic fit {r['quad_kx']:.4f}/{r['quad_ky']:.4f}" if "quad_kx" in r else "")
    print(f"lcefem: gridshell ({summary['support']}): centre curvature x/y [1/mm]: circle "
          f"{r['circle_x']:.4f}/{r['circle_y']:.4f}{quad}; z range {r['z_range [mm]']:.2f} mm; "
          f"{summary['increments']} increments, {summary['newton_iterations']} Newton iterations, "
          f"{summary['wall_time [s]']:.1f} s; results in {args.out}")
    return 0
