"""Mesh-convergence study of a user's body: ``lcefem converge --config robot.toml --levels 3``.

The case file's body (:mod:`lcefem.solvers.problems.body_case`) runs at ``--levels`` refinement
levels, each in ``DIR/level<i>/`` (its history.csv and summary.json, no field files):

* a ``.geo`` mesh: level i meshes it with size factor s_0 / 2^i (s_0 the case file's
  ``[mesh] size_factor``), so every element edge halves from one level to the next;
* a read mesh (.msh, .vtu, .xdmf, ...): level i refines it uniformly ``[mesh] refine`` + i times
  (:func:`lcefem.meshes.reader.refine_uniformly`: tetrahedra only; a hexahedral file is refused
  with one line before anything runs).

The mesh size of level i is Celik et al.'s representative cell size relative to level 0,
h_i = (N_0 / N_i)^(1/3) [-] (N the cell count: J. Fluids Eng. 130, 078001, 2008, Eq. 1), so an
unstructured mesh that does not quite octuple its cells gets its true ratio.

Every history observable at the final time (and, in ``gci_by_time.csv``, at every program time)
is analysed on the finest three levels by :func:`lcefem.validation.app.converge.analyse` (observed
order, Richardson extrapolation and GCI of :mod:`lcefem.validation.studies.verification.gci`, with
the same flags as the built-in cases' studies). Writes ``levels.csv``, ``gci.csv``,
``convergence.json``, ``convergence.png`` (the same files, through the same writer, as ``lcefem
converge CASE``), ``gci_by_time.csv`` and ``report.md``.
"""

from __future__ import annotations

import math
import pathlib
import sys

import numpy as np

from lcefem.models.errors import InputError
from lcefem.solvers.runtime.files import write_text
from lcefem.validation.app import converge as study

MIN_LEVELS = 3  #: three solutions give one observed order (Celik et al. 2008)
MAX_LEVELS = 5  #: each level has 8x the cells of the one before: level 4 has 4096x level 0's
NOT_ANALYSED = ("newton_iterations [-]", "step_cuts [-]", "time [s]")
ROUND_OFF = 1e-12  #: |value| below this fraction of the largest value of its unit is zero


def level_overrides(case, level: int) -> dict:
    """The case-file overrides of ``level``: the .geo's size factor halved ``level`` times, or a
    read mesh refined ``level`` more times; no field files."""
    over = {("output", "fields"): False}
    if case.mesh_file.suffix.lower() == ".geo":
        over[("mesh", "size_factor")] = case.mesh["size_factor"] / 2**level
    else:
        over[("mesh", "refine")] = case.mesh["refine"] + level
    return over


def check_refinable(case, levels: int) -> None:
    """InputError (one line) for a study that cannot run: too few or many levels, a read mesh of
    hexahedra (dolfinx refines tetrahedra only), refinements beyond the schema's bound."""
    from lcefem.meshes.reader import volume_cell_types
    from lcefem.solvers.problems.body_case import SCHEMA

    if not MIN_LEVELS <= levels <= MAX_LEVELS:
        raise InputError(
            f"--levels = {levels}: allowed {MIN_LEVELS} to {MAX_LEVELS} for a case file "
            "(three solutions give an observed order; each level has 8x the cells)"
        )
    if case.program.get("stretches"):
        raise InputError(
            "converge --config: a stretch ramp ([program] stretches) records the path "
            "follower's own increments, which differ between levels; allowed: a time program"
        )
    if case.mesh_file.suffix.lower() == ".geo":
        return
    types = volume_cell_types(case.mesh_file)
    if types - {"tetra", "tetra10"}:
        raise InputError(
            f"converge --config: {case.mesh_file.name} has {', '.join(sorted(types))} "
            "cells and dolfinx refines tetrahedra only; give the .geo (refined by its "
            "size factor) or a tetrahedral mesh"
        )
    top = SCHEMA["mesh"]["refine"][3][1]
    if case.mesh["refine"] + levels - 1 > top:
        raise InputError(
            f"--levels = {levels}: [mesh] refine = {case.mesh['refine']} plus {levels - 1} "
            f"refinements exceeds {top}"
        )


def run_levels(
    case_path: pathlib.Path, base_case, out: pathlib.Path, levels: int, progress: bool, comm=None
) -> list:
    """The body at levels 0..levels-1 (each checked again with its overrides, then run into
    ``out/level<i>``); their :class:`lcefem.solvers.problems.body.BodyResult`."""
    from lcefem.solvers.problems.body import run_body
    from lcefem.solvers.problems.body_case import load_case

    results = []
    for level in range(levels):
        case = load_case(
            case_path,
            comm,
            overrides={**_base_overrides(base_case), **level_overrides(base_case, level)},
        )
        if progress:
            print(f"converge {case_path.name}: level {level} of {levels - 1}", file=sys.stderr)
        results.append(run_body(case, out / f"level{level}", progress=progress, comm=comm))
    return results


def _base_overrides(case) -> dict:
    """The level-0 values the command line may have changed (kept for every level)."""
    return {
        ("mesh", "size_factor"): case.mesh["size_factor"],
        ("mesh", "refine"): case.mesh["refine"],
        ("program", "duration"): case.program["duration"],
        ("program", "dt"): case.program["dt"],
    }


def analyse_levels(results) -> tuple[list[float], list, list[dict]]:
    """(relative mesh sizes h_i = (N_0/N_i)^(1/3), the final-time studies, per-time rows)."""
    cells = [r.summary["mesh"]["cells"] for r in results]
    h = [(cells[0] / n) ** (1.0 / 3.0) for n in cells]
    names = [k for k in results[0].history if k not in NOT_ANALYSED]
    # A value zero by symmetry (u_y on a mirror plane) is round-off at every level: compared with
    # the largest value of its unit it is zero, so it is mesh-independent, not "converging".
    scale: dict[str, float] = {}
    for name in names:
        unit = _split(name)[1]
        biggest = max(float(np.max(np.abs(r.history[name]))) for r in results)
        scale[unit] = max(scale.get(unit, 0.0), biggest)

    def values(name: str, k: int) -> list[float]:
        v = [float(r.history[name][k]) for r in results]
        small = ROUND_OFF * scale[_split(name)[1]]
        return [0.0 if abs(x) <= small else x for x in v]

    studies = []
    for name in names:
        label, unit = _split(name)
        studies.append(study.analyse(h, values(name, -1), label, unit))
    by_time = []
    times = np.asarray(results[-1].history["time [s]"], float)
    same = all(
        len(r.history["time [s]"]) == len(times) and np.allclose(r.history["time [s]"], times)
        for r in results
    )
    if same:  # every level took the program's steps (no cut changed the recorded times)
        for k, t in enumerate(times):
            for name in names:
                label, unit = _split(name)
                s = study.analyse(h, values(name, k), label, unit)
                by_time.append(
                    {
                        "time [s]": t,
                        "observable": label,
                        "unit": unit,
                        "finest": s.values[-1],
                        "p [-]": s.p,
                        "extrapolated": s.extrapolated,
                        "GCI_fine [-]": s.gci_fine,
                        "flags": " ".join(s.flags),
                    }
                )
    return h, studies, by_time


def _split(column: str) -> tuple[str, str]:
    name, _, unit = column.rpartition(" [")
    return (name, unit[:-1]) if name else (column, "-")


def report_markdown(case_path: pathlib.Path, h, cells, studies, warnings, levels_info) -> str:
    """report.md: what ran, the table of every observable, the figure."""
    lines = [
        f"# Mesh convergence of {case_path.name}",
        "",
        f"- case file: `{case_path}`",
        "- levels: " + "; ".join(levels_info),
        "- mesh size h: (N_0/N)^(1/3) relative to level 0 (Celik et al. 2008, Eq. 1)",
        "- observed order p, Richardson extrapolation and GCI_fine (safety factor 1.25) on the "
        "finest three levels (Celik et al., J. Fluids Eng. 130, 078001, 2008; "
        "lcefem.validation.studies.verification.gci)",
        "",
    ]
    lines += [f"- warning: {w}" for w in warnings]
    head = [
        "observable",
        "unit",
        *[f"level {i} (h={x:.3g})" for i, x in enumerate(h)],
        "p [-]",
        "extrapolated",
        "GCI_fine [%]",
        "flags",
    ]
    lines += ["", "| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for s in studies:
        cells_ = [
            s.metric,
            s.unit,
            *[study._fmt(v) for v in s.values],
            study._fmt(s.p, ".3f"),
            study._fmt(s.extrapolated, ".6g"),
            study._fmt(100 * s.gci_fine, ".3g"),
            ", ".join(s.flags) or "ok",
        ]
        lines.append("| " + " | ".join(c.replace("|", "\\|") for c in cells_) + " |")
    lines += [
        "",
        "![convergence](convergence.png)",
        "",
        "*|value - Richardson extrapolation| against the relative mesh size, per observable; "
        "tables: levels.csv, gci.csv (final time), gci_by_time.csv (every program time).*",
        "",
    ]
    return "\n".join(lines)


def main(args) -> int:
    """``lcefem converge --config FILE --levels N``: run, analyse, write and print the study."""
    from lcefem.solvers.runtime.ranks import world

    case = args.prepared
    out = study.out_folder(args)
    comm = world()
    results = run_levels(
        pathlib.Path(args.config), case, out, args.levels, progress=not args.quiet, comm=comm
    )
    if comm is not None and comm.rank != 0:
        return 0
    h, studies, by_time = analyse_levels(results)
    cells = [r.summary["mesh"]["cells"] for r in results]
    warnings = study.ratio_warnings(h)
    name = (
        pathlib.Path(args.config).stem
        if pathlib.Path(args.config).stem != "case"
        else pathlib.Path(args.config).parent.name
    )
    study.write_study(out, name, h, "-", studies, warnings)
    changing = [s for s in studies if "mesh-independent" not in s.flags]
    if changing and len(changing) < len(studies):  # the plot: only what changes with the mesh
        from lcefem.validation.app import plots

        plots.convergence_plot(
            out / "convergence.png",
            h,
            [
                plots.ConvergenceSeries(
                    f"{s.metric} [{s.unit}]", [v - s.extrapolated for v in s.values], s.p
                )
                for s in changing
            ],
            xlabel="relative mesh size (N_0/N)^(1/3) [-]",
            title=f"{name}: |value - Richardson extrapolation| (Celik et al. 2008); "
            f"{len(studies) - len(changing)} mesh-independent observables not drawn",
        )
    if by_time:
        cols = list(by_time[0])
        study._write_csv(
            out / "gci_by_time.csv",
            cols,
            [
                [
                    f"{v:.12g}"
                    if isinstance(v, float) and math.isfinite(v)
                    else ("-" if isinstance(v, float) else str(v))
                    for v in row.values()
                ]
                for row in by_time
            ],
        )
    geo = case.mesh_file.suffix.lower() == ".geo"
    info = [
        f"{i}: {n} cells, "
        + (
            f"size factor {case.mesh['size_factor'] / 2**i:g}"
            if geo
            else f"refine {case.mesh['refine'] + i}"
        )
        for i, n in enumerate(cells)
    ]
    write_text(
        out / "report.md",
        report_markdown(pathlib.Path(args.config).resolve(), h, cells, studies, warnings, info),
    )
    study.print_summary(studies, h)
    for w in warnings:
        print(f"warning: {w}")
    print(
        f"report: {out / 'report.md'}   tables: {out / 'gci.csv'}   plot: {out / 'convergence.png'}"
    )
    return 0
