"""Every repository path and module the documentation names exists: a file path such as
``solvers/der/ribbon.py`` or ``docs/ribbon.md`` in README.md, docs/*.md (the topic pages; the dated
decision logs of docs/notes/ keep the paths of their day) and every docstring of the package, and
every dotted ``lcefem.<module>[.<name>]`` in the same texts (the module exists and defines or
imports the name). A moved or renamed module then fails here instead of leaving a stale
reference."""

import ast
import re

import pytest

from tests.conftest import REPO

TOP = ("models", "meshes", "solvers", "validation", "benchmarks", "tests", "docs", "scripts")
#: a repository path to a Python module or a Markdown page, starting at one of the top-level folders
#: (so that another project's path, e.g. dolfinx's python/demo/test.py, is not read as ours)
PATH = re.compile(r"(?<![\w/.-])((?:%s)/[\w./-]*?\.(?:py|md))(?![\w/])" % "|".join(TOP))
DOTTED = re.compile(r"(?<![\w.])lcefem((?:\.\w+)+)")
SKIP = (".venv", ".git", "lcefem.egg-info", "_build", "_autosummary", "_generated")

PAGES = [
    REPO / "README.md",
    *sorted((REPO / "docs").glob("*.md")),
    *sorted((REPO / "docs" / "layouts").glob("*.md")),
]
MODULES = sorted(p for p in REPO.rglob("*.py") if not set(p.relative_to(REPO).parts) & set(SKIP))


def docstrings(path):
    """The module's, classes' and functions' docstrings of a Python file."""
    tree = ast.parse(path.read_text(), filename=str(path))
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
            text = ast.get_docstring(node, clean=False)
            if text:
                yield text


def dotted_exists(dotted: str) -> bool:
    """``dotted`` (what follows "lcefem"): walk the packages and modules of the repository (lcefem
    is its root); the first part that is no module must be a name its module (or package's __init__)
    mentions."""
    base = REPO
    parts = dotted.strip(".").split(".")
    for i, part in enumerate(parts):
        if (base / part / "__init__.py").exists():
            base = base / part
            continue
        if (base / f"{part}.py").exists():
            rest = parts[i + 1 :]
            return not rest or re.search(
                rf"\b{re.escape(rest[0])}\b", (base / f"{part}.py").read_text()
            )
        init = base / "__init__.py"
        return init.exists() and re.search(rf"\b{re.escape(part)}\b", init.read_text()) is not None
    return True


def generated(path: str) -> bool:
    """A path `make docs` writes (docs/_generated, docs/_build, ...): absent in a fresh clone."""
    return bool(set(path.split("/")) & set(SKIP))


def missing_in(text: str) -> list[str]:
    paths = [
        m.group(1)
        for m in PATH.finditer(text)
        if not generated(m.group(1)) and not (REPO / m.group(1)).exists()
    ]
    names = ["lcefem" + m.group(1) for m in DOTTED.finditer(text) if not dotted_exists(m.group(1))]
    return sorted(set(paths + names))


def test_the_pattern_reads_paths_and_modules():
    text = (
        "see `solvers/der/ribbon.py`, docs/ribbon.md and (validation/app/report.py); not "
        "python/demo/test.py nor src/festim/problem.py; :func:`lcefem.models.lce.no_such_law`"
    )
    assert [m.group(1) for m in PATH.finditer(text)] == [
        "solvers/der/ribbon.py",
        "docs/ribbon.md",
        "validation/app/report.py",
    ]
    assert missing_in(text) == ["lcefem.models.lce.no_such_law"]
    assert missing_in("solvers/no_such_module.py and lcefem.validation.no_such_module") == [
        "lcefem.validation.no_such_module",
        "solvers/no_such_module.py",
    ]
    assert not missing_in(
        "lcefem.validation.app.report.render_report, lcefem.models, docs/notes/index.md"
    )


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.relative_to(REPO).as_posix())
def test_paths_named_in_the_docs_exist(page):
    missing = missing_in(page.read_text())
    assert not missing, f"{page.relative_to(REPO)} names what does not exist: {', '.join(missing)}"


def test_paths_named_in_docstrings_exist():
    stale = {}
    for path in MODULES:
        for text in docstrings(path):
            if missing := missing_in(text):
                stale.setdefault(str(path.relative_to(REPO)), set()).update(missing)
    assert not stale, "stale references in docstrings: " + "; ".join(
        f"{f}: {', '.join(sorted(m))}" for f, m in sorted(stale.items())
    )
