"""Writers with the ``.part`` convention: a file is complete only under its final name; a failed or
interrupted run leaves ``*.partial.*``. Disk errors (full disk, read-only, permissions) named in one
line with the file and what to do."""

from __future__ import annotations

import contextlib
import csv
import errno
import json
import math
import os
import pathlib
import shutil

from lcefem.models.errors import InputError
from lcefem.solvers.runtime.ranks import barrier, rank

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


#: errno -> what to do when the file is not in --out (a cache, a case file's folder, ...)
ELSEWHERE = {
    errno.ENOSPC: "free space on that device",
    errno.EDQUOT: "free space in your quota",
    errno.EROFS: "that file system is read-only",
    errno.EACCES: "you may not write there",
    errno.EPERM: "you may not write there",
}


def cache_folders() -> dict[pathlib.Path, tuple[str, str]]:
    """The caches lcefem's libraries write outside --out -> (what, the variable that moves it): the
    FFCx/DOLFINx JIT cache (dolfinx.jit: $XDG_CACHE_HOME/fenics, default ~/.cache/fenics), numba's
    cache (NUMBA_CACHE_DIR) and matplotlib's (MPLCONFIGDIR, default ~/.config/matplotlib)."""
    home = pathlib.Path(os.path.expanduser("~"))
    xdg = pathlib.Path(os.environ.get("XDG_CACHE_HOME") or home / ".cache")
    folders = {xdg / "fenics": ("the FFCx/DOLFINx JIT cache", "XDG_CACHE_HOME")}
    if os.environ.get("NUMBA_CACHE_DIR"):
        folders[pathlib.Path(os.environ["NUMBA_CACHE_DIR"])] = ("numba's cache", "NUMBA_CACHE_DIR")
    folders[
        pathlib.Path(
            os.environ.get("MPLCONFIGDIR")
            or pathlib.Path(os.environ.get("XDG_CONFIG_HOME") or home / ".config") / "matplotlib"
        )
    ] = ("matplotlib's configuration and cache", "MPLCONFIGDIR")
    return folders


def _within(path: pathlib.Path, folder: pathlib.Path) -> bool:
    """``path`` is ``folder``, lies inside it, or is one of the folders that must be created for
    it."""
    path, folder = pathlib.Path(os.path.abspath(path)), pathlib.Path(os.path.abspath(folder))
    return path.is_relative_to(folder) or (
        folder.is_relative_to(path) and path != pathlib.Path("/")
    )


def disk_error_message(exc: OSError, out=None) -> str:
    """One line: the file, the cause (with its errno name) and what to do. Only a file in ``out``
    (the command's --out) is blamed on --out; a cache folder of a library names the variable that
    moves it; any other file gets advice about its own folder."""
    where = f"'{exc.filename}'" if exc.filename else "a file"
    name = f" ({errno.errorcode[exc.errno]})" if exc.errno in errno.errorcode else ""
    cause = DISK_ERRORS[exc.errno][0] if exc.errno in DISK_ERRORS else (exc.strerror or str(exc))
    if exc.filename:
        for folder, (what, variable) in cache_folders().items():
            if _within(pathlib.Path(str(exc.filename)), folder):
                return (
                    f"cannot write {where}: {cause}{name}; it is {what} ({folder}): set {variable} "
                    "to a folder you may write to"
                )
    in_out = (
        out is not None
        and exc.filename
        and pathlib.Path(os.path.abspath(str(exc.filename))).is_relative_to(
            pathlib.Path(os.path.abspath(out))
        )
    )
    if exc.errno in DISK_ERRORS:
        todo = (
            DISK_ERRORS[exc.errno][1]
            if in_out or (out is None and not exc.filename)
            else ELSEWHERE[exc.errno]
        )
        return f"cannot write {where}: {cause}{name}; {todo}"
    return f"cannot write {where}: {cause}"


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


def partial_name(path: pathlib.Path) -> pathlib.Path:
    """history.csv -> history.partial.csv; beam_steps -> beam_steps.partial."""
    return path.with_name(f"{path.stem}.partial{path.suffix}")


def part_name(path: pathlib.Path) -> pathlib.Path:
    return path.with_name(path.name + ".part")


def refuse_link(path) -> None:
    """InputError when ``path`` is a symbolic link: lcefem never writes through a link planted in an
    output folder (it would overwrite the link's target, anywhere)."""
    if os.path.islink(path):
        raise InputError(
            f"'{path}': a symbolic link inside the output folder; lcefem does not write "
            "through links: remove it or choose another --out"
        )


def open_new(path, mode: str = "w", **kwargs):
    """A new file at ``path`` for writing (text ``mode`` "w" or binary "wb"): a link there is
    refused (:func:`refuse_link`), any other old entry removed first (a hard link's other name keeps
    its data), and the file created with O_EXCL | O_NOFOLLOW so that a link planted meanwhile is not
    followed either."""
    path = pathlib.Path(path)
    refuse_link(path)
    if path.is_file():
        path.unlink()
    flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_NOFOLLOW", 0)
    try:
        fd = os.open(path, flags, 0o644)
    except FileExistsError:
        refuse_link(path)
        raise
    except OSError as exc:
        if exc.errno == errno.ELOOP:
            refuse_link(path)
        raise
    return os.fdopen(fd, mode, **kwargs)


def replace(src: pathlib.Path, dst: pathlib.Path) -> None:
    """Move ``src`` onto ``dst`` (file or folder), removing what was there."""
    if dst.is_dir() and not dst.is_symlink():
        shutil.rmtree(dst)
    elif dst.exists():
        dst.unlink()
    os.replace(src, dst)


def json_safe(obj):
    """Plain JSON values: numpy scalars and arrays as Python ones, NaN and infinities as None, paths
    as strings (strict JSON)."""
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
    if rank(comm) == 0:
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = part_name(path)
        try:
            with naming(tmp), open_new(tmp, "w", encoding="utf-8") as fh:
                fh.write(text)
        except InputError:  # a link at tmp: not ours to remove
            raise
        except BaseException:
            with contextlib.suppress(OSError):
                tmp.unlink(missing_ok=True)
            raise
        os.replace(tmp, path)
    barrier(comm)
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
        self._writes = self.path is not None and rank(comm) == 0

    def _open(self) -> None:
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self._fh = open_new(part_name(self.path), "w", newline="")
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
        barrier(self.comm)
        if rank(self.comm) == 0 and part_name(self.path).exists():
            replace(part_name(self.path), target)
        barrier(self.comm)
        return target


class FrameSeries:
    """A ParaView time series: frames ``<stem>_steps/<stem>_NNNNN.vtp`` and the index
    ``<stem>.pvd``. Frames go to ``<stem>_steps.part/`` during the run; :meth:`finalize` renames the
    folder and writes the index (``<stem>_steps.partial/`` and ``<stem>.partial.pvd`` for an
    unfinished run)."""

    def __init__(self, out: pathlib.Path, stem: str):
        self.out = pathlib.Path(out)
        self.stem = stem
        self.folder = self.out / f"{stem}_steps"
        self.part = part_name(self.folder)
        refuse_link(self.part)
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
        rows = "\n".join(
            f'    <DataSet timestep="{t:.10g}" group="" part="0" file="{folder.name}/{name}"/>'
            for t, name in self.entries
        )
        return write_text(
            self.out / (f"{self.stem}.pvd" if complete else f"{self.stem}.partial.pvd"),
            '<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n  <Collection>\n'
            f"{rows}\n  </Collection>\n</VTKFile>\n",
        )


def salvage_parts(out: pathlib.Path) -> None:
    """Rename every ``*.part`` entry of ``out`` to its ``*.partial.*`` name, without collectives
    (any rank may call it; a rename another rank did first is skipped)."""
    for p in list(pathlib.Path(out).glob("*.part")):
        with contextlib.suppress(OSError):
            replace(p, partial_name(p.with_name(p.name[: -len(".part")])))
