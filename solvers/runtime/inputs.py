"""Reading the user's files (case files, schedules): one decoding path, one-line errors; and the
start-up checks of the command line and the environment, done before any library is imported."""

from __future__ import annotations

import math
import os
import pathlib

from lcefem.models.errors import InputError


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
        raise InputError(
            f"{name}: not UTF-8 text (byte 0x{data[exc.start]:02x} at offset {exc.start}); "
            "save it as UTF-8 (TOML files are UTF-8)"
        ) from None


def read_toml(path, name: str) -> dict:
    """A TOML file through :func:`read_text`; bad syntax is an InputError naming ``name``."""
    import tomllib

    text = read_text(path, name)
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{name}: invalid TOML ({exc})") from None
    except RecursionError:  # tomllib recurses per nested table or array (a 2,000-deep nesting)
        raise InputError(
            f"{name}: invalid TOML (tables or arrays nested too deep for the parser)"
        ) from None
    except (ValueError, TypeError) as exc:  # an integer of more digits than Python converts (4,300)
        first = str(exc).splitlines()[0][:160] if str(exc) else type(exc).__name__
        raise InputError(f"{name}: invalid TOML ({first})") from None


def decode_error(name: str, exc: BaseException) -> InputError:
    """One-line InputError for a value ``name`` whose parsing raised ValueError, TypeError or
    RecursionError: every parser of user data raises only this."""
    first = str(exc).splitlines()[0][:160] if str(exc) else type(exc).__name__
    return InputError(f"{name}: cannot be read ({first})")


#: numeric environment variables read by lcefem or by the libraries it starts, each with its rule:
#: (kind, minimum, what it is). Checked at start-up, before numba or dolfinx reads them and fails
#: with a traceback (numba: NUMBA_NUM_THREADS=0 raises ValueError at import).
NUMERIC_ENVIRONMENT = {
    "NUMBA_NUM_THREADS": (int, 1, "a whole number >= 1 (numba's thread count)"),
    "LCEFEM_MEMORY": (float, 0.0, "a number of GiB > 0 (the memory lcefem may plan for)"),
    "PMI_RANK": (int, 0, "a whole number >= 0 (the MPI launcher's rank)"),
    "PMI_SIZE": (int, 1, "a whole number >= 1 (the MPI launcher's process count)"),
    "OMPI_COMM_WORLD_RANK": (int, 0, "a whole number >= 0 (the MPI launcher's rank)"),
    "OMPI_COMM_WORLD_SIZE": (int, 1, "a whole number >= 1 (the MPI launcher's process count)"),
}


def check_start(argv: list[str], environ=None) -> None:
    """Start-up checks, before any library (dolfinx, numba, PETSc) is imported: every argument is
    valid UTF-8 (dolfinx passes sys.argv to C++ at import and fails on bytes a shell passed
    through), and every numeric environment variable of :data:`NUMERIC_ENVIRONMENT` that is set is a
    number in its range. InputError naming the argument or the variable."""
    for i, arg in enumerate(argv):
        try:
            str(arg).encode("utf-8")
        except UnicodeEncodeError:
            shown = str(arg).encode("utf-8", "surrogateescape").decode("utf-8", "backslashreplace")
            flag = argv[i - 1] if i and str(argv[i - 1]).startswith("--") else f"argument {i + 1}"
            raise InputError(f"{flag} = {shown!r}: not valid UTF-8; choose a UTF-8 name") from None
    environ = os.environ if environ is None else environ
    for var, (kind, low, what) in NUMERIC_ENVIRONMENT.items():
        text = environ.get(var)
        if text is None or text.strip() == "":  # empty: unset for lcefem and numba
            continue
        try:
            value = kind(text.strip()) if text.strip().isascii() else None
        except ValueError:
            value = None
        if (
            value is None
            or (kind is float and not math.isfinite(value))
            or value < low
            or (kind is float and value <= low)
        ):
            shown = text.encode("ascii", "backslashreplace").decode()[:40]
            raise InputError(
                f"environment variable {var} = {shown!r}: must be {what}; unset it or fix it"
            )


def _writable_folder(folder: pathlib.Path) -> bool:
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError:
        return False
    return os.access(folder, os.W_OK | os.X_OK)


def matplotlib_folder_note(environ=None) -> str | None:
    """When matplotlib's configuration or cache folder cannot be written (and MPLCONFIGDIR is not
    set), point MPLCONFIGDIR at a temporary folder, as matplotlib itself would, but with one line
    (returned) instead of its two-paragraph warning in the middle of a run's output."""
    import tempfile

    environ = os.environ if environ is None else environ
    if environ.get("MPLCONFIGDIR"):
        return None
    home = pathlib.Path(os.path.expanduser("~"))
    folders = [
        pathlib.Path(environ.get("XDG_CONFIG_HOME") or home / ".config") / "matplotlib",
        pathlib.Path(environ.get("XDG_CACHE_HOME") or home / ".cache") / "matplotlib",
    ]
    bad = next((f for f in folders if not _writable_folder(f)), None)
    if bad is None:
        return None
    import atexit
    import shutil

    environ["MPLCONFIGDIR"] = tempfile.mkdtemp(prefix="lcefem-matplotlib-")
    atexit.register(shutil.rmtree, environ["MPLCONFIGDIR"], True)
    return (
        f"lcefem: matplotlib's folder {bad} is not writable; using a temporary one (set "
        "MPLCONFIGDIR "
        "to a writable folder to keep its cache)"
    )


def check_jit_cache() -> None:
    """When dolfinx is loaded: its JIT cache folder (where FFCx compiles the forms) can be written,
    else InputError naming XDG_CACHE_HOME, before any form is compiled (a failure inside the
    compilation leaves half-built solver objects that report errors of their own at exit)."""
    import sys

    if "dolfinx" not in sys.modules:
        return
    try:
        import dolfinx.jit

        folder = pathlib.Path(dolfinx.jit.get_options()["cache_dir"])
    except Exception:  # an older dolfinx without these options: the compilation will tell
        return
    if not _writable_folder(folder):
        raise InputError(
            f"the FFCx/DOLFINx JIT cache folder {folder} cannot be written: set "
            "XDG_CACHE_HOME to a folder you may write to (the cache goes to its fenics/)"
        )
