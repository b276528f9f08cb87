"""The output folder's ownership: :func:`claim_out` refuses another run's results unless
``--resume`` or ``--overwrite``, and holds a lock file while a run writes; :func:`add_out_arguments`
gives every command the same flags and words."""

from __future__ import annotations

import argparse
import contextlib
import os
import pathlib
import shutil
import socket
import sys
import time

from lcefem.models.errors import InputError
from lcefem.solvers.runtime.ranks import barrier_quietly, rank

#: Folders this process holds through :func:`claim_out` (resolved paths): a run writing into one of
#: them, or into a folder below one, was claimed by its caller (the command line, ``validate``);
#: any other folder is claimed by the run itself (lcefem.solvers.runtime.run.Run).
_CLAIMED: list[pathlib.Path] = []

LOCK = ".lcefem.lock"  #: "pid host" of the run writing the folder
#: marks a folder written by lcefem (so --overwrite may empty it) and by which command
STAMP = ".lcefem-out"
STAMP_TEXT = "written by lcefem; --overwrite may empty this folder\ncommand: {command}\n"
#: [s] how old a lock file without a readable "pid host" must be before it is taken over: the claim
#: writes the pid right after creating the file (microseconds), so an older empty or garbled lock
#: was left by a run that died there (a full disk during the claim) and would otherwise block for
#: ever
LOCK_GRACE = 2.0
#: where --overwrite puts the previous run's files while the new run starts: an input error found
#: only once the run is under way (a [petsc] option the solver never reads) puts them back, so exit
#: 2 leaves the folder as it was; any other end deletes them
PREVIOUS = ".lcefem-previous"


def stamped_command(out: pathlib.Path) -> str | None:
    """The command recorded in ``out``'s marker (``run strip``, ``validate``, ``converge CASE``),
    None when there is none (no marker, or one written before commands were recorded)."""
    try:
        fd = os.open(pathlib.Path(out) / STAMP, os.O_RDONLY | os.O_NOFOLLOW)
        with os.fdopen(fd, "rb") as fh:
            text = fh.read(4096).decode("utf-8", errors="replace")
    except OSError:
        return None
    for line in text.splitlines():
        if line.startswith("command:"):
            return line[len("command:") :].strip() or None
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
    source = _source_folder(out)
    if source is not None:
        raise InputError(
            f"{flag} = '{out}': inside lcefem's own source tree ({source}); results go to "
            "a folder of their own, e.g. results/<name>"
        )
    return out


def source_folders() -> list[pathlib.Path]:
    """lcefem's own folders: its packages (models, meshes, solvers, validation) and, in a source
    checkout, the repository's tests, docs, scripts and .git; no run writes there."""
    import importlib.util

    folders = []
    for name in ("models", "meshes", "solvers", "validation"):
        with contextlib.suppress(ImportError, ValueError, AttributeError):
            spec = importlib.util.find_spec(f"lcefem.{name}")
            folders += [pathlib.Path(p) for p in (spec.submodule_search_locations or ())]
    root = pathlib.Path(__file__).resolve().parents[2]  # solvers/runtime/outdir.py -> the checkout
    if (root / "pyproject.toml").is_file() and (root / "solvers").is_dir():
        folders += [root / name for name in ("tests", "docs", "scripts", ".git")]
    return [f.resolve() for f in folders]


def _source_folder(out: pathlib.Path) -> pathlib.Path | None:
    """The source folder ``out`` is (or lies in), or the checkout's root if ``out`` is that root."""
    try:
        target = out.resolve()
    except (OSError, RuntimeError):
        return None
    folders = source_folders()
    root = pathlib.Path(__file__).resolve().parents[2]
    if target == root and (root / "pyproject.toml").is_file():
        return root
    for folder in folders:
        if target.is_relative_to(folder):
            return folder
    return None


def _lock_owner(lock: pathlib.Path) -> tuple[int, str] | None:
    """(pid, host) written in ``lock``, None when it holds no readable pid (empty, garbled)."""
    try:
        fd = os.open(lock, os.O_RDONLY | os.O_NOFOLLOW)
        with os.fdopen(fd, "rb") as fh:
            words = fh.read(512).decode("ascii").split()
        pid, host = int(words[0]), words[1]
    except (OSError, ValueError, IndexError, UnicodeDecodeError):
        return None
    return (pid, host) if pid > 0 else None


def _lock_is_live(lock: pathlib.Path) -> bool:
    """A lock another process holds: a live pid on this host (or one on another host, which cannot
    be checked), or one without a pid younger than :data:`LOCK_GRACE`."""
    owner = _lock_owner(lock)
    if owner is None:
        try:
            return time.time() - lock.lstat().st_mtime < LOCK_GRACE
        except OSError:
            return False
    pid, host = owner
    return host != socket.gethostname() or _pid_alive(pid)


def live_lock_inside(folder: pathlib.Path) -> pathlib.Path | None:
    """A lock file of a live run anywhere below ``folder`` (links not followed), or None: a folder
    holding one is being written by another run and may not be emptied."""
    for root, dirs, files in os.walk(folder, followlinks=False):
        if LOCK in files and _lock_is_live(pathlib.Path(root) / LOCK):
            return pathlib.Path(root) / LOCK
    return None


def remove_owned(path: pathlib.Path, flag: str = "--out") -> None:
    """Delete ``path`` (a file, or a folder of an lcefem run) without following links, after
    checking that no live run holds a lock below it (InputError naming it)."""
    path = pathlib.Path(path)
    if path.is_dir() and not path.is_symlink():
        held = live_lock_inside(path)
        if held is not None:
            raise InputError(
                f"{flag}: '{held.parent}' is in use by another lcefem run (lock file "
                f"{held}); wait for it or choose another folder"
            )
        shutil.rmtree(path)
    else:
        path.unlink(missing_ok=True)


def _take(
    out: pathlib.Path, resume: bool | None, overwrite: bool, flag: str, command: str | None
) -> None:
    """Rank 0's part of :func:`claim_out` (raises InputError)."""
    try:
        out.mkdir(parents=True, exist_ok=True)
        lock = out / LOCK
        waited = 0.0
        while True:
            try:
                fd = os.open(lock, os.O_CREAT | os.O_EXCL | os.O_WRONLY | os.O_NOFOLLOW, 0o644)
                break
            except FileExistsError:
                if lock.is_symlink() or not lock.is_file():
                    raise InputError(
                        f"{flag} = '{out}': its lock file {lock} is a link or not a "
                        "file; lcefem does not write through links: remove it"
                    ) from None
                owner = _lock_owner(lock)
                if owner is None:  # no readable pid: stale once older than LOCK_GRACE
                    try:
                        age = time.time() - lock.stat().st_mtime
                    except FileNotFoundError:  # released meanwhile: claim again
                        continue
                    if age < LOCK_GRACE and waited < 2 * LOCK_GRACE:
                        time.sleep(0.1)
                        waited += 0.1
                        continue
                    print(
                        f"lcefem: taking over {lock}: it names no process (empty or garbled, "
                        f"{age:.0f} s old), left by a run that died while claiming the folder",
                        file=sys.stderr,
                    )
                    lock.unlink(missing_ok=True)
                    continue
                pid, host = owner
                if host == socket.gethostname() and not _pid_alive(pid):
                    lock.unlink(missing_ok=True)  # left by a killed run
                    continue
                raise InputError(
                    f"{flag} = '{out}': in use by another lcefem run (pid {pid} on {host}, "
                    f"lock file {LOCK}); wait for it or choose another folder"
                ) from None
        with os.fdopen(fd, "w") as fh:
            fh.write(f"{os.getpid()} {socket.gethostname()}\n")
        others = [p for p in out.iterdir() if p.name not in (LOCK, STAMP)]
        stamp = out / STAMP
        if stamp.is_symlink() or (stamp.exists() and not stamp.is_file()):
            raise _release(
                out,
                InputError(
                    f"{flag} = '{out}': its marker {stamp} is a link or not a file; lcefem does "
                    "not "
                    "write "
                    "through links: remove it"
                ),
            )
        previous = stamped_command(out)
        if others and resume and not stamp.exists():
            raise _release(
                out,
                InputError(
                    f"{flag} = '{out}': holds files not written by lcefem (no {STAMP} marker); "
                    "--resume "
                    "continues only a folder lcefem wrote: choose another folder"
                ),
            )
        if others and resume and command and previous != command:
            raise _release(
                out,
                InputError(
                    f"{flag} = '{out}': holds the results of `lcefem {
                        previous or 'an unrecorded command'
                    }`; "
                    f"--resume continues only a folder of `lcefem {command}`: choose another folder"
                ),
            )
        if others and not resume:
            if not overwrite:
                raise _release(
                    out,
                    InputError(
                        f"{flag} = '{out}': holds the results of another run ({len(others)} "
                        "entries, "
                        "e.g. "
                        f"{sorted(p.name for p in others)[0]}); pass --overwrite to replace them"
                        f"{' or --resume to continue' if resume is not None else ''}"
                    ),
                )
            if not (out / STAMP).exists():
                raise _release(
                    out,
                    InputError(
                        f"{flag} = '{out}': holds files not written by lcefem; --overwrite empties "
                        "only "
                        "lcefem output folders: choose another folder"
                    ),
                )
            held = next(
                (
                    h
                    for p in others
                    if p.is_dir() and not p.is_symlink()
                    for h in [live_lock_inside(p)]
                    if h is not None
                ),
                None,
            )
            if held is not None:
                raise _release(
                    out,
                    InputError(
                        f"{flag} = '{out}': '{held.parent}' inside it is in use by another lcefem "
                        "run "
                        "(lock "
                        f"file {held}); --overwrite would delete its files: wait for it or choose "
                        "another "
                        "folder"
                    ),
                )
            aside = out / PREVIOUS
            if aside.is_dir() and not aside.is_symlink():  # left by a run killed before it ended
                shutil.rmtree(aside)
            elif aside.is_symlink():
                aside.unlink()
            aside.mkdir()
            for p in [*others, stamp]:  # the previous run's state (failure.json, summary.json, ...)
                if p.name != PREVIOUS and (p.exists() or p.is_symlink()):
                    os.rename(p, aside / p.name)
        fd = os.open(stamp, os.O_WRONLY | os.O_CREAT | os.O_TRUNC | os.O_NOFOLLOW, 0o644)
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(STAMP_TEXT.format(command=command or previous or "unknown"))
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
def claim_out(
    out,
    *,
    resume: bool | None = False,
    overwrite: bool = False,
    comm=None,
    flag: str = "--out",
    command: str | None = None,
    inputs: dict | None = None,
):
    """Own ``out`` while the body runs: check the path, refuse another run's results (unless
    ``resume`` or ``overwrite``, which empties an lcefem folder first), hold a lock file naming
    this process. ``resume=None``: the command has no --resume. ``command`` (e.g. ``run strip``) is
    recorded in the folder's marker; --resume refuses a folder another command wrote. ``inputs``
    (flag -> path: the case files the command reads) may not lie inside a folder --overwrite
    empties. Errors are InputError on every rank."""
    out = _check_out_path(out, flag)
    if overwrite and out.is_dir():
        for name, path in (inputs or {}).items():
            if path is not None and _inside(pathlib.Path(path), out):
                raise InputError(
                    f"{name} = '{path}': inside --out = '{out}', which --overwrite empties; "
                    "move the file out of the folder first"
                )
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
    bad_input = False
    held = out.resolve()
    _CLAIMED.append(held)
    try:
        yield out
    except InputError:
        bad_input = True
        raise
    finally:
        _CLAIMED.remove(held)
        barrier_quietly(comm)
        if rank(comm) == 0:
            _settle_previous(out, restore=bad_input)
            (out / LOCK).unlink(missing_ok=True)
            if created and [p.name for p in out.iterdir()] == [STAMP]:  # bad input: leave no trace
                (out / STAMP).unlink()
                out.rmdir()


def _settle_previous(out: pathlib.Path, restore: bool) -> None:
    """The previous run's files that --overwrite set aside (:data:`PREVIOUS`): back in place after
    an input error (the new run's files removed), else deleted."""
    aside = out / PREVIOUS
    if not aside.is_dir() or aside.is_symlink():
        return
    with contextlib.suppress(OSError):
        if restore:
            for p in out.iterdir():
                if p.name not in (LOCK, PREVIOUS):
                    shutil.rmtree(p) if p.is_dir() and not p.is_symlink() else p.unlink()
            for p in aside.iterdir():
                os.rename(p, out / p.name)
            aside.rmdir()
        else:
            shutil.rmtree(aside)


def claimed(out) -> bool:
    """True when ``out`` is, or lies below, a folder this process holds through
    :func:`claim_out`."""
    try:
        path = pathlib.Path(out).resolve()
    except (OSError, RuntimeError):
        return False
    return any(path == c or path.is_relative_to(c) for c in _CLAIMED)


def _not_utf8(text: str) -> str | None:
    """None, or the message for a name that is not valid UTF-8 (bytes the shell passed through, held
    by Python as lone surrogates): dolfinx, ADIOS2 and VTK take UTF-8 names and fail deep inside on
    it."""
    try:
        text.encode("utf-8")
    except UnicodeEncodeError:
        return (
            f"= {text.encode('utf-8', 'surrogateescape').decode('utf-8', 'backslashreplace')!r}: "
            "not valid UTF-8; choose a UTF-8 name"
        )
    if any(
        ord(c) < 32 or ord(c) == 127 for c in text
    ):  # a newline would split every one-line message
        return f"= {text!r}: contains a control character (newline, tab, ...); choose a plain name"
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
    parser.add_argument(
        "--out",
        type=_out_path,
        default=None if default is None else pathlib.Path(default),
        help=f"output folder (default {default})" if default else "output folder",
    )
    parser.add_argument(
        "--overwrite", action="store_true", help="replace the results of an earlier run in --out"
    )
    if resume:
        parser.add_argument(
            "--resume",
            action="store_true",
            help="keep the complete parts of an earlier run in --out and do the rest",
        )
    parser.add_argument("--quiet", action="store_true", help="no progress bar")
