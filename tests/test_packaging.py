"""The distribution lists every subpackage of the four top-level folders (a non-editable install
would silently miss an unlisted one)."""

import pathlib
import tomllib

REPO = pathlib.Path(__file__).resolve().parents[1]
ROOTS = {
    "models": "lcefem.models",
    "meshes": "lcefem.meshes",
    "solvers": "lcefem.solvers",
    "validation": "lcefem.validation",
}


def test_every_subpackage_is_listed():
    config = tomllib.loads((REPO / "pyproject.toml").read_text())["tool"]["setuptools"]
    listed = set(config["packages"])
    found = set()
    for folder, package in ROOTS.items():
        assert config["package-dir"][package] == folder
        for init in (REPO / folder).rglob("__init__.py"):
            rel = init.parent.relative_to(REPO / folder)
            found.add(".".join([package, *rel.parts]))
    assert found == listed, f"missing: {sorted(found - listed)}, stale: {sorted(listed - found)}"
