"""The parameter reference's tables, read from the code: every parameter dataclass of
``lcefem.models`` (fields with a unit and a source in their metadata: ``models.parameters.param``)
with each field's default, unit and source, one page per area (:data:`AREAS`), written to
``docs/_generated/parameters_<area>.md`` and included by ``docs/parameters_<area>.md``. The site's
build (docs/conf.py) writes them, so a page cannot drift from the defaults that run; the test of the
pages' length (tests/test_docs_titles.py) writes them to a temporary folder and counts their lines.

    .venv/bin/python docs/parameter_tables.py OUT_DIR   # the tables alone, to look at
"""

from __future__ import annotations

import dataclasses
import importlib
import os
import pathlib
import pkgutil
import re
import sys

#: area -> the modules of lcefem.models whose parameter dataclasses its page lists. One page held
#: all 31 classes (340 lines); a page per area keeps each under the docs' 300 lines. A new module
#: with parameters must be placed here: the build stops and names it otherwise.
AREAS = {
    "materials": ("bar_hinge_materials", "contact", "empirical", "hyperelastic", "lce"),
    "heat": ("cover_scales", "heat", "lumped_heat", "shape_control"),
    "bodies": ("ball", "loads", "ribbon", "rod"),
}

# The code's sources name the project's reference notes (outside the repository); the facts they
# hold are restated, with their public sources, on the Sources page (sources.md).
REFERENCE_PAGES = {
    "published_reduced_model": "the published reduced-order model",
    "materials": "material data",
    "gridshell_recipes": "the published reduced-order model",
}


def restated(text: str) -> str:
    """``text`` with each reference note named by the Sources page section that restates it."""
    return re.sub(
        r"(\.\./)*(/work/)?shared/reference/(\w+)\.md",
        lambda m: "see Sources: " + REFERENCE_PAGES.get(m.group(3), m.group(3)),
        text,
    )


def _parameter_classes(module) -> list[type]:
    return sorted(
        (
            c
            for c in vars(module).values()
            if isinstance(c, type)
            and c.__module__ == module.__name__
            and dataclasses.is_dataclass(c)
            and any("unit" in f.metadata for f in dataclasses.fields(c))
        ),
        key=lambda c: c.__name__,
    )


def _table(cls) -> list[str]:
    doc = restated((cls.__doc__ or "").strip().split("\n\n")[0].replace("\n", " "))
    out = [
        f"## `{cls.__module__}.{cls.__name__}`",
        "",
        doc,
        "",
        "| field | default | unit | source |",
        "|---|---|---|---|",
    ]
    for f in dataclasses.fields(cls):
        if "unit" not in f.metadata:
            continue
        default = "" if f.default is dataclasses.MISSING else f"{f.default!r}"
        cells = [f"`{f.name}`", default, f.metadata["unit"], restated(f.metadata["source"])]
        out.append(
            "| " + " | ".join(str(c).replace("|", "\\|").replace("\n", " ") for c in cells) + " |"
        )
    return out + [""]


def parameter_tables() -> dict[str, str]:
    """area -> the Markdown of its tables (one section per class, modules and classes sorted by
    name). Raises RuntimeError naming a module with parameters that no area lists."""
    import dolfinx_solver  # noqa: F401  (MPI before dolfinx/petsc4py, which the models import)

    import lcefem.models

    placed = {m: area for area, modules in AREAS.items() for m in modules}
    pages: dict[str, list[str]] = {area: [] for area in AREAS}
    for info in sorted(pkgutil.iter_modules(lcefem.models.__path__), key=lambda m: m.name):
        classes = _parameter_classes(importlib.import_module(f"lcefem.models.{info.name}"))
        if not classes:
            continue
        if info.name not in placed:
            raise RuntimeError(
                f"lcefem.models.{info.name} has parameters but no page: add it to AREAS in "
                f"docs/parameter_tables.py (one of {', '.join(AREAS)})"
            )
        for cls in classes:
            pages[placed[info.name]] += _table(cls)
    return {area: "\n".join(lines) + "\n" for area, lines in pages.items()}


def write_parameter_tables(folder: pathlib.Path) -> list[pathlib.Path]:
    """Write ``folder/parameters_<area>.md`` for every area (a file is rewritten only when its text
    changed, through a temporary name, so Sphinx does not see a page change that is none)."""
    folder = pathlib.Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    written = []
    for area, text in parameter_tables().items():
        path = folder / f"parameters_{area}.md"
        if not path.exists() or path.read_text() != text:
            tmp = path.with_name(path.name + ".part")
            tmp.write_text(text)
            os.replace(tmp, path)
        written.append(path)
    return written


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: docs/parameter_tables.py OUT_DIR")
    for page in write_parameter_tables(pathlib.Path(sys.argv[1])):
        print(page)
