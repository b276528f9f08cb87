"""``--layout NAME|FILE`` of ``lcefem run gridshell`` and ``lcefem design``: a named gridshell
layout (:data:`lcefem.meshes.gridshell_layout.NAMED_LAYOUTS`) or a TOML case file whose ``[layout]``
section describes one (:func:`lcefem.meshes.gridshell_layout.layout_from_table`;
docs/layouts/index.md)."""

from __future__ import annotations

import pathlib

from lcefem.meshes.gridshell_layout import NAMED_LAYOUTS, Layout, layout_from_table
from lcefem.models.errors import InputError
from lcefem.validation.app.config import load_toml


def load_layout(spec: str) -> Layout:
    """A name of :data:`NAMED_LAYOUTS`, or a TOML file with a ``[layout]`` section (other sections
    of a gridshell case file are allowed and ignored here); one-line InputError otherwise."""
    if spec in NAMED_LAYOUTS:
        return NAMED_LAYOUTS[spec].checked()
    path = pathlib.Path(spec)
    if not path.is_file():
        raise InputError(
            f"--layout = {spec!r}: a name ({', '.join(NAMED_LAYOUTS)}) or an existing TOML "
            "file with a [layout] section"
        )
    from lcefem.solvers.problems.gridshell_bh_run import GridshellBHRunConfig

    data = load_toml(path, {*GridshellBHRunConfig.PARAM_SECTIONS, "lambda", "current"})
    if "layout" not in data:
        raise InputError(f"--layout = {spec!r}: {path.name} has no [layout] section")
    return layout_from_table(data["layout"], name=f"{path.name}: layout")
