"""Case files (TOML): sections override parameter dataclasses; unknown sections or keys are errors."""

from __future__ import annotations

import pathlib
from typing import Any

from lcefem.models.errors import InputError


def load_toml(path: str | pathlib.Path | None, allowed_sections: set[str]) -> dict[str, Any]:
    """Read a TOML case file; raise InputError for a missing file, bad syntax or an unknown section."""
    if path is None:
        return {}
    from lcefem.solvers.runtime.inputs import read_toml

    path = pathlib.Path(path)
    data = read_toml(path, f"config = {str(path)!r}")
    for key, value in data.items():
        if key not in allowed_sections:
            raise InputError(f"unknown section '[{key}]' in {path.name}; allowed: "
                             f"{', '.join(sorted(allowed_sections))}")
        if not isinstance(value, dict):
            raise InputError(f"'{key}' in {path.name} must be a table [{key}]")
    return data


def config_from_toml(path, base, raw_sections: tuple[str, ...] = ("petsc",)):
    """``base`` (a frozen dataclass of parameter sections) with the sections of the case file at
    ``path`` applied; a section in ``raw_sections`` is a table of PETSc options, each checked against
    the options a case file may set (:func:`lcefem.solvers.petsc_options.check_case_options`) here,
    before any output folder is touched."""
    import dataclasses

    from lcefem.models.parameters import with_overrides
    from lcefem.solvers.petsc_options import check_case_options

    data = load_toml(path, {f.name for f in dataclasses.fields(base)})
    try:
        changes = {name: check_case_options(table, f"[{name}]") if name in raw_sections
                   else with_overrides(getattr(base, name), table, name) for name, table in data.items()}
    except InputError:
        raise
    except (ValueError, TypeError, RecursionError) as exc:  # only the decode error leaves the parser
        from lcefem.solvers.runtime.inputs import decode_error

        raise decode_error(f"config = {str(path)!r}", exc) from None
    return dataclasses.replace(base, **changes)


def override(config, section: str, **values):
    """``config`` with the given keys of ``section`` replaced (None values, i.e. options not given on
    the command line, are left alone); type- and bound-checked like a case file."""
    import dataclasses

    from lcefem.models.parameters import with_overrides

    table = {k: v for k, v in values.items() if v is not None}
    if not table:
        return config
    return dataclasses.replace(config, **{section: with_overrides(getattr(config, section), table, section)})


def assign(config, assignment: str, option: str = "--set"):
    """``config`` with one ``section.field=value`` assignment of a command line applied (the value cast
    to the field's present type, then type- and bound-checked like a case file). A malformed
    assignment or an unknown section or field is an InputError naming ``option``."""
    try:
        path, text = assignment.split("=", 1)
        section, name = path.split(".", 1)
        old = getattr(getattr(config, section), name)
        value = type(old)(text)
    except (ValueError, AttributeError, TypeError):
        raise InputError(f"{option} {assignment!r}: expected section.field=value with a field of "
                         f"{type(config).__name__} (e.g. numerics.cells_thickness=4)") from None
    return override(config, section, **{name: value})


def assign_or_exit(config, assignment: str, option: str = "--set"):
    """:func:`assign` for scripts: bad input is one line on stderr and exit 2."""
    import sys

    try:
        return assign(config, assignment, option)
    except InputError as e:
        print(e, file=sys.stderr)
        raise SystemExit(2) from None
