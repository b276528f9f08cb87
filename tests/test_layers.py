"""The import graph of the sources (read with ast, nothing imported): imports flow one way
(validation -> solvers -> models, validation/solvers -> meshes), the numerics never reach the
application runtime (lcefem.solvers.runtime: exit codes, output folders, signal handlers, writers),
and no module imports another's private name."""

from __future__ import annotations

import ast
import pathlib

ROOT = pathlib.Path(__file__).resolve().parents[1]
PACKAGES = ("models", "meshes", "solvers", "validation")
RUNTIME = "lcefem.solvers.runtime"

#: The numerics: what a solver needs to compute, nothing of how a command runs.
NUMERICS = (
    "lcefem.solvers.mechanics",
    "lcefem.solvers.heat",
    "lcefem.solvers.thermomechanics",
    "lcefem.solvers.continuation",
    "lcefem.solvers.contact",
    "lcefem.solvers.pmultigrid",
    "lcefem.solvers.supports",
    "lcefem.solvers.probes",
    "lcefem.solvers.interrupts",
    "lcefem.solvers.petsc_options",
    "lcefem.solvers.bar_hinge",
    "lcefem.solvers.der",
    "lcefem.models",
    "lcefem.meshes",
)
#: Output writers inside a numerics package (they write files, so they may use the runtime's
#: writers).
WRITERS = ("lcefem.solvers.der.output",)

#: Private names still imported across modules, each with why it is not renamed yet.
PRIVATE_ALLOWED: set[tuple[str, str]] = set()


def module_name(path: pathlib.Path) -> str:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(["lcefem", *parts])


def sources() -> dict[str, pathlib.Path]:
    return {module_name(p): p for top in PACKAGES for p in sorted((ROOT / top).rglob("*.py"))}


SOURCES = sources()


def imports(name: str) -> list[tuple[str, str | None, int]]:
    """(module, imported name or None, line) of every import in module ``name``, at any depth
    (imports inside functions count: they run too)."""
    path = SOURCES[name]
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            found += [(a.name, None, node.lineno) for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = package.split(".")
                anchor = anchor[: len(anchor) - node.level + 1]
                base = ".".join(anchor + ([base] if base else []))
            found += [(base, a.name, node.lineno) for a in node.names]
    return found


def targets(name: str) -> set[str]:
    """The lcefem modules ``name`` imports (a ``from package import submodule`` names the
    submodule)."""
    out = set()
    for module, imported, _ in imports(name):
        if not module.startswith("lcefem."):
            continue
        sub = f"{module}.{imported}" if imported else None
        out.add(sub if sub in SOURCES else module)
    return out


def closure(name: str) -> dict[str, str]:
    """Every lcefem module reachable from ``name``, each with the module that imports it."""
    seen = {name: name}
    todo = [name]
    while todo:
        current = todo.pop()
        for target in targets(current):
            if target in SOURCES and target not in seen:
                seen[target] = current
                todo.append(target)
    return seen


def chain(seen: dict[str, str], end: str) -> str:
    path = [end]
    while seen[path[-1]] != path[-1]:
        path.append(seen[path[-1]])
    return " <- ".join(path)


def in_any(name: str, prefixes) -> bool:
    return any(name == p or name.startswith(p + ".") for p in prefixes)


def test_the_import_walk_sees_the_modules_it_checks():
    # A walk that found nothing would pass every check below.
    assert "lcefem.solvers.mechanics" in SOURCES and "lcefem.solvers.runtime.run" in SOURCES
    assert "lcefem.solvers.interrupts" in targets("lcefem.solvers.mechanics")
    assert in_any("lcefem.solvers.runtime.run", [RUNTIME])
    assert any(in_any(t, [RUNTIME]) for t in targets("lcefem.validation.app.cli"))


def test_numerics_never_reach_the_runtime():
    """Mechanics, heat, bar-and-hinge, rods (and the models and meshes under them) raise
    lcefem.models.errors' exceptions and check interrupts through lcefem.solvers.interrupts; the
    command line maps those to exit codes. Not one of them imports the runtime, even indirectly."""
    numerics = [n for n in SOURCES if in_any(n, NUMERICS) and not in_any(n, WRITERS)]
    assert len(numerics) > 30
    bad = []
    for name in numerics:
        seen = closure(name)
        bad += [chain(seen, t) for t in seen if in_any(t, [RUNTIME])]
    assert not bad, "numerics importing the application runtime:\n" + "\n".join(sorted(set(bad)))


def test_imports_flow_one_way():
    """validation -> solvers -> models, validation/solvers -> meshes: never upward."""
    forbidden = {
        "lcefem.models": ("lcefem.meshes", "lcefem.solvers", "lcefem.validation"),
        "lcefem.meshes": ("lcefem.solvers", "lcefem.validation"),
        "lcefem.solvers": ("lcefem.validation",),
    }
    bad = [
        f"{name} imports {t}"
        for name in SOURCES
        for layer, above in forbidden.items()
        if in_any(name, [layer])
        for t in targets(name)
        if in_any(t, above)
    ]
    assert not bad, "\n".join(bad)


def test_no_module_imports_another_modules_private_name():
    """A leading underscore means "this module's business": used elsewhere, the name is public in
    all but its spelling, and a rename in its home breaks a module nobody thought of. (A private
    submodule, such as lcefem.models._math, is a module of its package, not a private name.)"""
    bad = []
    for name in SOURCES:
        for module, imported, line in imports(name):
            if (
                imported
                and imported.startswith("_")
                and not imported.startswith("__")
                and module.startswith("lcefem.")
                and f"{module}.{imported}" not in SOURCES
                and (name, imported) not in PRIVATE_ALLOWED
            ):
                bad.append(f"{SOURCES[name].relative_to(ROOT)}:{line}: {imported} from {module}")
    assert not bad, "\n".join(bad)


def test_no_import_cycle_through_the_command_line():
    """lcefem.validation.app.cli loads the commands (validate, converge, ...) by name; none of them
    may import the command line back (a hidden cycle: which module finishes loading first depends on
    which one the user started from)."""
    bad = [
        name
        for name in SOURCES
        if name != "lcefem.validation.app.cli" and "lcefem.validation.app.cli" in targets(name)
    ]
    assert not bad, bad


def test_the_current_bound_lives_once():
    """A coil current's bound MAX_CURRENT is read only by lcefem.models.limits (current_param's
    metadata, check_current); every other check of a current calls check_current."""
    import numpy as np
    import pytest

    from lcefem.models.errors import InputError
    from lcefem.models.limits import MAX_CURRENT, check_current, current_param

    users = sorted(
        name
        for name, path in SOURCES.items()
        if name != "lcefem.models.limits"
        and any(
            isinstance(n, ast.Name) and n.id == "MAX_CURRENT"
            for n in ast.walk(ast.parse(path.read_text(encoding="utf-8")))
        )
    )
    assert users == []
    assert current_param(0.2, "test").metadata["maximum"] == MAX_CURRENT
    assert check_current("current", 0.2) == 0.2
    assert check_current("currents", np.array([0.0, MAX_CURRENT])) is not None
    for bad in (-0.1, MAX_CURRENT * 1.01, float("nan"), np.array([0.1, 2.0]), "0.1"):
        with pytest.raises(InputError, match=r"^current"):
            check_current("current", bad)


# The rooms of validation/ (docs/layout.md), written by scripts/dev/rooms.py.
APP, STUDIES, CASES = (
    "lcefem.validation.app",
    "lcefem.validation.studies",
    "lcefem.validation.cases",
)
#: the application's doors: the command line and the commands' drivers, imported by the application
#: only
DOORS = (
    "lcefem.validation.app.cli",
    "lcefem.validation.app.commands",
    "lcefem.validation.app.validate",
    "lcefem.validation.app.converge",
    "lcefem.validation.app.converge_body",
    "lcefem.validation.app.farm",
)
#: the scripts outside the package (python benchmarks/<script>.py): the package never imports them
SCRIPTS = sorted(p.stem for p in (ROOT / "benchmarks").rglob("*.py"))


def case_modules() -> list[str]:
    """The validation case modules, read from the ``register_cases`` calls of
    lcefem.solvers.registry (CASE_MODULES derives from them; nothing imported)."""
    out = []
    for node in ast.walk(ast.parse(SOURCES["lcefem.solvers.registry"].read_text(encoding="utf-8"))):
        if isinstance(node, ast.Call) and getattr(node.func, "id", "") == "register_cases":
            out += [f"{CASES}.{arg.value}" for arg in node.args[1:]]
    return out


def test_every_validation_module_is_in_a_room():
    """validation/ holds three rooms: app/, studies/<topic>/, cases/ (with data/); no module lies
    loose beside them, and every study sits in a topic folder."""
    rooms = [n for n in SOURCES if in_any(n, [APP, STUDIES, CASES])]
    assert len(rooms) > 40 and all(n in SOURCES for n in DOORS)
    loose = [
        n
        for n in SOURCES
        if in_any(n, ["lcefem.validation"]) and n != "lcefem.validation" and n not in rooms
    ]
    flat = [
        n
        for n in SOURCES
        if in_any(n, [STUDIES]) and n.count(".") == 3 and SOURCES[n].name != "__init__.py"
    ]
    assert not loose and not flat, f"outside a room: {loose}, a study without a topic: {flat}"


def test_only_the_application_imports_its_doors():
    """A study or a case computes; running a command, farming cases or writing the report is the
    application's (a study importing the CLI would load every command with it)."""
    bad = [
        f"{name} imports {t}"
        for name in SOURCES
        if not in_any(name, [APP])
        for t in targets(name)
        if in_any(t, DOORS)
    ]
    assert not bad, "\n".join(bad)


def test_studies_never_import_a_case():
    """Cases compare the studies with experiment; a study importing a case would run the comparison
    inside the computation (the cases package's helpers, Metric and write_csv, are fine)."""
    cases = case_modules()
    assert len(cases) > 10 and all(c in SOURCES for c in cases)
    bad = [
        f"{name} imports {t}"
        for name in SOURCES
        if in_any(name, [STUDIES])
        for t in targets(name)
        if t in cases
    ]
    assert not bad, "\n".join(bad)


def test_the_package_never_imports_the_scripts():
    """The benchmark and calibration scripts import lcefem; lcefem never imports them (they are not
    installed)."""
    assert len(SCRIPTS) > 20 and "timing" in SCRIPTS
    bad = [
        f"{name} imports {module}"
        for name in SOURCES
        for module, _, _ in imports(name)
        if module.split(".")[0] in [*SCRIPTS, "benchmarks"]
    ]
    assert not bad, "\n".join(bad)
