"""Reading the user's files (case files, schedules): one decoding path, one-line errors."""

from __future__ import annotations

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
        raise InputError(f"{name}: not UTF-8 text (byte 0x{data[exc.start]:02x} at offset {exc.start}); "
                         "save it as UTF-8 (TOML files are UTF-8)") from None


def read_toml(path, name: str) -> dict:
    """A TOML file through :func:`read_text`; bad syntax is an InputError naming ``name``."""
    import tomllib

    try:
        return tomllib.loads(read_text(path, name))
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{name}: invalid TOML ({exc})") from None
