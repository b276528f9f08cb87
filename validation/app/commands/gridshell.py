"""The robotic surface (seed 001, Fig. 4, 5): the n x n gridshell in the bar-and-hinge model or the
3D FE, driven by strip lambdas, a published recipe, coil currents or a schedule of currents.

``lcefem run gridshell [--shape dome|saddle|cylinder|table [--route lambda|current] | --recipe NAME
| --lambda Tx=1.33,... | --current Tx=0.04,... | --schedule FILE.toml]
[--support clamp|rollers|middle_rollers|table] [--model-set fe-calibrated|published]
[--configuration model-set|published] [--departure NAME] [--thermal-model strip|segment|eq1]
[--ribbons N | --layout NAME|FILE] [--config FILE.toml] [--out DIR] [--quiet]``; the 3D FE:
``--model fe`` with the same drives, ``--support``, ``--config`` and ``--mesh-level 0..3``
(lcefem.solvers.problems.gridshell_fe_run; docs/fe_bodies.md).

Selections (``--lambda``/``--current`` keys, applied in order): channels Tx, Ty, Bx, By (seed 001,
Fig. 4A), T / B (a layer), families XD, YD, XU, YU, groups XD1..YU3, half planes like XD:x<70.5,
or strip ids (see lcefem.meshes.gridshell; the FE takes its strip tags instead). Unnamed strips stay
as built (lambda_N = 1.4; current 0). ``--shape`` takes the paper's Fig. 4 lambdas (with
``--current``-route twins in the case ``gridshell_shapes_bh``); ``--recipe`` a published recipe
(rest fractions P0). The bar-and-hinge model set (``--model-set``, issue 46): 'fe-calibrated' by
default (validation.calibrate.model_set: strip element, plate torsion, fitted factors, glue squares,
strip-ribbon contact, volume law), 'published' by default with ``--recipe`` (the published elements,
supports and glue squares plus the contact); ``--configuration published`` is the published script
exactly (no contact); ``--departure`` adds named departures (docs/gridshell_configuration.md).
Case file sections: run (shape, recipe, support, model_set, configuration, departures), lambda,
current (tables of selection = value), and the parameter sections geometry, layout, mesh, kapton,
lce, glue, strip_contact, contact, weight, current_route, solver, path.

Outputs in --out DIR: summary.json (resolved configuration, per-strip lambdas, centre curvatures by
both measures with their sign convention, z range, the deepest strip-ribbon penetration [mm] and
whether strips pass through the ribbon, increments, Newton iterations, wall time), nodes.csv (node
id, as-built and final coordinates [mm]), gridshell.png (3D render, junction centres marked),
history.csv (one row per converged increment), gridshell.pvd + gridshell_steps/*.vtp (ParaView: N5B8
ribbon triangles, strip and glue bars; displacement, element kind, axial force). Files carry .part
names until the run completes; a run that stops leaves *.partial.* files, last_converged.vtp and
failure.json (exit code 3), through the run skeleton (lcefem.solvers.runtime.run.Run). The problem,
the drives and the run: lcefem.solvers.problems.gridshell_bh_run (GridshellBHRunConfig,
run_gridshell); this module parses the command line and the case file, renders gridshell.png and
prints one line.
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
from lcefem.solvers.problems.gridshell_bh_run import (
    CONFIGURATIONS,
    DEPARTURES,
    MODEL_SET_DEPARTURES,
    ROUTES,
    GridshellBHRunConfig,
    GridshellRun,
    run_gridshell,
)
from lcefem.solvers.runtime.outdir import add_out_arguments
from lcefem.solvers.runtime.ranks import world_rank
from lcefem.validation.app.commands import MODELS, parallel_if_fe
from lcefem.validation.app.config import load_toml
from lcefem.validation.cases.programs import RECIPES, SHAPE_DRIVES

#: Under mpiexec: the FE model only, every drive and --layout (its node-wise terms run on N ranks,
#: solvers/contact.py; the heated routes' pad coils by global search, solvers/problems/
#: gridshell_heated.py); the bar-and-hinge model is numpy/scipy (ranks would race on one folder).
PARALLEL = parallel_if_fe


def model_set_config(name: str) -> GridshellBHRunConfig:
    """The run configuration of bar-and-hinge model set ``name``
    (lcefem.validation.studies.gridshell.calibrate.model_set): its materials (the FE-calibrated
    set's fitted hinge and strip E I factors and the plate's torsion; the published set's published
    ones), its grid exchange factor and its configuration (run.model_set), with the experiments'
    programs (shapes, recipes)."""
    from lcefem.validation.studies.gridshell import calibrate

    ms = calibrate.model_set(name)
    base = GridshellBHRunConfig(
        shapes=SHAPE_DRIVES, recipes=RECIPES, run=GridshellRun(model_set=name)
    )
    mats = {f.name: getattr(ms.materials, f.name) for f in dataclasses.fields(ms.materials)}
    return dataclasses.replace(base, **mats, current_route=ms.current_route(base.current_route))


def default_model_set(recipe: str | None) -> str:
    """The command's model set when none is named: the published set for a published recipe (its P0
    were written for the published elements; with the contact it lands within 0.5-1.6 mm of the
    published code's own runs, issue 46), the FE-calibrated set otherwise (as design, bands and
    sequences: calibrate.DEFAULT_MODEL_SET)."""
    from lcefem.validation.studies.gridshell import calibrate

    return "published" if recipe else calibrate.DEFAULT_MODEL_SET


def config_from_toml(
    path, base: GridshellBHRunConfig | None = None, model_set: str | None = None
) -> GridshellBHRunConfig:
    """The case file at ``path`` applied on ``base`` (default: the configuration of ``model_set``,
    else of the case file's run.model_set, else of :func:`default_model_set`)."""
    data = load_toml(path, {*GridshellBHRunConfig.PARAM_SECTIONS, "lambda", "current"})
    if base is None:
        run = data.get("run", {})
        name = model_set or run.get("model_set") or default_model_set(run.get("recipe"))
        base = model_set_config(str(name))
    kw = {
        name: with_overrides(getattr(base, name), table, name)
        for name, table in data.items()
        if name in GridshellBHRunConfig.PARAM_SECTIONS and name != "layout"
    }
    if "layout" in data:  # lists and tables (glued, wiring): the layout's own loader
        kw["layout"] = layout_from_table(data["layout"], base.layout)
    # TOML keys are strings: strip ids ("3") become integers as on the command line
    # (parse_assignments)
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
        key = int(key) if key.isdigit() else key
        if key in out:
            # A repeated selection would silently keep its last value.
            raise InputError(f"--{name} {key}: given twice; give each selection once")
        out[key] = val
    return out


class _JoinAssignments(argparse.Action):
    """A repeated ``--lambda``/``--current`` adds its assignments to the earlier ones (argparse's
    default would keep only the last option)."""

    def __call__(self, parser, namespace, values, option_string=None):
        earlier = getattr(namespace, self.dest, None)
        setattr(namespace, self.dest, f"{earlier},{values}" if earlier else values)


def report(out, cfg: GridshellBHRunConfig, structure, x, drive: dict) -> None:
    """gridshell.png: 3D render, junction centres marked."""
    from lcefem.validation.studies.gridshell.gridshell_plots import render_gridshell

    render_gridshell(
        out / "gridshell.png",
        structure,
        x,
        f"gridshell {drive.get('shape') or drive.get('recipe') or ''} ({cfg.support})",
    )


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--model",
        choices=MODELS,
        default="bar-hinge",
        help="bar-and-hinge model (default) or "
        "the 3D FE gridshell (every drive below and --layout; the smallest valid mirror model; "
        "also under mpiexec -n N)",
    )
    p.add_argument("--mesh-level", type=int, help="FE only: mesh level 0..3 (default 0)")
    p.add_argument("--shape", help="the paper's Fig. 4 shape: " + ", ".join(SHAPE_DRIVES))
    p.add_argument(
        "--route",
        choices=ROUTES,
        help="with --shape: 'lambda' (the Fig. 4 lambdas, default) "
        "or 'current' (the paper's rule: Eq. 1 inverted at those lambdas through the grid "
        "strip's 130 ohm coil, then the current route's thermal model)",
    )
    p.add_argument("--recipe", help="a published recipe: " + ", ".join(RECIPES))
    p.add_argument(
        "--lambda",
        dest="lambdas",
        action=_JoinAssignments,
        help="lambdas [-] per selection, e.g. "
        "Tx=1.33,Ty=1.33,Bx=1.05,By=1.05 (1 isotropic .. 1.4 as built); may be repeated",
    )
    p.add_argument(
        "--current",
        dest="currents",
        action=_JoinAssignments,
        help="currents [A] per selection, e.g. Tx=0.04,Ty=0.04,Bx=0.07,By=0.07; may be repeated",
    )
    p.add_argument(
        "--thermal-model",
        choices=THERMAL_MODELS,
        help="current -> lambda: 'strip' "
        "(our lumped grid strip, 130 ohm over 80 mm isotropic, calibrated exchange; default), "
        "'segment' (a 25 ohm segment) or 'eq1' (the paper's Eq. 1 estimate)",
    )
    p.add_argument("--support", choices=SUPPORTS, help="supports (default: the published ones)")
    p.add_argument(
        "--model-set",
        choices=tuple(MODEL_SET_DEPARTURES),
        help="bar-and-hinge model set "
        "with its configuration (lcefem.validation.studies.gridshell.calibrate.model_set): "
        "'fe-calibrated' (default; "
        "the strip element, the plate's torsion and the fitted factors, glue squares, "
        "strip-ribbon contact, constant-volume bar law: within 10 %% of the 3D FE) or "
        "'published' (the published elements, supports and squares plus the strip-ribbon "
        "contact; default with --recipe)",
    )
    p.add_argument(
        "--configuration",
        choices=CONFIGURATIONS,
        help="'model-set' (default: the model "
        "set's configuration, the ribbon impenetrable) or 'published' (the published script "
        "exactly: no strip-ribbon contact, strips may pass through the ribbon; published "
        "model set only)",
    )
    p.add_argument(
        "--departure",
        action="append",
        dest="departures",
        metavar="NAME",
        help="a departure added to the configuration (repeatable or comma-separated): "
        + "; ".join(f"{k}: {v}" for k, v in DEPARTURES.items()),
    )
    p.add_argument("--ribbons", type=int, help="ribbons per direction (default 3)")
    p.add_argument(
        "--layout",
        help="the gridshell's layout: a name (published, 5x5, 7x7, rhombic60, "
        "rhombic60_5x5) or a TOML file with a [layout] section (docs/layouts/index.md)",
    )
    p.add_argument(
        "--schedule",
        help="TOML schedule of channel currents over time: a programmed shape "
        "sequence (lcefem.solvers.problems.gridshell_bh_sequence; e.g. validation/data/"
        "gridshell_fig5a_schedule.toml)",
    )
    p.add_argument(
        "--scales",
        action="store_true",
        help="cover scales on (Kapton disks, seed 001 Fig. 5; "
        "lcefem.models.cover_scales): with --schedule the covered sequence and its movie "
        "sequence.gif; with --task always on",
    )
    p.add_argument(
        "--task",
        choices=("sequence", "ball", "weights"),
        help="a Fig. 5 task of seed 001 on "
        "the covered surface (lcefem.validation.studies.gridshell.fig5_tasks; "
        "docs/fig5_tasks.md): the Fig. 5A "
        "schedule (or --schedule FILE), the ball manoeuvre, the weights on the table",
    )
    p.add_argument(
        "--config",
        help="TOML case file (sections: run, lambda, current, "
        + ", ".join(GridshellBHRunConfig.PARAM_SECTIONS[1:])
        + ")",
    )
    add_out_arguments(p, "results/gridshell")


def config_from_args(args: argparse.Namespace) -> GridshellBHRunConfig:
    model_set = getattr(args, "model_set", None)
    if model_set is None and args.recipe:
        model_set = default_model_set(args.recipe)
    cfg = config_from_toml(args.config, model_set=model_set)
    departures = ",".join(args.departures) if getattr(args, "departures", None) else None
    run = {
        k: v
        for k, v in {
            "shape": args.shape,
            "recipe": args.recipe,
            "support": args.support,
            "model_set": model_set,
            "configuration": getattr(args, "configuration", None),
            "departures": departures,
            "route": getattr(args, "route", None),
        }.items()
        if v is not None
    }
    kw = {"run": with_overrides(cfg.run, run, "run")}
    if args.lambdas is not None:
        kw["lambdas"] = parse_assignments(args.lambdas, "lambda")
    if args.currents is not None:
        kw["currents"] = parse_assignments(args.currents, "current")
    if args.thermal_model is not None:
        kw["current_route"] = dataclasses.replace(
            cfg.current_route, thermal_model=args.thermal_model
        )
    if getattr(args, "layout", None):
        from lcefem.validation.app.layouts import load_layout

        if args.ribbons is not None:
            raise InputError("--ribbons: not with --layout (set ribbons in the layout)")
        kw["layout"] = load_layout(args.layout)
    if args.ribbons is not None:
        kw["layout"] = with_overrides(cfg.layout, {"ribbons": args.ribbons}, "layout")
    return on_layout(dataclasses.replace(cfg, **kw))


def on_layout(cfg: GridshellBHRunConfig) -> GridshellBHRunConfig:
    """``cfg`` with its model set's materials where they apply on its layout
    (:meth:`lcefem.validation.studies.gridshell.calibrate.ModelSet.materials_for`: the plate's
    torsion is a rectangle's, so parallelogram panels take the N5B8 spokes', and a rhombic grid
    keeps it on its rectangular free panels); a Kapton section the case file changed is kept."""
    from lcefem.validation.studies.gridshell import calibrate

    ms = calibrate.model_set(cfg.run.model_set)
    if cfg.kapton != ms.materials.kapton:
        return cfg
    return dataclasses.replace(cfg, kapton=ms.materials_for(cfg.layout).kapton)


def prepare(args: argparse.Namespace) -> GridshellBHRunConfig:
    """The validated configuration (before the output folder is claimed)."""
    if getattr(args, "model", "bar-hinge") == "fe":
        return prepare_fe(args)
    if getattr(args, "mesh_level", None) is not None:
        raise InputError("--mesh-level: only with --model fe")
    if getattr(args, "task", None) or getattr(args, "scales", False):
        from lcefem.validation.studies.gridshell import fig5_tasks

        return fig5_tasks.prepare(args)
    if getattr(args, "schedule", None):
        from lcefem.validation.studies.gridshell import gridshell_sequence

        return gridshell_sequence.prepare(args)
    return config_from_args(args).validated()


#: Sections of a case file of the FE run (--model fe --config FILE): run (shape, recipe, support,
#: route, symmetry), lambda / current (selection = value), and the FE gridshell's parameter
#: sections.
FE_SECTIONS = ("run", "lambda", "current", "mesh", "supports", "contact", "control")
FE_RUN_KEYS = ("shape", "recipe", "support", "route", "symmetry")


def _fe_case(path) -> dict:
    """The case file of an FE run (:data:`FE_SECTIONS`), run keys checked."""
    data = load_toml(path, set(FE_SECTIONS))
    for key in data.get("run", {}):
        if key not in FE_RUN_KEYS:
            raise InputError(
                f"run.{key}: not in an FE case file (allowed: {', '.join(FE_RUN_KEYS)})"
            )
    return data


def prepare_fe(args: argparse.Namespace):
    """--model fe: the FE gridshell run (lcefem.solvers.problems.gridshell_fe_run) of the drive
    given as to the bar-and-hinge run: a Fig. 4 shape by its lambdas or the paper's rule of
    currents, a published recipe (lambda = lambda_N P0), lambdas or currents per selection, a
    schedule; on the published support of the shape, recipe or schedule unless --support; the
    smallest mirror model valid for the drive."""
    from lcefem.meshes.gridshell_fe import GridshellFEMesh
    from lcefem.models.bar_hinge_materials import PUBLISHED_LAMBDA_N
    from lcefem.models.lumped_heat import GRID_STRIP_RESISTANCE, shape_currents
    from lcefem.solvers.problems.gridshell import GridshellConfig
    from lcefem.solvers.problems.gridshell_fe_run import (
        GridshellFERun,
        GridshellFERunConfig,
        supports_of,
    )

    flags = {
        "model_set": ("--model-set", "the bar-and-hinge model set"),
        "configuration": ("--configuration", "a bar-and-hinge configuration"),
        "departures": ("--departure", "a bar-and-hinge departure"),
        "thermal_model": (
            "--thermal-model",
            "the bar-and-hinge current route's strip model; the 3D FE solves the heat equation",
        ),
        "ribbons": ("--ribbons", "the 3D FE runs the 3 x 3 surface"),
        "task": ("--task", "a Fig. 5 task of the bar-and-hinge surface"),
        "scales": ("--scales", "the cover scales of the bar-and-hinge surface"),
    }
    for name, (flag, why) in flags.items():
        if getattr(args, name, None):
            raise InputError(f"{flag}: not with --model fe ({why})")
    data = _fe_case(args.config)
    run = {
        **data.get("run", {}),
        **{
            k: v
            for k, v in {
                "shape": args.shape,
                "recipe": args.recipe,
                "support": args.support,
                "route": getattr(args, "route", None),
            }.items()
            if v is not None
        },
    }
    lambdas = (
        parse_assignments(args.lambdas, "lambda") if args.lambdas else dict(data.get("lambda", {}))
    )
    currents = (
        parse_assignments(args.currents, "current")
        if args.currents
        else dict(data.get("current", {}))
    )
    schedule = getattr(args, "schedule", None)
    drives = [
        f
        for f, given in (
            ("--shape", run.get("shape")),
            ("--recipe", run.get("recipe")),
            ("--lambda", lambdas),
            ("--current", currents),
            ("--schedule", schedule),
        )
        if given
    ]
    if len(drives) != 1:
        raise InputError(
            "--model fe: give one drive of --shape, --recipe, --lambda, --current, --schedule"
            + (f" (given: {', '.join(drives)})" if drives else "")
        )
    route = run.get("route") or "lambda"
    if route not in ROUTES:
        raise InputError(f"--route = {route!r}: allowed {', '.join(ROUTES)}")
    if route != "lambda" and not run.get("shape"):
        raise InputError("--route: only with --shape (give currents with --current)")
    kw, notes, support, label = {}, {}, "rollers", ""
    if run.get("shape"):
        shape = run["shape"]
        if shape not in SHAPE_DRIVES:
            raise InputError(f"--shape = {shape!r}: allowed {', '.join(SHAPE_DRIVES)}")
        support, label, notes["shape"] = SHAPE_DRIVES[shape]["support"], shape, shape
        if route == "current":
            currents = shape_currents(SHAPE_DRIVES[shape]["lambdas"], GRID_STRIP_RESISTANCE)
            notes["current rule"] = (
                "Eq. 1 inverted at the Fig. 4 lambdas through the grid strip's "
                "130 ohm coil (models.lumped_heat.eq1_current)"
            )
        else:
            lambdas = dict(SHAPE_DRIVES[shape]["lambdas"])
    elif run.get("recipe"):
        recipe = run["recipe"]
        if recipe not in RECIPES:
            raise InputError(f"--recipe = {recipe!r}: allowed {', '.join(RECIPES)}")
        p0, support = RECIPES[recipe]
        lambdas = {
            k: PUBLISHED_LAMBDA_N * v for k, v in p0.items()
        }  # programs.toml: lambda = 1.4 P0
        label, notes["recipe"] = f"recipe {recipe}", recipe
    elif schedule:
        from lcefem.solvers.problems.gridshell_bh_sequence import load_schedule

        sched = load_schedule(schedule)
        support, label = sched.support, f"schedule {pathlib.Path(schedule).name}"
        kw = {
            "protocol": tuple(
                (t, {sel: v[k] for sel, v in sched.currents.items()})
                for k, t in enumerate(sched.times)
            ),
            "run": GridshellFERun(
                drive="schedule",
                duration=sched.end,
                dt=sched.output_interval,
                label=label,
                symmetry=run.get("symmetry", ""),
            ),
        }
        notes["schedule"] = {"file": str(schedule), "labels": list(sched.labels)}
    if not label:  # the user's drive, for the bar, the render's title and the summary
        given = lambdas or currents
        label = (
            ",".join(f"{k}={v:g}" for k, v in given.items())
            if len(given) <= 6
            else f"{len(given)} selections"
        )
    support = run.get("support") or support
    level = 0 if args.mesh_level is None else args.mesh_level
    if not 0 <= level <= 3:
        raise InputError(f"--mesh-level = {level}: allowed 0..3")
    model = GridshellConfig(
        mesh=with_overrides(GridshellFEMesh(level=level), data.get("mesh", {}), "mesh"),
        supports=with_overrides(supports_of(support), data.get("supports", {}), "supports"),
    )
    for name in ("contact", "control"):
        if name in data:
            model = dataclasses.replace(
                model, **{name: with_overrides(getattr(model, name), data[name], name)}
            )
    if args.mesh_level is not None:  # the command line wins over the case file
        model = dataclasses.replace(model, mesh=dataclasses.replace(model.mesh, level=level))
    if getattr(args, "layout", None):
        model = _on_layout_fe(model, args.layout)
        notes["layout"] = args.layout
    drive = "current" if currents else "lambda"
    kw.setdefault("run", GridshellFERun(drive=drive, label=label, symmetry=run.get("symmetry", "")))
    return GridshellFERunConfig(
        model=model,
        lambdas=lambdas if drive == "lambda" else {},
        currents=currents,
        notes=notes,
        **kw,
    ).validated()


def _fe_report(out, cfg, model) -> dict:
    """gridshell_fe.png: the deformed FE surface (the mirror model mirrored to the whole surface),
    coloured by the von Mises stress (rank 0 of a serial run only: pyvista reads one process's
    mesh)."""
    if model.tmesh.mesh.comm.size > 1:
        return {}
    from lcefem.validation.app import render

    c = model.info["centre"]
    mirror = tuple(
        (axis, c) for axis, name in ((0, "sym_x"), (1, "sym_y")) if name in model.tmesh.facets
    )
    model.update_stress()
    render.render_deformed(
        out / "gridshell_fe.png",
        model.u,
        model.stress,
        scalar_label="von Mises stress [MPa]",
        title=f"gridshell (FE) {cfg.run.label}",
        mirror=mirror,
        show_undeformed=False,
    )
    return {}


def _on_layout_fe(model, spec: str):
    """The FE gridshell configuration ``model`` on the layout ``spec`` (a name or a TOML file): its
    ribbons, its lengths in the mesh builder's coordinates and its angle (the gmsh mesh of
    :func:`lcefem.meshes.gridshell_fe_gmsh.build_layout_fe`); one-line refusals of what the FE mesh
    does not build (triangular and hexagonal kinds, unbonded junctions)."""
    from lcefem.meshes.gridshell_fe_gmsh import layout_fe_geometry
    from lcefem.meshes.gridshell_layout import FE_KINDS
    from lcefem.validation.app.layouts import load_layout

    layout = load_layout(spec)
    if layout.kind not in FE_KINDS:
        raise InputError(
            f"--layout {spec}: kind {layout.kind!r}: the 3D FE is built for "
            f"{', '.join(FE_KINDS)} layouts"
        )
    if layout.glued != "all":
        raise InputError(
            f"--layout {spec}: glued = {layout.glued!r}: the 3D FE bonds every junction; allowed "
            "'all'"
        )
    if layout.wiring != "channels" or layout.support:
        raise InputError(
            f"--layout {spec}: wiring and support of a layout are the bar-and-hinge run's; "
            "with --model fe give the drive and --support"
        )
    mesh = dataclasses.replace(model.mesh, mesher="gmsh", shear_angle=float(layout.angle))
    return dataclasses.replace(
        model, cells=layout.ribbons, mesh=mesh, geometry=layout_fe_geometry(layout, model.geometry)
    )


def main_fe(args: argparse.Namespace) -> int:
    from lcefem.solvers.problems.gridshell_fe_run import run_gridshell_fe

    cfg = args.prepared
    s = run_gridshell_fe(cfg, pathlib.Path(args.out), progress=not args.quiet, report=_fe_report)
    h = s["results"]
    heat = ""
    if cfg.run.drive != "lambda":
        heat = "; lambda T/B " + "/".join(
            f"{h[f'lambda {c} [-]']:.3f}"
            for c in ("Tx", "Ty", "Bx", "By")
            if f"lambda {c} [-]" in h
        )
    if world_rank() != 0:  # one line under mpiexec (cli.py: rank 0 prints)
        return 0
    print(
        f"lcefem: gridshell (fe, {s['symmetry']}, {s['support']}, level {s['mesh level']}) "
        f"{cfg.run.label or 'drive'} ({cfg.run.drive}): centre curvature x/y [1/mm]: circle "
        f"{h['kappa_circle_x [1/mm]']:.4f}/{h['kappa_circle_y [1/mm]']:.4f}, quadratic fit "
        f"{h['kappa_quad_x [1/mm]']:.4f}/{h['kappa_quad_y [1/mm]']:.4f}; z range "
        f"{h['z_range [mm]']:.2f} "
        "mm"
        f"{heat}; {s['dofs [-]']} DOFs, {s['newton iterations [-]']} Newton iterations, "
        f"{s['cpu time [s]']:.0f} s CPU; results in {args.out}"
    )
    return 0


def main(args: argparse.Namespace) -> int:
    if getattr(args, "model", "bar-hinge") == "fe":
        return main_fe(args)
    if getattr(args, "task", None) or getattr(args, "scales", False):
        from lcefem.validation.studies.gridshell import fig5_tasks

        return fig5_tasks.main(args)
    if getattr(args, "schedule", None):
        from lcefem.validation.studies.gridshell import gridshell_sequence

        return gridshell_sequence.main(args)
    cfg = args.prepared
    summary = run_gridshell(cfg, pathlib.Path(args.out), progress=not args.quiet, report=report)
    r = summary["results"]
    quad = f", quadratic fit {r['quad_kx']:.4f}/{r['quad_ky']:.4f}" if "quad_kx" in r else ""
    depth = summary["strip-ribbon penetration [mm]"]
    through = (
        " (strips pass through the ribbon)" if summary["strips pass through the ribbon"] else ""
    )
    print(
        f"lcefem: gridshell ({summary['model set']} set, {summary['support']}): centre curvature "
        "x/y "
        f"[1/mm]: circle {r['circle_x']:.4f}/{r['circle_y']:.4f}{quad}; z range "
        f"{r['z_range [mm]']:.2f} "
        "mm; "
        f"strip-ribbon penetration {depth:.2f} mm{through}; "
        f"{summary['increments']} increments, {summary['newton_iterations']} Newton iterations, "
        f"{summary['wall_time [s]']:.1f} s; results in {args.out}"
    )
    return 0
