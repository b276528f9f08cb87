"""Mesh-convergence study of one case: observed order, Richardson extrapolation, GCI.

``lcefem converge CASE [--levels N] [--prolong] [--out DIR] [--resume] [--quiet]``

(``lcefem converge --config robot.toml --levels 3``: the same study of a user's body,
:mod:`lcefem.validation.app.converge_body`.)

Runs the case at refinement levels 0..N-1 (N >= 4; ``ctx.level = i``, the case sets
``ctx.mesh_size``) in ``DIR/level<i>/``; ``--resume`` reuses levels whose outputs are complete
(their ``metrics.json`` marker, written last). For every metric it reports, on the finest three
levels, the observed order p, the Richardson-extrapolated value and the fine-grid Grid Convergence
Index with safety factor 1.25 (Celik et al. 2008, J. Fluids Eng. 130, 078001;
lcefem.validation.studies.verification.gci), and flags

- ``oscillatory``: successive differences change sign;
- ``diverging``: the finest difference is not smaller than the one before;
- ``drifting``: the observed orders of successive level triples differ by more than 20 % of their
  mean (not yet in the asymptotic range);
- ``mesh-independent``: the value does not change with the mesh (p undefined, GCI 0).

Under ``mpiexec -n N`` without ``--prolong`` the levels are independent and farmed over the N ranks,
finest first, each whole on one rank (the serial answers; rank 0 writes the study): the wall time is
about the finest level's rather than the sum. With ``--prolong`` they run in order, each on all
ranks.

``--prolong`` (cases registered with ``prolong=True``): level 0 is solved as usual, every finer
level starts from the previous level's converged state interpolated onto its mesh
(``ctx.prolong_from``) and solves at the full load from there (the FE gridshell: the residual
homotopy of ``GridshellFE.settle``), where a path from scratch is too costly on the fine meshes
(the FE gridshell dome: ~300 Newton iterations per level from flat). The equilibrium must be the
same one the path from scratch reaches; the case states how that was checked.

It checks that each refinement ratio h_(i)/h_(i+1) is at least 1.3 (Celik et al. 2008, step 2) and
says so when not. Writes ``DIR/levels.csv`` (metric values per level, units in the headers),
``DIR/gci.csv`` (one row per metric), ``DIR/convergence.json`` and ``DIR/convergence.png`` (log-log
|value - extrapolated| vs mesh size per metric).
"""

from __future__ import annotations

import argparse
import csv
import dataclasses
import io
import math
import pathlib
import sys
from dataclasses import asdict, dataclass, field

import numpy as np

from lcefem.models.errors import ConvergenceError, InputError
from lcefem.solvers.runtime.files import write_json, write_text
from lcefem.solvers.runtime.outdir import add_out_arguments, remove_owned
from lcefem.validation.app import plots
from lcefem.validation.app.validate import MARKER, guarded_run, is_terminal, load_complete, run_case
from lcefem.validation.cases import CaseContext, registry
from lcefem.validation.studies.verification import gci as gci_mod

MIN_LEVELS = 4
#: Most levels a study may ask for: the meshes refine up to level 8 (StripMesh, CompositeBeamMesh,
#: GridshellFEMesh, KaptonRibbonMesh: ``maximum=8``), so levels 0..8; more would fail at level 9
#: after running every coarser one.
MAX_LEVELS = 9
MIN_RATIO = 1.3  # Celik et al. 2008: refinement ratio r = h_coarse/h_fine should exceed 1.3
DRIFT_TOL = (
    0.20  # relative spread of successive observed orders flagged as drift (not one power of h)
)
ZERO_REL = 1e-12  # differences below this fraction of |value| count as zero


@dataclass
class MetricConvergence:
    """Convergence of one metric over the levels (coarse to fine)."""

    metric: str
    unit: str
    values: list[float]
    p: float
    extrapolated: float
    e_a: float
    e_ext: float
    gci_fine: float
    triple_orders: list[float]  #: observed order of each successive triple (coarsest first)
    flags: list[str] = field(default_factory=list)


def analyse(mesh_sizes, values, metric: str = "", unit: str = "") -> MetricConvergence:
    """Convergence of one metric given per level (coarse to fine, mesh sizes decreasing)."""
    h = np.asarray(mesh_sizes, float)
    f = np.asarray(values, float)
    if h.size < 3 or h.size != f.size:
        raise ValueError("need at least three levels with one value each")
    if np.any(np.diff(h) >= 0):
        raise ValueError(f"mesh sizes must decrease with the level: {h.tolist()}")
    nan = math.nan
    if not np.all(np.isfinite(f)):
        return MetricConvergence(
            metric, unit, f.tolist(), nan, nan, nan, nan, nan, [], ["missing values"]
        )
    scale = max(np.abs(f).max(), 1e-300)
    d = np.diff(f)
    d[np.abs(d) <= ZERO_REL * scale] = 0.0
    flags = []
    if not d.any():
        res = gci_mod.gci((h[-1], h[-2], h[-3]), (f[-1], f[-1], f[-1]))
        return MetricConvergence(
            metric,
            unit,
            f.tolist(),
            res.p,
            res.extrapolated,
            res.e_a,
            res.e_ext,
            res.gci_fine,
            [],
            ["mesh-independent"],
        )
    nz = np.sign(d[d != 0])
    if np.any(nz[1:] != nz[:-1]):
        flags.append("oscillatory")
    if abs(d[-1]) >= abs(d[-2]):
        flags.append("diverging")
    orders = []
    for i in range(f.size - 2):  # triple (i, i+1, i+2): coarse, medium, fine
        hf = (h[i + 2], h[i + 1], h[i])
        ff = (f[i + 2], f[i + 1], f[i])
        orders.append(gci_mod.observed_order(hf, ff)[0])
    fin = [p for p in orders if math.isfinite(p)]
    if len(fin) >= 2 and (max(fin) - min(fin)) > DRIFT_TOL * abs(np.mean(fin)):
        flags.append("drifting")
    res = gci_mod.gci((h[-1], h[-2], h[-3]), (f[-1], f[-2], f[-3]))
    if not math.isfinite(res.p):
        flags.append("no observed order")
    return MetricConvergence(
        metric,
        unit,
        f.tolist(),
        res.p,
        res.extrapolated,
        res.e_a,
        res.e_ext,
        res.gci_fine,
        orders,
        flags,
    )


def ratio_warnings(mesh_sizes) -> list[str]:
    """Messages for refinement ratios below MIN_RATIO."""
    h = list(mesh_sizes)
    return [
        f"refinement ratio between levels {i} and {i + 1} is {h[i] / h[i + 1]:.3f} < {MIN_RATIO} "
        f"(Celik et al. 2008 ask for > 1.3)"
        for i in range(len(h) - 1)
        if h[i] / h[i + 1] < MIN_RATIO
    ]


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "case",
        metavar="CASE",
        nargs="?",
        help="a case with convergence support (lcefem validate --list)",
    )
    parser.add_argument(
        "--config",
        help="instead of CASE: a body's case file (lcefem run body; "
        "docs/own_robot.md), refined by its .geo's size factor or uniformly",
    )
    parser.add_argument(
        "--levels",
        type=int,
        default=None,
        help=f"number of levels (CASE: >= {MIN_LEVELS}, default {MIN_LEVELS}; "
        "--config: 3 to 5, default 3)",
    )
    parser.add_argument(
        "--prolong",
        action="store_true",
        help="start each level from the previous level's solution interpolated onto "
        "its mesh (cases that support it)",
    )
    add_out_arguments(parser, None, resume=True)  # default: results/converge/<case>


def _fmt(v: float, spec: str = ".5g") -> str:
    return "-" if v is None or not math.isfinite(v) else format(v, spec)


def write_outputs(
    out: pathlib.Path,
    case_name: str,
    mesh_sizes,
    mesh_unit: str,
    studies: list[MetricConvergence],
    warnings: list[str],
) -> None:
    """levels.csv, gci.csv, convergence.json and convergence.png in ``out`` (each atomically)."""
    out.mkdir(parents=True, exist_ok=True)
    cols = {"level [-]": list(range(len(mesh_sizes))), f"mesh size [{mesh_unit}]": list(mesh_sizes)}
    for s in studies:
        cols[f"{s.metric} [{s.unit}]"] = s.values
    _write_csv(
        out / "levels.csv", list(cols), [[f"{v:.12g}" for v in row] for row in zip(*cols.values())]
    )
    _write_csv(
        out / "gci.csv",
        [
            "metric",
            "unit",
            "finest value [unit]",
            "observed order p [-]",
            "extrapolated value [unit]",
            "e_a [-]",
            "e_ext [-]",
            "GCI_fine [-]",
            "triple orders [-]",
            "flags",
        ],
        [
            [
                s.metric,
                s.unit,
                f"{s.values[-1]:.12g}",
                _fmt(s.p, ".6g"),
                _fmt(s.extrapolated, ".12g"),
                _fmt(s.e_a, ".6g"),
                _fmt(s.e_ext, ".6g"),
                _fmt(s.gci_fine, ".6g"),
                " ".join(_fmt(p, ".4g") for p in s.triple_orders),
                " ".join(s.flags),
            ]
            for s in studies
        ],
    )
    write_json(
        out / "convergence.json",
        {
            "case": case_name,
            "mesh_sizes": list(mesh_sizes),
            "mesh_size_unit": mesh_unit,
            "safety_factor": gci_mod.SAFETY_FACTOR,
            "warnings": warnings,
            "metrics": [asdict(s) for s in studies],
        },
    )
    series = [
        plots.ConvergenceSeries(
            f"{s.metric} [{s.unit}]", [v - s.extrapolated for v in s.values], s.p
        )
        for s in studies
    ]
    plots.convergence_plot(
        out / "convergence.png",
        mesh_sizes,
        series,
        xlabel=f"mesh size [{mesh_unit}]",
        title=f"{case_name}: |value - Richardson extrapolation| (Celik et al. 2008)",
    )


def _write_csv(path: pathlib.Path, header: list[str], rows: list[list[str]]) -> None:
    text = io.StringIO()
    w = csv.writer(text, lineterminator="\n")
    w.writerow(header)
    w.writerows(rows)
    write_text(path, text.getvalue())


def print_summary(studies: list[MetricConvergence], mesh_sizes, file=None) -> None:
    file = file or sys.stdout
    header = [
        "metric",
        "unit",
        *[f"h={h:.3g}" for h in mesh_sizes],
        "p",
        "extrapolated",
        "e_a",
        "e_ext",
        "GCI_fine",
        "flags",
    ]
    rows = [
        [
            s.metric,
            s.unit,
            *[_fmt(v) for v in s.values],
            _fmt(s.p, ".3f"),
            _fmt(s.extrapolated, ".6g"),
            _fmt(100 * s.e_a, ".3g") + " %",
            _fmt(100 * s.e_ext, ".3g") + " %",
            _fmt(100 * s.gci_fine, ".3g") + " %",
            ", ".join(s.flags) or "ok",
        ]
        for s in studies
    ]
    try:
        from rich.console import Console
        from rich.table import Table
    except ImportError:
        widths = [max(len(h), *(len(r[i]) for r in rows)) for i, h in enumerate(header)]
        for line in [header, ["-" * w for w in widths], *rows]:
            print("  ".join(c.ljust(w) for c, w in zip(line, widths)), file=file)
        return
    from rich.markup import escape

    table = Table(title="convergence (finest triple; GCI with Fs = 1.25)")
    for h in header:
        table.add_column(escape(h), overflow="fold")
    for r in rows:
        table.add_row(*(escape(c) for c in r))
    Console(file=file, width=None if is_terminal(file) else 180, highlight=False).print(table)


def run_study(
    case,
    out: pathlib.Path,
    levels: int,
    quiet: bool = False,
    resume: bool = False,
    prolong: bool = False,
    comm=None,
):
    """Run ``case`` at levels 0..levels-1 and analyse; returns (mesh sizes, unit, studies,
    warnings).

    With ``resume``, a level whose directory holds a complete result of this case is reused; with
    ``prolong``, level i > 0 gets ``ctx.prolong_from`` = the folder of level i - 1. With ``comm`` of
    more than one rank and no ``prolong`` (every rank calls this), the levels are farmed over its
    ranks, finest first (:func:`_farm_levels`); every rank returns the same analysis."""
    from tqdm import tqdm

    if comm is not None and comm.size > 1 and not prolong:
        results = _farm_levels(case, out, levels, quiet=quiet, resume=resume, comm=comm)
    else:
        results = []
        for level in tqdm(
            range(levels),
            desc=f"converge {case.name}",
            unit="level",
            disable=quiet,
            file=sys.stderr,
        ):
            results.append(
                _run_level(case, out, level, resume=resume, prolong=prolong, progress=not quiet)
            )
    h = [r.mesh_size for r in results]
    unit = results[0].mesh_size_unit or "-"
    names: dict[str, str] = {}
    for r in results:
        for m in r.metrics:
            names.setdefault(m["metric"], m["unit"])
    studies = []
    for name, metric_unit in names.items():
        vals = []
        for r in results:
            found = [m["value"] for m in r.metrics if m["metric"] == name]
            vals.append(float(found[0]) if found and found[0] is not None else math.nan)
        studies.append(analyse(h, vals, name, metric_unit))
    return h, unit, studies, ratio_warnings(h)


def _run_level(
    case,
    out: pathlib.Path,
    level: int,
    *,
    resume: bool,
    prolong: bool,
    progress: bool,
    rank: int | None = None,
):
    """One level of the study in ``out/level<i>``: reused when ``resume`` finds it complete, else
    run in an emptied folder; its CaseResult (exceptions propagate). ``rank``: the MPI rank running
    it when farmed (recorded in the result)."""
    ctx = CaseContext(
        out=out / f"level{level}",
        quick=False,
        level=level,
        progress=progress,
        prolong_from=out / f"level{level - 1}" if prolong and level > 0 else None,
    )
    stored = load_complete(case, ctx.out, out, quick=False) if resume else None
    if stored is not None and stored.mesh_size:
        return stored
    # the level owns its folder: nothing of an earlier run may remain (a link is removed, not
    # followed)
    remove_owned(ctx.out)
    res = dataclasses.replace(run_case(case, ctx, out), rank=rank)
    if res.mesh_size is None or not res.mesh_size > 0:
        raise RuntimeError(f"case {case.name} did not set ctx.mesh_size (> 0) at level {level}")
    write_json(ctx.out / MARKER, res.as_dict())  # LAST: this level is complete
    return res


def _farm_levels(case, out: pathlib.Path, levels: int, *, quiet: bool, resume: bool, comm) -> list:
    """``mpiexec -n N lcefem converge`` (without ``--prolong``, so the levels are independent): the
    levels handed out over the N ranks by :mod:`lcefem.validation.app.farm`, finest (costliest)
    first, each level whole on its rank's ``MPI.COMM_SELF``, so its answers are the serial run's. A
    level that raises ends the study with its one-line error after the other ranks have finished
    theirs (its traceback in ``out/level<i>/error.log``); an interrupt stops every rank (exit 130 /
    143)."""
    from mpi4py import MPI

    from tqdm import tqdm

    from lcefem.meshes.communicator import case_communicator
    from lcefem.validation.app import farm
    from lcefem.validation.app.report import CaseResult

    items = list(range(levels))
    results = [CaseResult(case.name, case.description, "not run", 0.0, level=i) for i in items]

    def run_one(level: int) -> CaseResult:
        with case_communicator(MPI.COMM_SELF):
            return guarded_run(
                case,
                out / f"level{level}",
                lambda: _run_level(
                    case, out, level, resume=resume, prolong=False, progress=False, rank=comm.rank
                ),
                rank=comm.rank,
                level=level,
                label=f"level {level}: ",
            )

    groups = [[i] for i in reversed(items)]  # the finest level costs most: first out
    bar = tqdm(
        total=levels,
        desc=f"converge {case.name} ({comm.size} ranks)",
        unit="level",
        disable=quiet or comm.rank != 0,
        file=sys.stderr,
    )
    try:
        results = farm.farm_validation(items, groups, results, run_one, lambda: None, bar, comm)
    finally:
        bar.close()
    failed = [r for r in results if r.status != "done"]
    if failed:  # every rank raises the same error (the CLI's exit agreement)
        r = failed[0]
        where = f"converge {case.name}"
        why = f"{r.error or r.status} (traceback in {out / f'level{r.level}' / 'error.log'})"
        raise (
            ConvergenceError(where, why)
            if r.status == "failed"
            else RuntimeError(f"{where}: {why}")
        )
    return results


def prepare(args: argparse.Namespace) -> None:
    """Under mpiexec without --prolong (the levels farmed over the ranks), before any case module
    starts PETSc: each rank's PETSc world is its own
    (:func:`lcefem.validation.app.farm.petsc_world_per_rank`). With --prolong the levels run in
    order, each solved on all the ranks (their FE in parallel)."""
    from lcefem.solvers.runtime.ranks import world

    if args.config is not None:  # a body's case file: checked now, before any folder or mesh
        return _prepare_body(args)
    comm = world()
    if comm is not None and comm.size > 1 and not args.prolong:
        from lcefem.validation.app import farm

        farm.petsc_world_per_rank()


def selected_case(args: argparse.Namespace):
    """The case to study (InputError for an unknown case, one without levels, too few levels)."""
    if args.case is None:
        raise InputError("converge: give a CASE (lcefem validate --list) or --config robot.toml")
    if args.levels is None:
        args.levels = MIN_LEVELS
    cases = registry()
    if args.case not in cases:
        raise InputError(f"unknown case '{args.case}'; known cases: {', '.join(cases) or '(none)'}")
    case = cases[args.case]
    if not case.convergence:
        able = [c.name for c in cases.values() if c.convergence]
        raise InputError(
            f"case '{case.name}' has no refinement levels; cases with levels: "
            f"{', '.join(able) or '(none)'}"
        )
    if getattr(args, "prolong", False) and not case.prolong:
        able = [c.name for c in cases.values() if c.prolong]
        raise InputError(
            f"--prolong: case '{case.name}' cannot start from a coarser level's state; "
            f"cases that can: {', '.join(able) or '(none)'}"
        )
    if not MIN_LEVELS <= args.levels <= MAX_LEVELS:
        raise InputError(
            f"--levels = {args.levels}: must be between {MIN_LEVELS} and {MAX_LEVELS} "
            "(the meshes' refinement levels 0..8)"
        )
    return case


def _prepare_body(args: argparse.Namespace):
    """The checked case file of ``--config`` (lcefem.validation.app.converge_body)."""
    from lcefem.solvers.problems.body_case import load_case
    from lcefem.validation.app.converge_body import MIN_LEVELS as BODY_LEVELS
    from lcefem.validation.app.converge_body import check_refinable

    if args.case is not None:
        raise InputError(f"converge: give CASE ({args.case!r}) or --config, not both")
    if args.prolong or getattr(args, "resume", False):
        raise InputError("converge --config: --prolong and --resume are for built-in cases")
    if args.levels is None:
        args.levels = BODY_LEVELS
    case = load_case(args.config)
    check_refinable(case, args.levels)
    return case


def out_folder(args: argparse.Namespace) -> pathlib.Path:
    """--out (default results/converge/<case>), once the input is known good."""
    if args.config is not None:
        path = pathlib.Path(args.config)
        return args.out or pathlib.Path("results/converge") / (
            path.parent.name if path.stem == "case" else path.stem
        )
    case = selected_case(args)  # checked even with --out: bad input must not touch a folder
    return args.out or pathlib.Path("results/converge") / case.name


#: the study's own files, under their final names only once all are written (convergence.json last:
#: the marker of a complete study); a study stopped while writing them leaves ``study.partial/``
STUDY_FILES = ("levels.csv", "gci.csv", "convergence.png", "convergence.json")


def write_study(
    out: pathlib.Path,
    case_name: str,
    mesh_sizes,
    mesh_unit: str,
    studies: list[MetricConvergence],
    warnings: list[str],
) -> None:
    """:func:`write_outputs` into ``out/study.part/``, then each file moved to ``out`` (the marker
    convergence.json last); an interrupt or error on the way renames the folder
    ``study.partial/``."""
    from lcefem.solvers.runtime.files import replace

    staging = out / "study.part"
    remove_owned(staging)  # a link planted there is removed, not followed
    try:
        write_outputs(staging, case_name, mesh_sizes, mesh_unit, studies, warnings)
        for name in STUDY_FILES:
            replace(staging / name, out / name)
        staging.rmdir()
    except BaseException:
        if staging.exists():
            partial = out / "study.partial"
            remove_owned(partial)
            replace(staging, partial)
        raise


def main(args: argparse.Namespace) -> int:
    if args.config is not None:
        from lcefem.validation.app import converge_body

        return converge_body.main(args)
    case = selected_case(args)
    out = out_folder(args)
    from lcefem.solvers.runtime.ranks import world

    comm = world()
    if comm is None or comm.rank == 0:  # an earlier study's results must not pass for this one's
        for name in (*STUDY_FILES, "study.partial"):
            remove_owned(out / name)
    h, unit, studies, warnings = run_study(
        case,
        out,
        args.levels,
        quiet=args.quiet,
        resume=args.resume,
        prolong=args.prolong,
        comm=comm,
    )
    if comm is not None and comm.rank != 0:  # rank 0 writes and prints the study
        return 0
    write_study(out, case.name, h, unit, studies, warnings)
    print_summary(studies, h)
    for w in warnings:
        print(f"warning: {w}")
    print(f"tables: {out / 'levels.csv'}, {out / 'gci.csv'}   plot: {out / 'convergence.png'}")
    return 0
