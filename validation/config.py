"""Case files (TOML): sections override parameter dataclasses; unknown sections or keys are errors."""

from __future__ import annotations

import pathlib
import tomllib
from typing import Any

from lcefem.models.errors import InputError


def load_toml(path: str | pathlib.Path | None, allowed_sections: set[str]) -> dict[str, Any]:
    """Read a TOML case file; raise InputError for a missing file, bad syntax or an unknown section."""
    if path is None:
        return {}
    path = pathlib.Path(path)
    if not path.is_file():
        raise InputError(f"config = {str(path)!r}: file not found")
    try:
        data = tomllib.loads(path.read_text())
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"config = {str(path)!r}: invalid TOML ({exc})") from exc
    for key, value in data.items():
        if key not in allowed_sections:
            raise InputError(f"unknown section '[{key}]' in {path.name}; allowed: "
                             f"{', '.join(sorted(allowed_sections))}")
        if not isinstance(value, dict):
            raise InputError(f"'{key}' in {path.name} must be a table [{key}]")
    return data
