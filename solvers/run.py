"""The run skeleton: what every ``lcefem run X``, ``validate`` and ``converge`` shares.

It lives in solvers/ (not validation/) because it drives any problem, knows nothing of experiments,
and the numerics need one piece of it: :func:`raise_if_interrupted`, so that a solver catching
PETSc errors never turns Ctrl-C into a non-convergence. It imports neither FEniCSx nor MPI at module
level, so the bar-and-hinge and rod targets start without them.

Pieces, each used by every command:

* exit codes (:data:`EXIT_INPUT` ...), and :func:`install_signal_handlers` (SIGTERM becomes
  :class:`Terminated`, a KeyboardInterrupt, so every ``finally`` runs and partial files are kept);
* :func:`claim_out`: the output folder's ownership (refuses another run's results unless
  ``--resume`` or ``--overwrite``; a lock file while a run writes);
* :func:`check_physical`: physical bounds of inputs (every temperature, modulus, integer field) and
  :func:`check_row`: of results, during the run;
* :class:`CSVTable`, :func:`write_json`: writers with the ``.part`` convention (a file is complete
  only under its final name; a failed or interrupted run leaves ``*.partial.*``);
* :class:`Run`: one run's progress bar, history, outputs, failure.json and summary.json.
"""

from __future__ import annotations

import argparse
import contextlib
import csv
import dataclasses
import errno
import json
import math
import os
import pathlib
import shutil
import signal
import socket
import sys

from lcefem.models.errors import ConvergenceError, InputError
from lcefem.models.limits import ABSOLUTE_ZERO, DECOMPOSITION_TEMPERATURE, MAX_CURRENT, MAX_DURATION

EXIT_OK = 0
EXIT_CASE_ERROR = 1  #: validate: a case raised an error (the others still ran)
EXIT_INPUT = 2  #: bad input, or an output folder that cannot be used
EXIT_SOLVER = 3  #: the solver failed, or a result left its physical bounds
EXIT_SIGINT = 128 + signal.SIGINT  # 130, the shell's convention
EXIT_SIGTERM = 128 + signal.SIGTERM  # 143

LOCK = ".lcefem.lock"  #: "pid host" of the run writing the folder
STAMP = ".lcefem-out"  #: marks a folder written by lcefem (so --overwrite may empty it) and by which command
STAMP_TEXT = "written by lcefem; --overwrite may empty this folder\ncommand: {command}\n"


def stamped_command(out: pathlib.Path) -> str | None:
    """The command recorded in ``out``'s marker (``run strip``, ``validate``, ``converge CASE``), None
    when there is none (no marker, or one written before commands were recorded)."""
    try:
        text = (pathlib.Path(out) / STAMP).read_text(encoding="utf-8", errors="replace")
    except OSError:
        return None
    for line in text.splitlines():
        if line.startswith("command:"):
            return line[len("command:"):].strip() or None
    return None


# -- signals ------------------------------------------------------------------------------------
class Terminated(KeyboardInterrupt):
    """SIGTERM, raised like Ctrl-C so that the same clean-up runs; exit status 143."""


_received: list[int] = []  # signals received by this process (checked by solvers that catch errors)
_installed: list[bool] = []  # [True] while the command line owns SIGINT and SIGTERM


_deferred: list[bool] = []  # [True] inside deferred_signals(): record the signal, raise at the next check


def _on_signal(signum, frame):
    _received.append(signum)
    if _deferred:
        return
    raise Terminated() if signum == signal.SIGTERM else KeyboardInterrupt()


@contextlib.contextmanager
def deferred_signals():
    """Within this block SIGINT/SIGTERM are recorded, not raised where they land: the next
    :func:`raise_if_interrupted` (every :meth:`Run.record`) raises them. For loops of compiled code
    (numba) whose steps take milliseconds: an exception raised inside numba's or ctypes' C callbacks
    (e.g. while numba loads a cached kernel) crashed the process with SIGSEGV instead of exit 143,
    measured in test_interrupted_ribbon_leaves_only_partial_frames on a fresh clone."""
    _deferred[:] = [True]
    try:
        yield
    finally:
        _deferred.clear()
    raise_if_interrupted()


def install_signal_handlers() -> dict:
    """Ctrl-C and SIGTERM raise in the main thread (Python ignores SIGINT when started in the
    background of a script; SIGTERM would kill without clean-up). Returns the previous handlers."""
    _received.clear()
    _installed[:] = [True]
    previous = {sig: signal.signal(sig, _on_signal) for sig in (signal.SIGINT, signal.SIGTERM)}
    if hasattr(signal, "SIGPIPE"):
        previous[signal.SIGPIPE] = signal.signal(signal.SIGPIPE, signal.SIG_IGN)
    return previous


def reinstall_signal_handlers() -> None:
    """Take SIGINT and SIGTERM back from C libraries that set their own behind Python's back (PETSc
    at initialisation, gmsh when a mesh is built), if :func:`install_signal_handlers` was called."""
    if _installed:
        for sig in (signal.SIGINT, signal.SIGTERM):
            signal.signal(sig, _on_signal)
        if hasattr(signal, "SIGPIPE"):
            # Python's own setting: a closed pipe (``lcefem validate --list | head``) raises
            # BrokenPipeError, which the command line ends quietly; PETSc's handler would abort MPI.
            signal.signal(signal.SIGPIPE, signal.SIG_IGN)


def keep_petsc_off_signals() -> None:
    """PETSc, when it initialises (the first import of petsc4py.PETSc, which may come inside a case
    or a plot long after the command line took the signals), installs a handler of its own that ends
    the process on SIGTERM with status 15 ("Caught signal number 15") and no clean-up: the lock stays,
    .part files stay. PETSc's option -no_signal_handler, read from PETSC_OPTIONS at initialisation,
    stops that at the root; :func:`reinstall_signal_handlers` still guards the cases where PETSc was
    initialised before (a library user's own session)."""
    options = os.environ.get("PETSC_OPTIONS", "")
    if "-no_signal_handler" not in options.split():
        os.environ["PETSC_OPTIONS"] = f"{options} -no_signal_handler".strip()


def forget_solver_options(prefix: str = "lcefem_") -> None:
    """Remove lcefem's solver options (prefix ``lcefem_``) from PETSc's options database when a
    command ends. Each problem puts its options there for its own SNES, KSP and factorisation, which
    read them when they first need them; a problem that never needed one (a beam confirmed in 0
    Newton iterations never factorises, so ``mat_mumps_icntl_7`` is never read) left it for PETSc to
    report at exit as "options you set that were not used". Options a user gives are checked
    when the solver has read its own (lcefem.solvers.mechanics: an unread [petsc] option is refused)."""
    petsc = sys.modules.get("petsc4py.PETSc")
    if petsc is None:
        return
    with contextlib.suppress(Exception):
        db = petsc.Options()
        for name in db.getAll():
            if name.startswith(prefix):
                db.delValue(name)


def restore_signal_handlers(previous: dict) -> None:
    _installed.clear()
    _received.clear()  # a later run in this process (lcefem as a library) starts uninterrupted
    for sig, handler in previous.items():
        signal.signal(sig, handler)


def interrupt_in(exc: BaseException | None) -> KeyboardInterrupt | None:
    """The interrupt behind ``exc``: itself or one in its cause/context chain (a callback of PETSc's
    interrupted by Ctrl-C surfaces as a PETSc error; numba's compiler turns a signal that arrives
    while it compiles a kernel into a RuntimeError), or, when this process has received SIGINT or
    SIGTERM, a new one of that kind; None otherwise."""
    seen = exc
    while seen is not None:
        if isinstance(seen, KeyboardInterrupt):
            return seen
        seen = seen.__cause__ or seen.__context__
    if _received:
        return Terminated() if _received[-1] == signal.SIGTERM else KeyboardInterrupt()
    return None


def raise_if_interrupted(exc: BaseException | None = None) -> None:
    """Re-raise the interrupt hidden inside a library's error (:func:`interrupt_in`); no-op otherwise."""
    interrupt = interrupt_in(exc)
    if interrupt is not None:
        raise interrupt


def interrupt_exit_code(exc: KeyboardInterrupt) -> int:
    return EXIT_SIGTERM if isinstance(exc, Terminated) else EXIT_SIGINT


# -- physical bounds ----------------------------------------------------------------------------
class PhysicalBoundsError(ConvergenceError):
    """A result left its physical bounds (exit 3): the model is outside what it describes."""

    def __str__(self) -> str:
        return f"result out of physical bounds at {self.where}: {self.reason}"


TEMPERATURE_RANGE = (f"between {ABSOLUTE_ZERO} C (absolute zero) and {DECOMPOSITION_TEMPERATURE} C "
                     "(decomposition, lcefem.models.limits)")


def check_temperature(name: str, value: float) -> None:
    if not ABSOLUTE_ZERO < value < DECOMPOSITION_TEMPERATURE:
        raise InputError(f"{name} = {value} C: must be {TEMPERATURE_RANGE}")


def check_physical(config, section: str = "") -> None:
    """Bounds every parameter must satisfy whatever its section: currents [A] in [0, MAX_CURRENT],
    durations [s] up to MAX_DURATION, temperatures [C] above absolute
    zero and below decomposition, moduli [MPa] > 0 (other stiffness coefficients >= 0), integer fields integers.
    Walks nested dataclasses; the message names the field (``section.field``)."""
    for f in dataclasses.fields(config):
        value = getattr(config, f.name)
        name = f"{section}.{f.name}" if section else f.name
        if dataclasses.is_dataclass(value):
            check_physical(value, name)
            continue
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            continue
        if isinstance(f.default, int) and not isinstance(f.default, bool) and not isinstance(value, int):
            raise InputError(f"{name} = {value}: must be an integer")
        if not math.isfinite(value):
            raise InputError(f"{name} = {value}: must be a finite number")
        unit = f.metadata.get("unit")
        if unit == "A" and "current" in f.name and not 0.0 <= value <= MAX_CURRENT:
            raise InputError(f"{name} = {value} A: must be between 0 and {MAX_CURRENT} A (5 x the largest "
                             "current of seed 001, lcefem.models.limits)")
        if unit == "s" and "duration" in f.name and value > MAX_DURATION:
            raise InputError(f"{name} = {value} s: must be <= {MAX_DURATION} s (lcefem.models.limits)")
        if unit == "C":
            check_temperature(name, value)
        elif unit == "MPa" and "modulus" in f.name and not value > 0:
            raise InputError(f"{name} = {value} MPa: a modulus must be > 0 MPa")
        elif unit == "MPa" and value < 0:
            raise InputError(f"{name} = {value} MPa: must be >= 0 MPa")


def check_row(row: dict, where: str) -> None:
    """Results must be finite (time may be infinite: a steady state) and temperatures (columns in
    [C]) inside the physical range; raises :class:`PhysicalBoundsError`."""
    for key, value in row.items():
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            continue
        if not math.isfinite(value):
            if key.startswith("time") and value == math.inf:
                continue
            raise PhysicalBoundsError(where, f"{key} = {value} is not a finite number")
        if key.endswith("[C]") and not ABSOLUTE_ZERO < value < DECOMPOSITION_TEMPERATURE:
            raise PhysicalBoundsError(where, f"{key} = {value:.6g}: not {TEMPERATURE_RANGE}")


# -- disk errors ---------------------------------------------------------------------------------
#: errno -> (what happened, what to do): the causes of a write that fails, each named in one line
DISK_ERRORS = {
    errno.ENOSPC: ("no space left on the device", "free space or choose another --out"),
    errno.EDQUOT: ("disk quota exceeded", "free space in your quota or choose another --out"),
    errno.EROFS: ("read-only file system", "choose a writable --out"),
    errno.EACCES: ("permission denied", "choose a folder you may write to"),
    errno.EPERM: ("operation not permitted", "choose a folder you may write to"),
}


def is_disk_error(exc: BaseException) -> bool:
    """An OSError whose cause is the disk or its permissions (:data:`DISK_ERRORS`): no case can
    succeed after it, so validate stops rather than carry on."""
    return isinstance(exc, OSError) and exc.errno in DISK_ERRORS


def disk_error_message(exc: OSError) -> str:
    """One line: the file, the cause (with its errno name) and what to do."""
    where = f"'{exc.filename}'" if exc.filename else "a file"
    if exc.errno in DISK_ERRORS:
        cause, todo = DISK_ERRORS[exc.errno]
        return f"cannot write {where}: {cause} ({errno.errorcode[exc.errno]}); {todo}"
    return f"cannot write {where}: {exc.strerror or exc}"


@contextlib.contextmanager
def naming(path):
    """Re-raise an OSError without a file name (a write() on a full disk) as one naming ``path``."""
    try:
        yield
    except OSError as exc:
        if exc.filename is None and exc.errno is not None:
            raise OSError(exc.errno, exc.strerror or os.strerror(exc.errno), str(path)) from None
        raise


def library_os_error(exc: BaseException) -> OSError | None:
    """The OSError behind a C++ library's error text (ADIOS2: "couldn't write to file PATH : errno =
    28: No space left on device"), with its file named; None if the text names no errno."""
    import re

    text = re.sub(r"\x1b\[[0-9;]*m", "", str(exc))
    found = re.search(r"errno\s*=\s*(\d+)", text)
    if not found:
        return None
    code = int(found.group(1))
    path = re.search(r"file\s+(\S+)\s*:", text)
    return OSError(code, os.strerror(code), path.group(1) if path else None)


# -- reading case files -------------------------------------------------------------------------
def read_text(path, name: str) -> str:
    """The one decoding path of every file lcefem reads from the user (case files, schedules): UTF-8
    (TOML's encoding; a UTF-8 byte-order mark is skipped), else one InputError naming ``name`` (e.g.
    ``config = 'case.toml'``) and what was found: UTF-16, binary, undecodable bytes, unreadable."""
    path = pathlib.Path(path)
    if not path.is_file():
        raise InputError(f"{name}: file not found" if not path.exists() else f"{name}: not a file")
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise InputError(f"{name}: cannot read ({exc.strerror or exc})") from None
    if data[:2] in (b"\xff\xfe", b"\xfe\xff"):
        raise InputError(f"{name}: UTF-16 text; save it as UTF-8 (TOML files are UTF-8)")
    if b"\x00" in data:
        raise InputError(f"{name}: a binary file (NUL bytes), not a UTF-8 TOML text file")
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise InputError(f"{name}: not UTF-8 text (byte 0x{data[exc.start]:02x} at offset {exc.start}); "
                         "save it as UTF-8 (TOML files are UTF-8)") from None


def read_toml(path, name: str) -> dict:
    """A TOML file through :func:`read_text`; bad syntax is an InputError naming ``name``."""
    import tomllib

    try:
        return tomllib.loads(read_text(path, name))
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{name}: invalid TOML ({exc})") from None


# -- writers with the .part convention ----------------------------------------------------------
def partial_name(path: pathlib.Path) -> pathlib.Path:
    """history.csv -> history.partial.csv; beam_steps -> beam_steps.partial."""
    return path.with_name(f"{path.stem}.partial{path.suffix}")


def part_name(path: pathlib.Path) -> pathlib.Path:
    return path.with_name(path.name + ".part")


def replace(src: pathlib.Path, dst: pathlib.Path) -> None:
    """Move ``src`` onto ``dst`` (file or folder), removing what was there."""
    if dst.is_dir() and not dst.is_symlink():
        shutil.rmtree(dst)
    elif dst.exists():
        dst.unlink()
    os.replace(src, dst)


def _rank(comm) -> int:
    return 0 if comm is None else comm.rank


def _barrier(comm) -> None:
    if comm is not None and comm.size > 1:
        comm.barrier()


def json_safe(obj):
    """Plain JSON values: numpy scalars and arrays as Python ones, NaN and infinities as None, paths as
    strings (strict JSON)."""
    if hasattr(obj, "tolist"):  # numpy scalars and arrays
        obj = obj.tolist()
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    if isinstance(obj, dict):
        return {str(k): json_safe(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [json_safe(v) for v in obj]
    if isinstance(obj, pathlib.PurePath):
        return str(obj)
    return obj


def json_text(data) -> str:
    """Strict JSON text of ``data`` (:func:`json_safe`)."""
    return json.dumps(json_safe(data), indent=2, allow_nan=False) + "\n"


def write_text(path: pathlib.Path, text: str, comm=None) -> pathlib.Path:
    """Write ``text`` under ``path.part`` and rename (from rank 0 of ``comm``). A write that fails
    (a full disk) removes its ``.part`` (giving the space back) and leaves ``path`` as it was."""
    path = pathlib.Path(path)
    if _rank(comm) == 0:
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = part_name(path)
        try:
            with naming(tmp):
                tmp.write_text(text, encoding="utf-8")
        except BaseException:
            with contextlib.suppress(OSError):
                tmp.unlink(missing_ok=True)
            raise
        os.replace(tmp, path)
    _barrier(comm)
    return path


def write_json(path: pathlib.Path, data, comm=None) -> pathlib.Path:
    """Atomic strict JSON (see :func:`json_text`)."""
    return write_text(path, json_text(data), comm)


class CSVTable:
    """A table, one row per :meth:`append`, units in the headers (``time [s]``). With a path, rank 0
    writes ``<path>.part`` row by row (flushed) and :meth:`finalize` renames it to ``path``, or to
    ``*.partial.csv`` for an unfinished run; without one, rows are only kept in memory."""

    def __init__(self, path: pathlib.Path | None, columns: list[str], comm=None):
        self.path = None if path is None else pathlib.Path(path)
        self.columns = list(columns)
        self.rows: list[list[float]] = []
        self.comm = comm
        self._fh = None
        # The .part file is opened at the first row (or at finalize), not here: a table is built in
        # Run.__init__, before the ``with`` block whose __exit__ renames it, so an interrupt landing
        # between the two would leave a bare .part behind.
        self._writes = self.path is not None and _rank(comm) == 0

    def _open(self) -> None:
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self._fh = part_name(self.path).open("w", newline="")
        self._csv = csv.writer(self._fh)
        self._csv.writerow(self.columns)

    def append(self, row: dict) -> None:
        values = [float(row[c]) for c in self.columns]
        self.rows.append(values)
        if self._writes:
            if self._fh is None:
                self._open()
            with naming(part_name(self.path)):
                self._csv.writerow([f"{v:.10g}" for v in values])
                self._fh.flush()

    def column(self, name: str):
        import numpy as np
        i = self.columns.index(name)
        return np.array([r[i] for r in self.rows])

    def as_arrays(self) -> dict:
        return {c: self.column(c) for c in self.columns}

    def finalize(self, complete: bool = True) -> pathlib.Path | None:
        if self.path is None:
            return None
        if self._writes and self._fh is None:  # no row yet: the file still gets its header
            self._open()
        if self._fh is not None and not self._fh.closed:
            with naming(part_name(self.path)):
                self._fh.close()
        target = self.path if complete else partial_name(self.path)
        _barrier(self.comm)
        if _rank(self.comm) == 0 and part_name(self.path).exists():
            replace(part_name(self.path), target)
        _barrier(self.comm)
        return target


class FrameSeries:
    """A ParaView time series: frames ``<stem>_steps/<stem>_NNNNN.vtp`` and the index ``<stem>.pvd``.
    Frames go to ``<stem>_steps.part/`` during the run; :meth:`finalize` renames the folder and writes
    the index (``<stem>_steps.partial/`` and ``<stem>.partial.pvd`` for an unfinished run)."""

    def __init__(self, out: pathlib.Path, stem: str):
        self.out = pathlib.Path(out)
        self.stem = stem
        self.folder = self.out / f"{stem}_steps"
        self.part = part_name(self.folder)
        if self.part.exists():
            shutil.rmtree(self.part)
        self.part.mkdir(parents=True)
        self.entries: list[tuple[float, str]] = []

    def write(self, t: float, save) -> pathlib.Path:
        """``save(path)`` writes the frame at time (or load factor) ``t``."""
        path = self.part / f"{self.stem}_{len(self.entries):05d}.vtp"
        save(path)
        self.entries.append((float(t), path.name))
        return path

    def finalize(self, complete: bool = True) -> pathlib.Path:
        folder = self.folder if complete else partial_name(self.folder)
        replace(self.part, folder)
        rows = "\n".join(f'    <DataSet timestep="{t:.10g}" group="" part="0" file="{folder.name}/{name}"/>'
                         for t, name in self.entries)
        return write_text(self.out / (f"{self.stem}.pvd" if complete else f"{self.stem}.partial.pvd"),
                          '<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n  <Collection>\n'
                          f"{rows}\n  </Collection>\n</VTKFile>\n")


_pending: list = []  # runs whose outputs wait for the ranks to agree (MPI)


def finish_pending(agreed: bool) -> None:
    """Close the outputs of runs that ended by an interrupt or error under MPI: collectively when
    every rank got here (``agreed``), else by renaming rank-locally before an abort."""
    while _pending:
        run = _pending.pop()
        if agreed:
            for w in run.outputs:
                with contextlib.suppress(Exception):
                    w.finalize(False)
        elif run.out is not None:
            salvage_parts(run.out)


def salvage_parts(out: pathlib.Path) -> None:
    """Rename every ``*.part`` entry of ``out`` to its ``*.partial.*`` name, without collectives (any
    rank may call it; a rename another rank did first is skipped)."""
    for p in list(pathlib.Path(out).glob("*.part")):
        with contextlib.suppress(OSError):
            replace(p, partial_name(p.with_name(p.name[:-len(".part")])))


# -- the output folder --------------------------------------------------------------------------
def _pid_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def _check_out_path(out, flag: str) -> pathlib.Path:
    if out is None or str(out).strip() == "":
        raise InputError(f"{flag} = '': must name a folder")
    bad = _not_utf8(str(out))
    if bad:
        raise InputError(f"{flag} {bad}")
    out = pathlib.Path(out)
    if out.exists() and not out.is_dir():
        raise InputError(f"{flag} = '{out}': is a file, not a folder")
    return out


def _take(out: pathlib.Path, resume: bool | None, overwrite: bool, flag: str, command: str | None) -> None:
    """Rank 0's part of :func:`claim_out` (raises InputError)."""
    try:
        out.mkdir(parents=True, exist_ok=True)
        lock = out / LOCK
        for _ in range(2):
            try:
                fd = os.open(lock, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644)
                break
            except FileExistsError:
                try:
                    pid, host = lock.read_text().split()[:2]
                except (OSError, ValueError):
                    pid, host = "0", ""
                if host == socket.gethostname() and pid.isdigit() and not _pid_alive(int(pid)):
                    lock.unlink(missing_ok=True)  # left by a killed run
                    continue
                raise InputError(f"{flag} = '{out}': in use by another lcefem run (pid {pid} on {host}, "
                                 f"lock file {LOCK}); wait for it or choose another folder")
        with os.fdopen(fd, "w") as fh:
            fh.write(f"{os.getpid()} {socket.gethostname()}\n")
        others = [p for p in out.iterdir() if p.name not in (LOCK, STAMP)]
        previous = stamped_command(out)
        if others and resume and command and previous and previous != command:
            raise _release(out, InputError(
                f"{flag} = '{out}': holds the results of `lcefem {previous}`; --resume continues only "
                f"a folder of `lcefem {command}`: choose another folder"))
        if others and not resume:
            if not overwrite:
                raise _release(out, InputError(
                    f"{flag} = '{out}': holds the results of another run ({len(others)} entries, e.g. "
                    f"{sorted(p.name for p in others)[0]}); pass --overwrite to replace them"
                    f"{' or --resume to continue' if resume is not None else ''}"))
            if not (out / STAMP).exists():
                raise _release(out, InputError(
                    f"{flag} = '{out}': holds files not written by lcefem; --overwrite empties only "
                    "lcefem output folders: choose another folder"))
            for p in others:  # the previous run's state (failure.json, summary.json, ...) goes
                shutil.rmtree(p) if p.is_dir() and not p.is_symlink() else p.unlink()
        (out / STAMP).write_text(STAMP_TEXT.format(command=command or previous or "unknown"))
    except OSError as exc:
        raise InputError(f"{flag} = '{out}': cannot write there ({exc.strerror or exc})") from None


def _inside(path: pathlib.Path, folder: pathlib.Path) -> bool:
    try:
        return path.resolve().is_relative_to(folder.resolve())
    except (OSError, RuntimeError):
        return False


def _release(out: pathlib.Path, exc: BaseException) -> BaseException:
    (out / LOCK).unlink(missing_ok=True)
    return exc


@contextlib.contextmanager
def claim_out(out, *, resume: bool | None = False, overwrite: bool = False, comm=None,
              flag: str = "--out", command: str | None = None, inputs: dict | None = None):
    """Own ``out`` while the body runs: check the path, refuse another run's results (unless
    ``resume`` or ``overwrite``, which empties an lcefem folder first), hold a lock file naming
    this process. ``resume=None``: the command has no --resume. ``command`` (e.g. ``run strip``) is
    recorded in the folder's marker; --resume refuses a folder another command wrote. ``inputs``
    (flag -> path: the case files the command reads) may not lie inside a folder --overwrite empties.
    Errors are InputError on every rank."""
    out = _check_out_path(out, flag)
    if overwrite and out.is_dir():
        for name, path in (inputs or {}).items():
            if path is not None and _inside(pathlib.Path(path), out):
                raise InputError(f"{name} = '{path}': inside --out = '{out}', which --overwrite empties; "
                                 "move the file out of the folder first")
    created = not out.exists()
    message = None
    if _rank(comm) == 0:
        try:
            _take(out, resume, overwrite, flag, command)
        except InputError as exc:
            message = str(exc)
    if comm is not None and comm.size > 1:
        message = comm.bcast(message, root=0)
    if message is not None:
        raise InputError(message)
    try:
        yield out
    finally:
        _barrier_quietly(comm)
        if _rank(comm) == 0:
            (out / LOCK).unlink(missing_ok=True)
            if created and [p.name for p in out.iterdir()] == [STAMP]:  # bad input: leave no trace
                (out / STAMP).unlink()
                out.rmdir()


def _barrier_quietly(comm) -> None:
    # On an interrupt the ranks may not all get here; the lock is rank 0's, so don't wait for them.
    if comm is not None and comm.size > 1 and sys.exc_info()[0] is None:
        comm.barrier()


def _not_utf8(text: str) -> str | None:
    """None, or the message for a name that is not valid UTF-8 (bytes the shell passed through, held by
    Python as lone surrogates): dolfinx, ADIOS2 and VTK take UTF-8 names and fail deep inside on it."""
    try:
        text.encode("utf-8")
    except UnicodeEncodeError:
        return (f"= {text.encode('utf-8', 'surrogateescape').decode('utf-8', 'backslashreplace')!r}: "
                "not valid UTF-8; choose a UTF-8 name")
    return None


def _out_path(text: str) -> pathlib.Path:
    if not text.strip():  # pathlib would read "" as the working directory
        raise argparse.ArgumentTypeError("--out = '': must name a folder")
    bad = _not_utf8(text)
    if bad:
        raise argparse.ArgumentTypeError(f"--out {bad}")
    return pathlib.Path(text)


def add_out_arguments(parser, default: str | None, *, resume: bool = False) -> None:
    """--out, --overwrite (and --resume), --quiet: the same flags and words for every command."""
    parser.add_argument("--out", type=_out_path, default=None if default is None else pathlib.Path(default),
                        help=f"output folder (default {default})" if default else "output folder")
    parser.add_argument("--overwrite", action="store_true",
                        help="replace the results of an earlier run in --out")
    if resume:
        parser.add_argument("--resume", action="store_true",
                            help="keep the complete parts of an earlier run in --out and do the rest")
    parser.add_argument("--quiet", action="store_true", help="no progress bar")


# -- one run ------------------------------------------------------------------------------------
class Progress:
    """A tqdm bar on stderr (rank 0 only) over a quantity: simulated time, load factor, ..."""

    def __init__(self, total: float, desc: str, unit: str, fmt: str = ".1f", enabled: bool = True,
                 comm=None):
        self.bar = None
        if enabled and _rank(comm) == 0:
            from tqdm import tqdm
            self.bar = tqdm(total=total, desc=desc, unit=unit, file=sys.stderr,
                            bar_format="{l_bar}{bar}| {n:" + fmt + "}/{total:" + fmt
                            + "} " + unit + " [{elapsed}<{remaining}{postfix}]")

    def to(self, value: float, postfix: str | None = None) -> None:
        if self.bar is not None:
            if postfix:
                self.bar.set_postfix_str(postfix, refresh=False)
            self.bar.update(min(value, self.bar.total) - self.bar.n)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()
            self.bar = None


class Run:
    """One run into ``out`` (or in memory when ``out`` is None), used as a context manager::

        with Run(out, config=cfg.resolved(), columns=COLUMNS, progress=Progress(...)) as run:
            run.output(FieldExport(...))        # anything with finalize(complete)
            for step ...:
                run.record(row, where=f"t = {t} s", at=t)
            run.complete(summary)               # outputs renamed, summary.json written

    On ConvergenceError (also a result out of physical bounds) the outputs become ``*.partial.*``
    and ``failure.json`` records where, why, the last converged row and the configuration; on an
    interrupt (Ctrl-C, SIGTERM) or any other error the outputs become ``*.partial.*`` and no
    failure.json is written (it would claim a physics failure). The exception propagates.
    """

    def __init__(self, out: pathlib.Path | None, *, config: dict, columns: list[str] | None = None,
                 history: str = "history.csv", progress: Progress | None = None, comm=None):
        reinstall_signal_handlers()  # the problem was just built: gmsh and PETSc may have taken them
        self.out = None if out is None else pathlib.Path(out)
        self.config = config
        self.comm = comm
        self.progress = progress or Progress(0, "", "", enabled=False)
        self.outputs: list = []
        self._failure_hooks: list = []
        if self.out is not None and _rank(comm) == 0:
            self.out.mkdir(parents=True, exist_ok=True)
            for stale in ("failure.json", "summary.json"):  # this run owns the folder's state
                (self.out / stale).unlink(missing_ok=True)
        _barrier(comm)
        self.history = None
        if columns is not None:
            self.history = self.output(CSVTable(None if self.out is None else self.out / history,
                                                columns, comm))
        self.done = False

    def output(self, writer):
        self.outputs.append(writer)
        return writer

    def on_failure(self, hook) -> None:
        """``hook(out)`` runs after a ConvergenceError, e.g. to save the last converged state."""
        self._failure_hooks.append(hook)

    def record(self, row: dict, where: str, at: float | None = None, postfix: str | None = None) -> None:
        """Check ``row`` against physical bounds, append it to the history, advance the bar. An
        interrupt a library swallowed (raised inside one of its callbacks) stops the run here at
        the latest."""
        raise_if_interrupted()
        check_row(row, where)
        if self.history is not None:
            self.history.append(row)
        if at is not None:
            self.progress.to(at, postfix)

    def last_row(self) -> dict | None:
        if self.history is None or not self.history.rows:
            return None
        return dict(zip(self.history.columns, self.history.rows[-1]))

    def complete(self, summary: dict) -> dict:
        """Finalize every output under its final name; write summary.json LAST (the marker of a
        complete run)."""
        self.progress.close()
        for w in self.outputs:
            w.finalize(True)
        summary = {"status": "completed", **summary, "config": self.config}
        if self.out is not None:
            write_json(self.out / "summary.json", summary, self.comm)
        self.done = True
        return summary

    def __enter__(self) -> "Run":
        return self

    def __exit__(self, kind, exc, tb) -> bool:
        if exc is None:
            if not self.done:
                raise RuntimeError("Run ended without complete(summary)")
            return False
        self.progress.close()
        if not isinstance(exc, ConvergenceError) and self.comm is not None and self.comm.size > 1:
            # An interrupt or error may have reached only some ranks; the others may wait in a
            # collective, so closing the outputs (collective) here could hang: the command line
            # closes them once the ranks agree (finish_pending), or renames them and aborts.
            _pending.append(self)
            return False
        failed = isinstance(exc, ConvergenceError) and self.out is not None
        for hook in self._failure_hooks if failed else ():  # before the outputs close
            with contextlib.suppress(Exception):
                hook(self.out)
        for w in self.outputs:
            with contextlib.suppress(Exception):  # keep the original error
                w.finalize(False)
        if failed:
            kept = sorted(p.name for p in self.out.iterdir() if ".partial" in p.name or
                          p.name.startswith("last_converged")) if _rank(self.comm) == 0 else []
            write_json(self.out / "failure.json", {
                "status": "failed", "kind": "out of physical bounds" if isinstance(exc, PhysicalBoundsError)
                else "no convergence", "where": exc.where, "reason": exc.reason,
                "last_converged": self.last_row(), "kept": kept, "config": self.config}, self.comm)
        return False


# -- configurations -----------------------------------------------------------------------------
def check_config(config, raw_sections: tuple[str, ...] = ("petsc",)):
    """Each section's own bounds (lcefem.models.parameters.check), then :func:`check_physical`."""
    from lcefem.models.parameters import check

    for f in dataclasses.fields(config):
        if f.name not in raw_sections:
            check(getattr(config, f.name), f.name)
    check_physical(config)
    return config


def resolved(config) -> dict:
    """The configuration as written next to results: every value with its unit and source."""
    from lcefem.models.parameters import describe

    return {f.name: dict(getattr(config, f.name)) if isinstance(getattr(config, f.name), dict)
            else describe(getattr(config, f.name)) for f in dataclasses.fields(config)}
