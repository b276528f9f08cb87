"""The output folder's ownership: :func:`claim_out` refuses another run's results unless ``--resume``
or ``--overwrite``, and holds a lock file while a run writes; :func:`add_out_arguments` gives every
command the same flags and words."""

from __future__ import annotations

import argparse
import contextlib
import os
import pathlib
import shutil
import socket

from lcefem.models.errors import InputError
from lcefem.solvers.runtime.ranks import barrier_quietly, rank

#: Folders this process holds through :func:`claim_out` (resolved paths): a run writing into one of
#: them, or into a folder below one, was claimed by its caller (the command line, ``validate``);
#: any other folder is claimed by the run itself (lcefem.solvers.runtime.run.Run).
_CLAIMED: list[pathlib.Path] = []

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
    if rank(comm) == 0:
        try:
            _take(out, resume, overwrite, flag, command)
        except InputError as exc:
            message = str(exc)
    if comm is not None and comm.size > 1:
        message = comm.bcast(message, root=0)
    if message is not None:
        raise InputError(message)
    held = out.resolve()
    _CLAIMED.append(held)
    try:
        yield out
    finally:
        _CLAIMED.remove(held)
        barrier_quietly(comm)
        if rank(comm) == 0:
            (out / LOCK).unlink(missing_ok=True)
            if created and [p.name for p in out.iterdir()] == [STAMP]:  # bad input: leave no trace
                (out / STAMP).unlink()
                out.rmdir()


def claimed(out) -> bool:
    """True when ``out`` is, or lies below, a folder this process holds through :func:`claim_out`."""
    try:
        path = pathlib.Path(out).resolve()
    except (OSError, RuntimeError):
        return False
    return any(path == c or path.is_relative_to(c) for c in _CLAIMED)


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
