"""Sphinx configuration of the lcefem documentation (MyST Markdown pages in docs/).

Build: ``make docs`` (creates the environment with the pinned ``docs`` group when missing, then
``sphinx-build -W``: every warning is an error). The HTML lands in docs/_build/html.
"""

import dataclasses
import pathlib
import re
import sys
import tomllib

# MPI must be loaded before dolfinx/petsc4py (the FEniCSx wheel); autodoc imports the solvers.
import dolfinx_solver  # noqa: F401

ROOT = pathlib.Path(__file__).resolve().parents[1]

project = "lcefem"
author = "the lcefem developers"
copyright = "2026, the lcefem developers"
release = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["version"]
version = release

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
]

source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
root_doc = "index"
# Pages are the *.md files of docs/ (new ones are picked up by the index's glob); the rest of docs/
# is data (convergence tables and plots, images, patches of unmerged experiments, example scripts).
exclude_patterns = [
    "_build",
    "_generated",
    "experiments",
    "convergence",
    "images",
    "examples/*.py",
    "README.md",
]

myst_enable_extensions = ["dollarmath", "colon_fence", "deflist"]
myst_heading_anchors = 3

autosummary_generate = True
autosummary_imported_members = False
autodoc_default_options = {
    "members": True,
    "undoc-members": False,
    "show-inheritance": False,
    # a package's __all__ re-exports its modules' names: document each once
    "ignore-module-all": True,
}
autodoc_member_order = "bysource"
autodoc_typehints = "none"
autodoc_preserve_defaults = True
autoclass_content = "class"


def _parameter_lines(cls):
    """One line per parameter field of a dataclass (``lcefem.models.parameters.param``: unit and
    source in the field's metadata): ``name = default [unit]: source``."""
    try:
        fields = dataclasses.fields(cls)
    except TypeError:
        return []
    rows = [f for f in fields if "unit" in f.metadata]
    if not rows:
        return []
    out = ["", "Parameters (field = default [unit]: source):"]
    for f in rows:
        default = "" if f.default is dataclasses.MISSING else f" = {f.default!r}"
        out.append(f"  {f.name}{default} [{f.metadata['unit']}]: {f.metadata['source']}")
    return out


def _docstring_as_text(app, what, name, obj, options, lines):
    """Docstrings here are plain text (units, formulas in Unicode, tables), not reStructuredText:
    render each one as a preformatted block so that its layout survives and no markup is guessed.
    A parameter dataclass lists its fields with unit and source (Sphinx shows undocumented
    attributes with their value only)."""
    if what == "class" and isinstance(obj, type):
        lines.extend(_parameter_lines(obj))
    if not lines or not any(line.strip() for line in lines):
        return
    text = [_restated(re.sub(r"``([^`]*)``", r"\1", line)) for line in lines]
    lines[:] = ["::", ""] + ["    " + line for line in text] + [""]


# The parameter reference's tables (one page per area), written from the code at every build.
sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from parameter_tables import restated as _restated  # noqa: E402
from parameter_tables import write_parameter_tables  # noqa: E402

write_parameter_tables(pathlib.Path(__file__).resolve().parent / "_generated")


def setup(app):
    app.connect("autodoc-process-docstring", _docstring_as_text)


html_theme = "furo"
html_title = f"lcefem {release}"
html_static_path = []
