"""Case files (TOML): sections override parameter dataclasses; unknown sections, keys are errors."""

from __future__ import annotations

import pathlib
from typing import Any

from lcefem.models.errors import InputError

#: The sections of a case file that go to the one door (lcefem.solvers.runner.run), not to the
#: body's configuration: ``[program]`` (lcefem.solvers.program.program_from_table) and
#: ``[[exports]]`` (lcefem.solvers.exports.exports_from_tables).
DOOR_SECTIONS = ("program", "exports")


def load_toml(path: str | pathlib.Path | None, allowed_sections: set[str]) -> dict[str, Any]:
    """Read a TOML case file; raise InputError for a missing file, bad syntax or an unknown
    section."""
    if path is None:
        return {}
    from lcefem.solvers.runtime.inputs import read_toml

    path = pathlib.Path(path)
    data = read_toml(path, f"config = {str(path)!r}")
    for key, value in data.items():
        if key not in allowed_sections:
            raise InputError(
                f"unknown section '[{key}]' in {path.name}; allowed: "
                f"{', '.join(sorted(allowed_sections))}"
            )
        if key == "exports":
            if not isinstance(value, list):
                raise InputError(f"'exports' in {path.name} must be a list of tables [[exports]]")
            continue
        if not isinstance(value, dict):
            raise InputError(f"'{key}' in {path.name} must be a table [{key}]")
        curve = value.get("curve")
        if isinstance(curve, str) and curve and not pathlib.Path(curve).is_absolute():
            # a measured contraction curve named in a case file sits beside it, wherever the run
            # starts
            value["curve"] = str(path.parent / curve)
    return data


def config_from_toml(path, base, raw_sections: tuple[str, ...] = ("petsc",), door: bool = False):
    """``base`` (a frozen dataclass of parameter sections) with the sections of the case file at
    ``path`` applied; a section in ``raw_sections`` is a table of PETSc options, each checked
    against the options a case file may set
    (:func:`lcefem.solvers.petsc_options.check_case_options`) here, before any output folder is
    touched; with ``door``, the file may also hold
    :data:`DOOR_SECTIONS` (read by :func:`door_from_toml`)."""
    import dataclasses

    from lcefem.models.parameters import with_overrides
    from lcefem.solvers.petsc_options import check_case_options

    data = load_toml(
        path, {f.name for f in dataclasses.fields(base)} | (set(DOOR_SECTIONS) if door else set())
    )
    data = {k: v for k, v in data.items() if k not in DOOR_SECTIONS}
    try:
        changes = {
            name: check_case_options(table, f"[{name}]")
            if name in raw_sections
            else with_overrides(getattr(base, name), table, name)
            for name, table in data.items()
        }
    except InputError:
        raise
    except (
        ValueError,
        TypeError,
        RecursionError,
    ) as exc:  # only the decode error leaves the parser
        from lcefem.solvers.runtime.inputs import decode_error

        raise decode_error(f"config = {str(path)!r}", exc) from None
    return dataclasses.replace(base, **changes)


def override(config, section: str, **values):
    """``config`` with the given keys of ``section`` replaced (None values, i.e. options not given
    on the command line, are left alone); type- and bound-checked like a case file."""
    import dataclasses

    from lcefem.models.parameters import with_overrides

    table = {k: v for k, v in values.items() if v is not None}
    if not table:
        return config
    return dataclasses.replace(
        config, **{section: with_overrides(getattr(config, section), table, section)}
    )


def assign(config, assignment: str, option: str = "--set"):
    """``config`` with one ``section.field=value`` assignment of a command line applied (the value
    cast to the field's present type, then type- and bound-checked like a case file). A malformed
    assignment or an unknown section or field is an InputError naming ``option``."""
    try:
        path, text = assignment.split("=", 1)
        section, name = path.split(".", 1)
        old = getattr(getattr(config, section), name)
        value = type(old)(text)
    except (ValueError, AttributeError, TypeError):
        raise InputError(
            f"{option} {assignment!r}: expected section.field=value with a field of "
            f"{type(config).__name__} (e.g. numerics.cells_thickness=4)"
        ) from None
    return override(config, section, **{name: value})


def assign_or_exit(config, assignment: str, option: str = "--set"):
    """:func:`assign` for scripts: bad input is one line on stderr and exit 2."""
    import sys

    try:
        return assign(config, assignment, option)
    except InputError as e:
        print(e, file=sys.stderr)
        raise SystemExit(2) from None


def door_from_toml(path):
    """(program, exports) of a case file: its ``[program]`` table as a
    :class:`lcefem.solvers.program.Program` (or ``[program] name = "..."``: an entry of
    validation/data/programs.toml's ``[run_programs]``) and its ``[[exports]]`` list as export
    objects (lcefem.solvers.exports), None where absent; a bad entry is one InputError naming the
    file and the key."""
    if path is None:
        return None, None
    from lcefem.solvers.exports import exports_from_tables
    from lcefem.solvers.program import program_from_table
    from lcefem.solvers.runtime.inputs import read_toml

    path = pathlib.Path(path)
    data = read_toml(path, f"config = {str(path)!r}")
    try:
        table = data.get("program")
        if isinstance(table, dict) and set(table) == {
            "name"
        }:  # an entry of programs.toml's [run_programs]
            from lcefem.validation.cases.programs import run_program

            program = run_program(table["name"])[0]
        else:
            program = program_from_table(table) if table is not None else None
        exports = exports_from_tables(data["exports"]) if "exports" in data else None
    except InputError as exc:
        raise InputError(f"{path.name}: {exc}") from None
    return program, exports
