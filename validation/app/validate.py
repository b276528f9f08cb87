"""Validation cases against experiment, closed forms and other models: table, plots, report.

``lcefem validate [CASE ...] [--quick] [--out DIR] [--resume] [--list] [--quiet]``

Each case runs in ``DIR/<case>/`` (its CSV data and PNG figures; emptied before the case runs);
when it completes, its results are written LAST, atomically, to ``DIR/<case>/metrics.json`` (the
completion marker ``--resume`` looks for). ``DIR/report.md`` and ``DIR/metrics.json`` are written
before the first case (every selected case "not run") and after every case, so a killed run leaves a
report that lists every selected case with its state and says it is incomplete. A case whose solver
fails (state "failed") or that raises ("error") is reported and the run goes on; Ctrl-C or SIGTERM
stop it (that case "interrupted", the rest "not run").

Under ``mpiexec -n N`` the cases are farmed over the N ranks, each case whole on one rank
(:mod:`lcefem.validation.app.farm`): the same files, answers and exit status as the serial run.

Exit status: 0 when every case ran (whether its metrics pass or fail), 1 when a case failed or
raised an error, 2 on bad input (unknown case, unusable --out), 130 / 143 when interrupted.
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import datetime
import json
import math
import pathlib
import shlex
import sys
import time
import traceback

from tqdm import tqdm

from lcefem.models.errors import ConvergenceError, InputError
from lcefem.solvers.interrupts import raise_if_interrupted
from lcefem.solvers.runtime.exits import EXIT_CASE_ERROR
from lcefem.solvers.runtime.files import (
    disk_error_message,
    is_disk_error,
    library_os_error,
    write_json,
    write_text,
)
from lcefem.solvers.runtime.outdir import add_out_arguments, remove_owned
from lcefem.solvers.runtime.ranks import world
from lcefem.solvers.runtime.signals import reinstall_signal_handlers
from lcefem.validation.app import phenomena, report
from lcefem.validation.app.report import CaseResult
from lcefem.validation.cases import Case, CaseContext, Metric, registry

DEFAULT_OUT = pathlib.Path("results/validation")
MARKER = "metrics.json"  #: per-case completion marker, written last


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "cases", nargs="*", metavar="CASE", help="cases to run (default: all; see --list)"
    )
    parser.add_argument("--quick", action="store_true", help="coarse resolution (CI)")
    parser.add_argument("--list", action="store_true", help="list the cases and exit")
    add_out_arguments(parser, str(DEFAULT_OUT), resume=True)


def select(names: list[str], cases: dict[str, Case]) -> list[Case]:
    """The cases named (all when ``names`` is empty); unknown names raise InputError listing known
    ones."""
    unknown = [n for n in names if n not in cases]
    if unknown:
        raise InputError(
            f"unknown case(s) {', '.join(unknown)}; known cases: "
            f"{', '.join(cases) or '(none registered)'}"
        )
    return [cases[n] for n in dict.fromkeys(names)] if names else list(cases.values())


def _relative(path: pathlib.Path, root: pathlib.Path) -> str:
    try:
        return pathlib.Path(path).resolve().relative_to(root.resolve()).as_posix()
    except ValueError:
        return str(pathlib.Path(path).resolve())


def run_case(case: Case, ctx: CaseContext, root: pathlib.Path) -> CaseResult:
    """Run ``case`` in ``ctx`` and check what it returns. Exceptions propagate to the caller.

    Metrics with an empty ``case`` field get the case's name; every recorded figure must exist.
    """
    ctx.case = case.name
    ctx.out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    try:
        metrics = case.run(ctx)
    finally:  # a case may have started a library that took the signals (gmsh, PETSc): retake them
        reinstall_signal_handlers()
    wall = time.perf_counter() - t0
    if not isinstance(metrics, (list, tuple)):
        raise TypeError(
            f"case {case.name} returned {type(metrics).__name__}, expected a list of Metric"
        )
    rows = []
    for m in metrics:
        if not isinstance(m, Metric):
            raise TypeError(f"case {case.name} returned {type(m).__name__}, expected Metric")
        if not m.case:
            m = dataclasses.replace(m, case=case.name)
        elif m.case != case.name:
            raise ValueError(f"case {case.name} returned a metric of case {m.case!r}")
        rows.append(m.as_dict())
    figures = []
    for path, caption in ctx.figures:
        if not path.is_file():
            raise FileNotFoundError(f"case {case.name} recorded figure {path} but did not write it")
        figures.append({"path": _relative(path, root), "caption": caption})
    mesh_size = None if ctx.mesh_size is None else float(ctx.mesh_size)
    return CaseResult(
        case=case.name,
        description=case.description,
        status="done",
        wall_time=wall,
        metrics=rows,
        figures=figures,
        quick=ctx.quick,
        level=ctx.level,
        phenomena=phenomena.evaluate(case.name, rows),
        mesh_size=mesh_size,
        mesh_size_unit=ctx.mesh_size_unit if mesh_size else "",
        finished=datetime.datetime.now().astimezone().isoformat(timespec="seconds"),
    )


def load_complete(
    case: Case, case_dir: pathlib.Path, root: pathlib.Path, quick: bool
) -> CaseResult | None:
    """The stored result of ``case`` if its marker exists, matches the resolution and its figures
    exist."""
    marker = case_dir / MARKER
    try:
        data = json.loads(marker.read_text(encoding="utf-8"))
    except (OSError, ValueError, RecursionError):  # none yet, or cut short: the case runs again
        return None
    problem = stored_shape_problem(data)
    if problem is not None:  # JSON, but not what lcefem writes: someone else's file
        raise InputError(
            f"--resume: '{marker}' is not a case result lcefem wrote ({problem}); remove "
            "it (the case then runs again) or choose another --out"
        )
    result = CaseResult.from_dict(data)
    if result.case != case.name or result.status != "done" or result.quick != quick:
        return None
    if not all((root / f["path"]).is_file() for f in result.figures):
        return None
    result.status = "reused"
    return result


_NUMBER = (int, float)
#: the fields of a stored case result read back by --resume, with the JSON types each may hold
_STORED = {
    "case": (str,),
    "description": (str,),
    "status": (str,),
    "wall_time": _NUMBER,
    "metrics": (list,),
    "figures": (list,),
    "quick": (bool,),
    "phenomena": (list,),
    "level": (int, type(None)),
    "mesh_size": (*_NUMBER, type(None)),
    "mesh_size_unit": (str,),
    "error": (str,),
    "finished": (str,),
    "rank": (int, type(None)),
}
_METRIC = {
    "case": (str,),
    "metric": (str,),
    "value": (*_NUMBER, type(None)),
    "unit": (str,),
    "reference": (*_NUMBER, type(None)),
    "tolerance": (*_NUMBER, type(None)),
    "passed": (bool, type(None)),
    "source": (str,),
}


def stored_shape_problem(data) -> str | None:
    """None when ``data`` (a case's metrics.json read back) has the shape :func:`_run_or_reuse`
    writes, else what is wrong, in a few words."""
    if not isinstance(data, dict):
        return f"a JSON {type(data).__name__}, not an object"
    for key, types in _STORED.items():
        if key in ("case", "status", "metrics", "figures", "quick") and key not in data:
            return f"no '{key}'"
        if key in data and (
            not isinstance(data[key], types) or (bool not in types and isinstance(data[key], bool))
        ):
            return f"'{key}' is a JSON {type(data[key]).__name__}"
    for i, row in enumerate(data["metrics"]):
        if not isinstance(row, dict):
            return f"metrics[{i}] is not an object"
        for key, types in _METRIC.items():
            if not isinstance(row.get(key), types) or (
                bool not in types and isinstance(row.get(key), bool)
            ):
                return f"metrics[{i}].{key} is missing or of the wrong type"
    for name in ("figures", "phenomena"):
        for i, entry in enumerate(data.get(name, [])):
            if not isinstance(entry, dict):
                return f"{name}[{i}] is not an object"
    for i, fig in enumerate(data["figures"]):
        if not isinstance(fig.get("path"), str) or not isinstance(fig.get("caption", ""), str):
            return f"figures[{i}] has no text 'path' and 'caption'"
        if (
            pathlib.PurePath(fig["path"]).is_absolute()
            or ".." in pathlib.PurePath(fig["path"]).parts
        ):
            return f"figures[{i}].path leaves the output folder"
    return None


def command_line(args: argparse.Namespace) -> str:
    parts = ["lcefem", "validate", *args.cases]
    parts += [
        flag
        for flag, on in (
            ("--quick", args.quick),
            ("--resume", args.resume),
            ("--overwrite", args.overwrite),
            ("--quiet", args.quiet),
        )
        if on
    ]
    parts += ["--out", str(args.out)]
    return shlex.join(parts)


def _use_rich() -> bool:
    try:
        import rich.console  # noqa: F401  (a dependency of meshio; optional here)
        import rich.table  # noqa: F401
    except ImportError:
        return False
    return True


def is_terminal(file) -> bool:
    return bool(getattr(file, "isatty", lambda: False)())


def print_table(rows: list[dict], title: str, file=None) -> None:
    """Console table: case, metric, value, reference ± tolerance, error, pass."""
    file = file or sys.stdout
    header = ("case", "metric", "value", "reference ± tol", "error", "pass")
    body = []
    for r in rows:
        unit = f" {r['unit']}" if r.get("unit") and r["unit"] != "-" else ""
        body.append(
            (
                r["case"],
                r["metric"],
                report.fmt_number(r["value"]) + (unit if r["value"] is not None else ""),
                report.fmt_reference(r),
                report.fmt_error(r),
                report.fmt_pass(r),
            )
        )
    if _use_rich():
        from rich.console import Console
        from rich.markup import escape
        from rich.table import Table

        table = Table(title=escape(title), show_lines=False)
        for h in header:
            table.add_column(
                h, overflow="fold", justify="right" if h in ("value", "error") else "left"
            )
        colour = {"pass": "green", "FAIL": "bold red", "info": "cyan"}
        for row in body:
            style = colour.get(row[-1], "bold magenta")
            table.add_row(*(escape(c) for c in row[:-1]), f"[{style}]{escape(row[-1])}[/]")
        width = None if is_terminal(file) else 160
        Console(file=file, width=width, highlight=False).print(table)
        return
    widths = [
        max(len(h), *(len(row[i]) for row in body)) if body else len(h)
        for i, h in enumerate(header)
    ]
    print(title, file=file)
    print("  ".join(h.ljust(w) for h, w in zip(header, widths)), file=file)
    print("  ".join("-" * w for w in widths), file=file)
    for row in body:
        print("  ".join(c.ljust(w) for c, w in zip(row, widths)), file=file)


def run_validation(
    cases: list[Case],
    out: pathlib.Path,
    *,
    quick: bool = False,
    resume: bool = False,
    quiet: bool = False,
    command: str = "lcefem validate",
    comm=None,
) -> list[CaseResult]:
    """Run ``cases`` into ``out``; returns their results (an interrupt propagates after the
    run-level files are written). With ``comm`` of more than one rank (every rank calls this) the
    cases are farmed over its ranks (:mod:`lcefem.validation.app.farm`); rank 0 writes the run-level
    files."""
    farmed = comm is not None and comm.size > 1
    lead = not farmed or comm.rank == 0
    if lead:
        out.mkdir(parents=True, exist_ok=True)
    results = [CaseResult(c.name, c.description, "not run", 0.0, quick=quick) for c in cases]
    t_start = time.perf_counter()

    def flush() -> None:
        write_json(out / "metrics.json", report.all_rows(results))
        report.write_report(
            out / "report.md",
            results,
            command=command,
            quick=quick,
            total_wall=time.perf_counter() - t_start,
            ranks=comm.size if farmed else 1,
        )

    if lead:
        flush()  # a run killed from now on leaves a report naming every case and its state
    bar = tqdm(
        total=len(cases), desc="validate", unit="case", disable=quiet or not lead, file=sys.stderr
    )
    if farmed:
        return _farm(cases, out, results, flush, bar, comm, quick=quick, resume=resume, quiet=quiet)
    for i, case in enumerate(cases):
        bar.set_postfix_str(case.name)
        try:
            results[i] = _run_or_reuse(case, out, quick=quick, resume=resume, quiet=quiet)
        except OSError as exc:  # a full disk (guarded_run lets only disk errors through): stop here
            results[i] = CaseResult(
                case.name,
                case.description,
                "error",
                0.0,
                quick=quick,
                error=disk_error_message(exc, out),
            )
            bar.close()
            with contextlib.suppress(
                OSError
            ):  # on a full disk the report may stay the last one written
                flush()
            raise
        flush()
        if results[i].status == "interrupted":
            bar.close()
            raise results[i].interrupt
        bar.update(1)
    bar.close()
    return results


def _farm(cases, out, results, flush, bar, comm, *, quick: bool, resume: bool, quiet: bool):
    """:func:`run_validation` over the ranks of ``comm``: largest expected cost first, each case on
    its rank's MPI.COMM_SELF, no progress bar inside a case (the ranks would write over each
    other)."""
    from mpi4py import MPI

    from lcefem.meshes.communicator import case_communicator
    from lcefem.validation.app import farm

    costs = farm.case_costs(quick)

    def cost(case: Case) -> float:  # [s]; a case --resume will reuse costs nothing
        if resume and load_complete(case, out / case.name, out, quick) is not None:
            return 0.0
        return costs.get(case.name, math.inf)

    def run_one(case: Case) -> CaseResult:
        with case_communicator(MPI.COMM_SELF):
            return _run_or_reuse(
                case, out, quick=quick, resume=resume, quiet=quiet, progress=False, rank=comm.rank
            )

    groups = farm.schedule(cases, cost) if comm.rank == 0 else None
    groups = comm.bcast(groups, root=0)  # every rank the same list (a --resume check may race)
    try:
        return farm.farm_validation(cases, groups, results, run_one, flush, bar, comm)
    finally:
        bar.close()


def _run_or_reuse(
    case: Case,
    out: pathlib.Path,
    *,
    quick: bool,
    resume: bool,
    quiet: bool,
    progress: bool | None = None,
    rank: int | None = None,
) -> CaseResult:
    """One case: reused when --resume finds it complete, else run in an emptied folder; its outcome
    as a CaseResult (an interrupt is returned in ``.interrupt``, to be raised after the report).
    ``progress``: the case's own progress bars (default: unless ``quiet``); ``rank``: the MPI rank
    running it when farmed (recorded in the result)."""
    case_dir = out / case.name
    if resume:
        stored = load_complete(case, case_dir, out, quick)
        if stored is not None:
            return stored
    # the case owns its folder: nothing of an earlier run may remain (a link there is removed, not
    # followed; a folder another live run holds a lock in is refused)
    remove_owned(case_dir)
    ctx = CaseContext(
        out=case_dir, quick=quick, progress=not quiet if progress is None else progress
    )
    result = guarded_run(
        case, case_dir, lambda: run_case(case, ctx, out), quick=quick, rank=rank, quiet=quiet
    )
    if result.status == "done":
        write_json(case_dir / MARKER, result.as_dict())  # LAST: marks the case complete
    return result


def guarded_run(
    case: Case,
    case_dir: pathlib.Path,
    run,
    *,
    quick: bool = False,
    rank: int | None = None,
    level: int | None = None,
    quiet: bool = True,
    label: str = "",
) -> CaseResult:
    """``run()`` (a CaseResult) with its outcome always returned: an interrupt as status
    "interrupted" (the exception in ``.interrupt``, to be raised after the report), a
    ConvergenceError as "failed" and any other exception as "error", with its traceback in
    ``case_dir/error.log`` and a one-line message (``label`` before it, e.g. the mesh level;
    printed unless ``quiet``). ``rank``: the MPI rank running it when farmed."""
    t0 = time.perf_counter()
    meta = {"quick": quick, "rank": rank, "level": level}
    try:
        try:
            return dataclasses.replace(run(), rank=rank)
        except Exception as exc:
            # A library may wrap the signal's exception in its own error (numba's compiler turns a
            # Ctrl-C/SIGTERM during a kernel's compilation into a RuntimeError): still an interrupt.
            raise_if_interrupted(exc)
            disk = library_os_error(exc) if isinstance(exc, RuntimeError) else None
            if disk is not None and is_disk_error(disk):
                raise disk from None
            raise
    except KeyboardInterrupt as exc:
        result = CaseResult(
            case.name,
            case.description,
            "interrupted",
            time.perf_counter() - t0,
            error=f"interrupted ({type(exc).__name__})",
            **meta,
        )
        result.interrupt = exc
        return result
    except OSError as exc:
        if is_disk_error(
            exc
        ):  # a full disk: no later case can write either; stop (report stays INCOMPLETE)
            raise
        return _errored(case, case_dir, exc, t0, meta, label, quiet)
    except Exception as exc:  # a failing case is reported and the run goes on
        return _errored(case, case_dir, exc, t0, meta, label, quiet)


def _errored(case, case_dir, exc, t0, meta, label, quiet) -> CaseResult:
    """The CaseResult of a case that raised ``exc`` (inside its except clause): traceback in
    ``case_dir/error.log``, one line on stderr."""
    case_dir.mkdir(parents=True, exist_ok=True)
    write_text(case_dir / "error.log", traceback.format_exc())
    msg = f"{label}{type(exc).__name__}: {exc}".splitlines()[0]
    status = "failed" if isinstance(exc, ConvergenceError) else "error"
    if not quiet:
        tqdm.write(f"lcefem validate: case {case.name} {status}: {msg}", file=sys.stderr)
    return CaseResult(
        case.name, case.description, status, time.perf_counter() - t0, error=msg, **meta
    )


def prepare(args: argparse.Namespace) -> None:
    """Under mpiexec (the cases farmed over the ranks), before any case module starts PETSc: each
    rank's PETSc world is its own (:func:`lcefem.validation.app.farm.petsc_world_per_rank`)."""
    comm = world()
    if comm is not None and comm.size > 1:
        from lcefem.validation.app import farm

        farm.petsc_world_per_rank()


def out_folder(args: argparse.Namespace) -> pathlib.Path:
    """--out, once the case names are known good (bad input must not create a folder)."""
    select(list(args.cases), registry())
    return args.out


def main(args: argparse.Namespace) -> int:
    cases = registry()
    # importing the FE case modules initialised PETSc, which took the signals
    reinstall_signal_handlers()
    if args.list:
        width = max((len(n) for n in cases), default=4)
        for c in cases.values():
            tags = ",".join(t for t, on in (("fe", c.fe), ("converge", c.convergence)) if on) or "-"
            print(f"{c.name.ljust(width)}  [{tags}]  {c.description}")
        return 0
    selected = select(list(args.cases), cases)
    comm = world()
    t_start = time.perf_counter()
    results = run_validation(
        selected,
        args.out,
        quick=args.quick,
        resume=args.resume,
        quiet=args.quiet,
        command=command_line(args),
        comm=comm,
    )
    failed = [r.case for r in results if r.status in ("failed", "error")]
    if comm is not None and comm.rank != 0:  # rank 0 prints; every rank returns the same status
        return EXIT_CASE_ERROR if failed else 0
    rows = report.all_rows(results)
    total = sum(r.wall_time for r in results if r.status != "reused")
    ranks = (
        f" on {comm.size} ranks in {time.perf_counter() - t_start:.1f} s wall"
        if comm is not None
        else ""
    )
    print_table(
        rows,
        title=f"lcefem validate{' --quick' if args.quick else ''}: {len(results)} cases, "
        f"{total:.1f} s{ranks}",
    )
    print(f"metrics: {args.out / 'metrics.json'}   report: {args.out / 'report.md'}")
    if failed:
        print(
            f"lcefem validate: {len(failed)} case(s) failed or raised an error: "
            f"{', '.join(failed)} "
            f"(see <out>/<case>/error.log)",
            file=sys.stderr,
        )
        return EXIT_CASE_ERROR
    return 0
