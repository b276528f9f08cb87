"""The ``lcefem`` command line: ``lcefem run TARGET ...``, ``lcefem validate``, ``lcefem converge``,
``lcefem uncertainty gridshell``, ``lcefem design``, ``lcefem mesh NAME``.

Every command goes through :func:`main`: signal handlers, the output folder's claim and lock
(lcefem.solvers.runtime), and one mapping of failures to a one-line message and an exit status:
0 done, 1 a validation case raised an error, 2 bad input or unusable output folder, 3 solver failure
or a result out of physical bounds, 130 Ctrl-C, 143 SIGTERM. Under mpiexec every rank agrees on the
exit (an error on one rank aborts them all) and rank 0 prints.
"""

from __future__ import annotations

import argparse
import contextlib
import importlib
import os
import sys
import time
import traceback

from lcefem.models.errors import ConvergenceError, InputError, PhysicalBoundsError
from lcefem.solvers.interrupts import Terminated, interrupt_in
from lcefem.solvers.petsc_options import (
    forget_solver_options,
    own_petsc_environment,
    skip_petscrc_files,
)
from lcefem.solvers.runtime.exits import EXIT_INPUT, interrupt_exit_code
from lcefem.solvers.runtime.exits import EXIT_SOLVER as EXIT_CONVERGENCE
from lcefem.solvers.runtime.files import disk_error_message, library_os_error, write_json
from lcefem.solvers.runtime.inputs import check_jit_cache, check_start, matplotlib_folder_note
from lcefem.solvers.runtime.outdir import claim_out
from lcefem.solvers.runtime.ranks import world, world_rank
from lcefem.solvers.runtime.run import finish_pending
from lcefem.solvers.runtime.signals import (
    install_signal_handlers,
    keep_petsc_off_signals,
    reinstall_signal_handlers,
    restore_signal_handlers,
)
from lcefem.solvers.runtime.streams import guarded_streams
from lcefem.validation.app.commands import RUN_TARGETS

#: commands besides ``run``: name -> its module (with add_arguments and main), written out in full
#: so that a module's move is one edit here (scripts/dev/rooms.py rewrites these strings)
COMMANDS = {
    "validate": "lcefem.validation.app.validate",
    "converge": "lcefem.validation.app.converge",
    "uncertainty": "lcefem.validation.studies.gridshell.uncertainty",
    "design": "lcefem.validation.studies.design.design",
    "control": "lcefem.validation.studies.design.control",
    "calibrate": "lcefem.validation.studies.gridshell.calibrate",
    "mesh": "lcefem.validation.app.mesh",
}
EXIT_BROKEN_PIPE = 128 + 13  #: as a Unix tool killed by SIGPIPE when its reader closes the pipe
AGREE_SECONDS = 3.0  #: s, how long a failing rank waits for the others before aborting them
ABORT_FLUSH_SECONDS = (
    0.5  #: s, the launcher's time to forward the aborting rank's last line (see _end)
)
INPUT_FILES = (
    "config",
    "schedule",
)  #: options naming files a command reads (--overwrite must spare them)


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # argparse's own errors: one line, exit 2
        if world_rank() == 0:
            sys.stderr.write(f"{self.prog}: error: {message}\n")
        self.exit(EXIT_INPUT)


def build_parser(argv: list[str] | None = None) -> argparse.ArgumentParser:
    """The parser; with ``argv`` naming a command or a run target, only that command's or
    target's module is imported (the others are bare entries); without one, every module."""
    parser = _Parser(prog="lcefem", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    run = sub.add_parser("run", help="run one simulation")
    targets = run.add_subparsers(
        dest="target",
        required=True,
        parser_class=_Parser,
        metavar="{" + ",".join(RUN_TARGETS) + "}",
    )
    # Import only the modules the command line names: a command's module pulls in FEniCSx, scipy,
    # VTK or matplotlib (0.3-2 s each), and a refused input should be refused at once. The others
    # get a bare entry so that argparse still lists every choice; the top-level help imports all.
    wanted, commands = list(RUN_TARGETS), list(COMMANDS)
    if argv and argv[0] == "run":
        commands = []
        if len(argv) >= 2 and argv[1] in RUN_TARGETS:
            wanted = [argv[1]]
        elif len(argv) >= 2 and not argv[1].startswith("-"):
            wanted = []  # an unknown target
    elif argv and argv[0] in COMMANDS:
        wanted, commands = [], [argv[0]]
    elif argv and not argv[0].startswith("-"):
        wanted, commands = [], []  # an unknown command: argparse's one-line error
    for group, table, chosen in ((targets, RUN_TARGETS, wanted), (sub, COMMANDS, commands)):
        for name, module in table.items():
            if name not in chosen:
                group.add_parser(name)
                continue
            mod = importlib.import_module(module)
            p = group.add_parser(name, help=(mod.__doc__ or "").strip().splitlines()[0])
            mod.add_arguments(p)
            p.set_defaults(_module=mod)
    return parser


def _classify(exc: BaseException, out=None) -> tuple[int, str]:
    """(exit status, one-line message) of an exception ending a command (``out``: the command's
    output folder, the only place a disk error may be blamed on)."""
    exc = interrupt_in(exc) or exc  # a signal wrapped in a library's error is still a signal
    if isinstance(exc, KeyboardInterrupt):
        name = "SIGTERM" if isinstance(exc, Terminated) else "Ctrl-C"
        return (
            interrupt_exit_code(exc),
            f"lcefem: interrupted ({name}); converged steps are kept as *.partial.* files",
        )
    if isinstance(
        exc, BrokenPipeError
    ):  # the reader went away (``| head``): stop quietly, as Unix tools do
        return EXIT_BROKEN_PIPE, ""
    if isinstance(exc, InputError):
        return EXIT_INPUT, f"lcefem: error: {exc}"
    if isinstance(exc, ConvergenceError):
        return EXIT_CONVERGENCE, f"lcefem: stopped: {exc}"
    if isinstance(exc, OSError):
        return EXIT_INPUT, f"lcefem: error: {disk_error_message(exc, out)}"
    disk = library_os_error(exc) if isinstance(exc, RuntimeError) else None
    if disk is not None:  # a C++ writer's (ADIOS2, VTK) error text naming an errno and its file
        return EXIT_INPUT, f"lcefem: error: {disk_error_message(disk, out)}"
    if type(exc).__module__.startswith(
        "petsc4py"
    ):  # raised while setting up: an option PETSc rejects
        first = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        return (
            EXIT_INPUT,
            f"lcefem: error: PETSc refused the set-up ({first}); check the [petsc] options",
        )
    return 1, "".join(traceback.format_exception(exc)).rstrip()  # a bug: keep the traceback


def _failure_json(out, exc: ConvergenceError, args, comm) -> None:
    """failure.json of a run that stopped (exit 3) before its run skeleton wrote one: during set-up
    (the first solve of a problem being built), or in a command without a Run."""
    import pathlib

    if out is None or (comm is not None and comm.rank != 0):
        return
    path = pathlib.Path(out) / "failure.json"
    if path.exists() or not pathlib.Path(out).is_dir():
        return
    prepared = getattr(args, "prepared", None)
    config = prepared.resolved() if hasattr(prepared, "resolved") else None
    with contextlib.suppress(Exception):  # the original error matters more than this record
        write_json(
            path,
            {
                "status": "failed",
                "kind": "out of physical bounds"
                if isinstance(exc, PhysicalBoundsError)
                else "no convergence",
                "where": getattr(exc, "where", ""),
                "reason": getattr(exc, "reason", str(exc)),
                "last_converged": None,
                "config": config,
            },
        )


def _end(code: int, message: str, comm) -> int:
    """Print ``message`` once and return ``code`` on every rank; when the other ranks do not fail
    too (they wait in a collective of their own), abort them all rather than hang."""
    if comm is None:
        if code == EXIT_BROKEN_PIPE:
            # Later writes (and the interpreter's final flush) must not raise again on the closed
            # pipe.
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        else:
            print(message, file=sys.stderr)
        return code
    req = _ERRORS.Ibarrier()
    deadline = time.monotonic() + AGREE_SECONDS
    while not req.Test():
        if time.monotonic() > deadline:
            finish_pending(agreed=False)
            print(
                f"{message} [rank {comm.rank}; aborting the other ranks]",
                file=sys.stderr,
                flush=True,
            )
            # MPICH's launcher forwards a rank's stderr through its proxy; MPI_Abort kills the
            # proxy's children at once, and under load the line above was lost on its way (CI, stop
            # 51). A short pause lets the proxy forward it before the abort.
            time.sleep(ABORT_FLUSH_SECONDS)
            comm.Abort(code)
        time.sleep(0.01)
    finish_pending(agreed=True)
    if comm.rank == 0:
        print(message, file=sys.stderr, flush=True)
    return code


_ERRORS = (
    None  # a duplicate of COMM_WORLD: failing ranks agree there without disturbing the solvers
)


def main(argv: list[str] | None = None) -> int:
    with guarded_streams():  # how stdout/stderr are connected never changes the outcome
        return _main(argv)


def _main(argv: list[str] | None) -> int:
    global _ERRORS
    argv = sys.argv[1:] if argv is None else list(argv)
    try:  # before any library is imported (dolfinx reads sys.argv, numba its environment)
        check_start(argv)
    except InputError as exc:
        return _end(EXIT_INPUT, f"lcefem: error: {exc}", None)
    note = matplotlib_folder_note()
    if note and world_rank() == 0:
        print(note, file=sys.stderr)
    ignored = own_petsc_environment()
    if ignored and world_rank() == 0:
        print(
            f"lcefem: PETSC_OPTIONS ignored ({ignored[:80]}): solver options come only from a case "
            "file's [petsc] section (docs/failure_modes.md)",
            file=sys.stderr,
        )
    previous = install_signal_handlers()
    keep_petsc_off_signals()
    skipped = skip_petscrc_files()  # after PETSC_OPTIONS is lcefem's own: PETSc may start here
    if skipped and world_rank() == 0:
        print(
            f"lcefem: {', '.join(skipped)} ignored: solver options come only from a case file's "
            "[petsc] section (docs/failure_modes.md)",
            file=sys.stderr,
        )
    comm = None
    out = None
    try:
        parser = build_parser(argv)
        args = parser.parse_args(argv)
        reinstall_signal_handlers()  # importing PETSc installed its own for SIGTERM
        check_jit_cache()
        comm = world()
        if comm is not None:
            _ERRORS = comm.Dup()
        mod = args._module
        if getattr(args, "list", False):
            return int(mod.main(args) or 0)
        parallel = getattr(mod, "PARALLEL", True)
        if comm is not None and not (parallel(args) if callable(parallel) else parallel):
            name = f"run {args.target}" if args.command == "run" else args.command
            raise InputError(f"{name}: runs in serial only; start it without mpiexec")
        if hasattr(mod, "prepare"):  # bad input is refused before the output folder is touched
            args.prepared = mod.prepare(args)
        out = mod.out_folder(args) if hasattr(mod, "out_folder") else args.out
        command = (
            f"run {args.target}"
            if args.command == "run"
            else (
                f"converge {args.case or args.config}"
                if args.command == "converge"
                else args.command
            )
        )
        inputs = {f"--{flag}": getattr(args, flag, None) for flag in INPUT_FILES}
        with claim_out(
            out,
            resume=getattr(args, "resume", None),
            overwrite=args.overwrite,
            comm=comm,
            command=command,
            inputs=inputs,
        ):
            try:
                return int(mod.main(args) or 0)
            except (
                ConvergenceError
            ) as exc:  # stopped before its Run existed: failure.json still says why
                _failure_json(out, exc, args, comm)
                raise
    except BaseException as exc:
        if isinstance(exc, SystemExit):
            raise
        code, message = _classify(exc, out)
        return _end(code, message, comm)
    finally:
        forget_solver_options()  # before PETSc's exit report of unused options
        restore_signal_handlers(previous)  # lcefem used as a library goes back to normal


if __name__ == "__main__":
    sys.exit(main())
