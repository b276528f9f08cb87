"""validation/ as three rooms (issue 48, item 5): the application, the studies by topic, the cases
and data; the benchmark and calibration scripts leave the package for the top-level benchmarks/.

    python3 scripts/dev/rooms.py [--dry-run]     (from anywhere in the repository; stdlib only)

What it does, in order (docs/layout.md says where things go and why):

1. refuses (exit 2, listing them) when a tracked file of validation/ is neither in :data:`MOVES`
   (as a source or a destination), nor under a folder that stays (:data:`STAYS`) or moves whole
   (:data:`FOLDERS`: a new benchmark follows its folder), nor one of the packages' ``__init__.py``
   this script writes: a module added on another branch needs its room decided here first;
2. ``git mv`` of every source of :data:`MOVES` still in place (``git rm`` where the destination is
   None), writes the new packages' ``__init__.py`` (:data:`NEW_PACKAGES`), and corrects the
   ``Path(__file__).parent`` / ``.parents[k]`` expressions of each moved module so that they name
   the same folder as before;
3. rewrites every reference in the tracked text files (:func:`rewrite_text`): dotted
   ``lcefem.validation.<name>`` names (imports, "module:attr" registry strings, CASE_MODULES,
   monkeypatch strings, ``python -m``), ``from lcefem.validation import a, b`` lines (split by the
   names' new packages), repository paths ``validation/<module>.py`` and folders, the benchmarks'
   imports of each other and their ``python -m`` (now ``python benchmarks/<script>.py``);
4. pyproject.toml: the packages list regenerated from the folders, pytest's pythonpath (the tests
   import the benchmark scripts by name), ruff's src; tests/test_layers.py: the rooms' rules;
5. checks that no import of an old module remains (exit 1 naming the file and line otherwise).

Running it again changes nothing (every step acts only on what is still in its old place).
Not rewritten: the dated logs (docs/notes/, CHANGELOG.md, docs/experiments/) keep the paths of
their day; the data (validation/data/) and the JSON/CSV records are data.
"""

from __future__ import annotations

import argparse
import ast
import pathlib
import re
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]

#: old path -> new path (repository-relative; None: removed). Module names do not change, only
#: their folder: a grep for a module's name still finds it.
MOVES: dict[str, str | None] = {
    # the application: the command line and what every command shares
    "validation/cli.py": "validation/app/cli.py",
    "validation/commands/__init__.py": "validation/app/commands/__init__.py",
    "validation/commands/beam.py": "validation/app/commands/beam.py",
    "validation/commands/body.py": "validation/app/commands/body.py",
    "validation/commands/gridshell.py": "validation/app/commands/gridshell.py",
    "validation/commands/ribbon.py": "validation/app/commands/ribbon.py",
    "validation/commands/ribbon_buckling.py": "validation/app/commands/ribbon_buckling.py",
    "validation/commands/strip.py": "validation/app/commands/strip.py",
    "validation/config.py": "validation/app/config.py",
    "validation/layouts.py": "validation/app/layouts.py",
    "validation/compare.py": "validation/app/compare.py",
    "validation/mesh.py": "validation/app/mesh.py",
    "validation/validate.py": "validation/app/validate.py",
    "validation/farm.py": "validation/app/farm.py",
    "validation/converge.py": "validation/app/converge.py",
    "validation/converge_body.py": "validation/app/converge_body.py",
    "validation/report.py": "validation/app/report.py",
    "validation/phenomena.py": "validation/app/phenomena.py",
    "validation/plots.py": "validation/app/plots.py",
    "validation/render.py": "validation/app/render.py",
    # the studies, by topic
    "validation/beam_plots.py": "validation/studies/beam/beam_plots.py",
    "validation/ribbon_analysis.py": "validation/studies/ribbon/ribbon_analysis.py",
    "validation/ribbon_blocks.py": "validation/studies/ribbon/ribbon_blocks.py",
    "validation/ribbon_obstacle.py": "validation/studies/ribbon/ribbon_obstacle.py",
    "validation/gridshell_bh.py": "validation/studies/gridshell/gridshell_bh.py",
    "validation/calibrate.py": "validation/studies/gridshell/calibrate.py",
    "validation/grid_exchange_calibration.py": (
        "validation/studies/gridshell/grid_exchange_calibration.py"
    ),
    "validation/gridshell_configuration.py": (
        "validation/studies/gridshell/gridshell_configuration.py"
    ),
    "validation/gridshell_current_route.py": (
        "validation/studies/gridshell/gridshell_current_route.py"
    ),
    "validation/gridshell_fe_current_store.py": (
        "validation/studies/gridshell/gridshell_fe_current_store.py"
    ),
    "validation/gridshell_junction_heating.py": (
        "validation/studies/gridshell/gridshell_junction_heating.py"
    ),
    "validation/gridshell_plots.py": "validation/studies/gridshell/gridshell_plots.py",
    "validation/gridshell_sequence.py": "validation/studies/gridshell/gridshell_sequence.py",
    "validation/gridshell_thermal_plots.py": (
        "validation/studies/gridshell/gridshell_thermal_plots.py"
    ),
    "validation/fig5_plots.py": "validation/studies/gridshell/fig5_plots.py",
    "validation/fig5_tasks.py": "validation/studies/gridshell/fig5_tasks.py",
    "validation/uncertainty.py": "validation/studies/gridshell/uncertainty.py",
    "validation/design.py": "validation/studies/design/design.py",
    "validation/gridshell_design.py": "validation/studies/design/gridshell_design.py",
    "validation/gridshell_reach_study.py": "validation/studies/design/gridshell_reach_study.py",
    "validation/control.py": "validation/studies/design/control.py",
    "validation/manufactured.py": "validation/studies/verification/manufactured.py",
    "validation/rod_verification.py": "validation/studies/verification/rod_verification.py",
    "validation/gci.py": "validation/studies/verification/gci.py",
    # the cases and data: the loaders of validation/data join the cases that read them
    "validation/reference_data.py": "validation/cases/reference_data.py",
    "validation/programs.py": "validation/cases/programs.py",
    # scripts, out of the package: benchmarks/ (calibration/ inside)
    "validation/benchmarks/__init__.py": "benchmarks/timing.py",
    **{
        f"validation/benchmarks/{n}.py": f"benchmarks/{n}.py"
        for n in (
            "bar_hinge_benchmark",
            "beam_fe_benchmark",
            "body_vs_dedicated",
            "control_benchmark",
            "der_benchmark",
            "dismech_benchmark",
            "fe_benchmark",
            "gridshell_benchmark",
            "gridshell_fe_benchmark",
            "gridshell_fe_dome_levels",
            "gridshell_fe_speed",
            "knife_edges",
            "layout_benchmark",
            "linear_solver_benchmark",
            "reach_benchmark",
            "ribbon_benchmark",
            "ribbon_convergence",
            "ribbon_curve_shape",
            "ribbon_heat_study",
            "ribbon_material_scan",
            "ribbon_speed_windows",
            "strip_benchmark",
        )
    },
    "validation/calibration/__init__.py": None,
    "validation/calibration/calibrate_thermal.py": "benchmarks/calibration/calibrate_thermal.py",
    "validation/calibration/fit_isotropic_law.py": "benchmarks/calibration/fit_isotropic_law.py",
}

#: folders whose files stay where they are (new files there need no decision)
STAYS = ("validation/__init__.py", "validation/cases/", "validation/data/")
#: the rooms: a file already in one is placed
ROOMS = ("validation/app/", "validation/studies/")

#: folders that moved as a whole (a path naming the folder, or a file not listed above, follows it)
FOLDERS = {
    "validation/commands": "validation/app/commands",
    "validation/benchmarks": "benchmarks",
    "validation/calibration": "benchmarks/calibration",
}

#: the script folders (outside the package): a module there is imported by its bare name
SCRIPT_FOLDERS = {
    "validation/benchmarks": "benchmarks",
    "validation/calibration": "benchmarks/calibration",
}
#: names the benchmarks' package exported, now in a module of their folder
SCRIPT_PACKAGE_NAMES = {"best_of": "timing"}

NEW_PACKAGES = {
    "validation/app/__init__.py": "The application: the ``lcefem`` command line, its commands, "
    "case files, the farm, the report.",
    "validation/studies/__init__.py": "The studies, one folder per topic: what the cases and "
    "commands compute beyond a body's run.",
    "validation/studies/beam/__init__.py": "Studies of the composite beam (seed 001, Fig. 3).",
    "validation/studies/ribbon/__init__.py": "Studies of the rolling twisted ribbon (seed 000).",
    "validation/studies/gridshell/__init__.py": "Studies of the robotic surface, the gridshell "
    "(seed 001, Fig. 4 and 5).",
    "validation/studies/design/__init__.py": "Inverse design and closed-loop control of the "
    "robotic surface.",
    "validation/studies/verification/__init__.py": "Verification: manufactured solutions, the "
    "rod's closed forms, the grid convergence "
    "index.",
}

#: tracked files whose text is rewritten: these suffixes and names, minus SKIP
TEXT_SUFFIXES = (".py", ".md", ".toml", ".sh", ".cfg", ".txt", ".rst", ".yml", ".yaml", ".ini")
TEXT_NAMES = ("Makefile", ".ci/run")
SKIP = (
    "docs/notes/",
    "docs/experiments/",
    "CHANGELOG.md",
    "validation/data/",
    "scripts/dev/",
    "tests/regression/data/",
)

LAYERS_MARKER = "# The rooms of validation/ (docs/layout.md), written by scripts/dev/rooms.py."
LAYERS_RULES = (
    '''

'''
    + LAYERS_MARKER
    + '''
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
    loose = [n for n in SOURCES if in_any(n, ["lcefem.validation"]) and n != "lcefem.validation"
             and n not in rooms]
    flat = [n for n in SOURCES if in_any(n, [STUDIES]) and n.count(".") == 3
            and SOURCES[n].name != "__init__.py"]
    assert not loose and not flat, f"outside a room: {loose}, a study without a topic: {flat}"


def test_only_the_application_imports_its_doors():
    """A study or a case computes; running a command, farming cases or writing the report is the
    application's (a study importing the CLI would load every command with it)."""
    bad = [f"{name} imports {t}" for name in SOURCES if not in_any(name, [APP])
           for t in targets(name) if in_any(t, DOORS)]
    assert not bad, "\\n".join(bad)


def test_studies_never_import_a_case():
    """Cases compare the studies with experiment; a study importing a case would run the comparison
    inside the computation (the cases package's helpers, Metric and write_csv, are fine)."""
    cases = case_modules()
    assert len(cases) > 10 and all(c in SOURCES for c in cases)
    bad = [f"{name} imports {t}" for name in SOURCES if in_any(name, [STUDIES])
           for t in targets(name) if t in cases]
    assert not bad, "\\n".join(bad)


def test_the_package_never_imports_the_scripts():
    """The benchmark and calibration scripts import lcefem; lcefem never imports them (they are not
    installed)."""
    assert len(SCRIPTS) > 20 and "timing" in SCRIPTS
    bad = [f"{name} imports {module}" for name in SOURCES for module, _, _ in imports(name)
           if module.split(".")[0] in [*SCRIPTS, "benchmarks"]]
    assert not bad, "\\n".join(bad)
'''
)


def git(*args: str) -> str:
    return subprocess.run(
        ["git", *args], cwd=ROOT, check=True, capture_output=True, text=True
    ).stdout


def dotted(path: str) -> str | None:
    """``lcefem.validation.<package>.<module>`` of a package path, None for a script outside the
    package."""
    p = pathlib.PurePosixPath(path)
    if p.parts[0] != "validation":
        return None
    parts = list(p.with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(["lcefem", *parts])


def module_map() -> dict[str, str]:
    """old dotted module or package -> new one, for what stays in the package."""
    out = {}
    for old, new in MOVES.items():
        if new and dotted(new) and dotted(old) != dotted(new):
            out[dotted(old)] = dotted(new)
    for old, new in FOLDERS.items():
        if dotted(new):
            out[dotted(old)] = dotted(new)
    return out


def script_map() -> dict[str, str]:
    """old dotted script module -> its new path (``benchmarks/<script>.py``)."""
    out = {}
    for old, new in MOVES.items():
        if new and not dotted(new) and not old.endswith("__init__.py"):
            out[dotted(old)] = new
    return out


def folder_moves(files: list[str]) -> dict[str, str]:
    """The tracked files of a folder that moves whole (:data:`FOLDERS`) and are not in MOVES (added
    on another branch, say a new benchmark): they follow their folder."""
    out = {}
    for f in files:
        for old, new in FOLDERS.items():
            if f.startswith(old + "/") and f not in MOVES and f.endswith(".py"):
                out[f] = new + f[len(old) :]
    return out


MOVES.update(folder_moves(git("ls-files", "validation").splitlines()))
MODULES = module_map()
SCRIPTS = script_map()
SCRIPT_PACKAGES = {dotted(old): new for old, new in SCRIPT_FOLDERS.items()}
PATHS = {old.removeprefix("validation/"): new for old, new in MOVES.items() if new}
PATHS.update({old.removeprefix("validation/"): new for old, new in FOLDERS.items()})


# ---------------------------------------------------------------------------------------------
# 1. the table covers validation/


def unplaced(files: list[str]) -> list[str]:
    known = set(MOVES) | {v for v in MOVES.values() if v} | set(NEW_PACKAGES)
    return sorted(f for f in files if f not in known and not f.startswith(STAYS + ROOMS))


# ---------------------------------------------------------------------------------------------
# 2. the moves

FILE_EXPR = re.compile(r"(Path\(__file__\)(?:\.resolve\(\))?)\.(?:parent\b(?!s)|parents\[(\d+)\])")


def fix_file_paths(text: str, old: str, new: str) -> str:
    """Each ``Path(__file__).parent`` / ``.parents[k]`` of a module moved from ``old`` to ``new``
    rewritten to name the folder it named before (``.parents[j] / "validation"`` when that folder is
    no longer an ancestor)."""
    old_up = list(pathlib.PurePosixPath(old).parents)
    new_up = list(pathlib.PurePosixPath(new).parents)

    def repl(m: re.Match) -> str:
        target = old_up[int(m.group(2) or 0)]
        if target in new_up:
            j, rest = new_up.index(target), ()
        else:
            common = next(a for a in new_up if a == target or a in target.parents)
            j, rest = new_up.index(common), target.relative_to(common).parts
        up = ".parent" if j == 0 else f".parents[{j}]"
        return m.group(1) + up + "".join(f' / "{part}"' for part in rest)

    return FILE_EXPR.sub(repl, text)


def move(dry: bool) -> list[str]:
    done = []
    for old, new in MOVES.items():
        src = ROOT / old
        if not src.exists():
            continue
        if new is None:
            done.append(f"rm {old}")
            if not dry:
                git("rm", "-q", old)
            continue
        dst = ROOT / new
        if dst.exists():
            raise SystemExit(f"rooms: both {old} and {new} exist; merge them by hand first")
        done.append(f"mv {old} -> {new}")
        if dry:
            continue
        dst.parent.mkdir(parents=True, exist_ok=True)
        git("mv", old, new)
        if new.endswith(".py"):
            text = dst.read_text(encoding="utf-8")
            fixed = fix_file_paths(text, old, new)
            if fixed != text:
                dst.write_text(fixed, encoding="utf-8")
    for path, doc in NEW_PACKAGES.items():
        if not (ROOT / path).exists():
            done.append(f"new {path}")
            if not dry:
                (ROOT / path).parent.mkdir(parents=True, exist_ok=True)
                (ROOT / path).write_text(f'"""{doc}"""\n', encoding="utf-8")
                git("add", path)
    for folder in FOLDERS:  # git mv leaves the emptied folders (and their caches) behind
        left = ROOT / folder
        if left.is_dir() and not git("ls-files", folder).strip() and not dry:
            for cache in sorted(left.rglob("__pycache__"), reverse=True):
                for f in cache.iterdir():
                    f.unlink()
                cache.rmdir()
            if not any(left.iterdir()):
                left.rmdir()
    return done


# ---------------------------------------------------------------------------------------------
# 3. the references

OLD_NAME = r"lcefem\.validation\.((?:\w+\.)*\w+)"
DOTTED = re.compile(r"(?<![\w.])" + OLD_NAME)
#: python -m of a script, and its argv form ("-m", "lcefem.validation.benchmarks.x")
RUN_M = re.compile(r"-m\s+" + OLD_NAME)
RUN_M_LIST = re.compile(r"""(["'])-m\1,\s*(["'])""" + OLD_NAME + r"\2")
FROM_IMPORT = re.compile(
    r"^([ \t]*)from\s+lcefem\.validation(\.[\w.]+)?\s+import\s+([\w ,]+?)[ \t]*(#.*)?$", re.M
)
FROM_IMPORT_PAREN = re.compile(
    r"^([ \t]*)from\s+lcefem\.validation(\.[\w.]+)?\s+import\s+\(([^)]*)\)", re.M
)
PATH = re.compile(r"(?<![\w/.-])validation/((?:[\w-]+/)*[\w-]+(?:\.\w+)?)")


def longest(name: str, table: dict[str, str]) -> tuple[str, str] | None:
    """(the longest key of ``table`` that is ``name`` or a dotted prefix of it, its value)."""
    parts = name.split(".")
    for k in range(len(parts), 0, -1):
        key = ".".join(parts[:k])
        if key in table:
            return key, table[key]
    return None


def script_path(name: str) -> str | None:
    """``benchmarks/<script>.py`` of a dotted script module (or a name in it), None otherwise."""
    hit = longest(name, SCRIPTS)
    if hit:
        return hit[1]
    hit = longest(name, SCRIPT_PACKAGES)
    if hit:
        return hit[1] + "/"
    return None


def rewrite_imports(text: str, here: str) -> str:
    """``from lcefem.validation[.pkg] import a, b as c`` lines, split by the names' new homes."""

    def repl(m: re.Match) -> str:
        return regroup(m.group(1), m.group(2) or "", m.group(3), m.group(4))

    def repl_paren(m: re.Match) -> str:  # from ... import (a,\n b): one line per new home
        if "#" in m.group(3):
            return m.group(0)  # comments among the names: left for check() to name
        return regroup(m.group(1), m.group(2) or "", " ".join(m.group(3).split()).strip(" ,"), None)

    def regroup(indent: str, sub: str, names: str, comment: str | None) -> str:
        package = "lcefem.validation" + sub
        groups: dict[str, list[str]] = {}
        for item in (s.strip() for s in names.split(",")):
            name = item.split(" as ")[0].strip()
            full = f"{package}.{name}"
            if package in SCRIPT_PACKAGES:  # a script, or a name of the scripts' package
                if name in SCRIPT_PACKAGE_NAMES:
                    groups.setdefault(f"from {SCRIPT_PACKAGE_NAMES[name]}", []).append(item)
                else:
                    groups.setdefault("import", []).append(item)
                continue
            if package in SCRIPTS:  # from a script import names
                groups.setdefault(
                    f"from {pathlib.PurePosixPath(SCRIPTS[package]).stem}", []
                ).append(item)
                continue
            hit = longest(full, MODULES)
            if hit and hit[0] == full:  # a module moved: import it from its new package
                new_package = hit[1].rpartition(".")[0]
            else:  # a name of the package itself, or a module that stays
                new_package = longest(package, MODULES)[1] if longest(package, MODULES) else package
            groups.setdefault(f"from {new_package}", []).append(item)
        lines = []
        for head, items in groups.items():
            if head == "import":
                lines += [f"{indent}import {item}" for item in items]
            else:
                lines.append(f"{indent}{head} import {', '.join(items)}")
        if comment:
            lines[0] += "  " + comment
        return "\n".join(lines)

    text = FROM_IMPORT_PAREN.sub(repl_paren, text)
    return FROM_IMPORT.sub(repl, text)


def rewrite_text(text: str, here: str) -> str:
    """Every reference to a moved module or file in ``text`` (the file ``here``) rewritten."""
    stem = pathlib.PurePosixPath(here).stem

    def run_list(m: re.Match) -> str:
        target = SCRIPTS.get("lcefem.validation." + m.group(3))
        if not target:
            return m.group(0)
        if pathlib.PurePosixPath(target).stem != stem:
            raise SystemExit(
                f"rooms: {here} runs another script by -m ({m.group(3)}): rewrite it by hand"
            )
        # the script runs itself in a child process: by its path, as it is now run
        return "__file__"

    text = RUN_M_LIST.sub(run_list, text)
    text = RUN_M.sub(lambda m: SCRIPTS.get("lcefem.validation." + m.group(1), m.group(0)), text)
    text = rewrite_imports(text, here)

    def name(m: re.Match) -> str:
        full = "lcefem.validation." + m.group(1)
        hit = longest(full, MODULES)
        if hit:
            return hit[1] + full[len(hit[0]) :]
        path = script_path(full)
        if path and full in SCRIPTS:
            return path
        if path:  # the scripts' package itself
            return path
        return m.group(0)

    text = DOTTED.sub(name, text)

    def path(m: re.Match) -> str:
        rel = m.group(1)
        if rel in PATHS:
            return PATHS[rel]
        parts = rel.split("/")
        for k in range(len(parts) - 1, 0, -1):
            head = "/".join(parts[:k])
            if head in PATHS:
                return PATHS[head] + "/" + "/".join(parts[k:])
        return m.group(0)

    return PATH.sub(path, text)


def text_files() -> list[str]:
    files = git("ls-files").splitlines()
    return [
        f
        for f in files
        if (f.endswith(TEXT_SUFFIXES) or f in TEXT_NAMES)
        and not f.startswith(SKIP)
        and (ROOT / f).is_file()
    ]


# ---------------------------------------------------------------------------------------------
# 4. pyproject and the layer rules


def packages_block() -> str:
    roots = {
        "models": "lcefem.models",
        "meshes": "lcefem.meshes",
        "solvers": "lcefem.solvers",
        "validation": "lcefem.validation",
    }
    names = []
    for folder, package in roots.items():
        subs = sorted(
            ".".join([package, *init.parent.relative_to(ROOT / folder).parts])
            for init in (ROOT / folder).rglob("__init__.py")
            if init.parent != ROOT / folder
        )
        names += [package, *subs]
    return "packages = [\n" + "".join(f'    "{n}",\n' for n in names) + "]"


def rewrite_pyproject(text: str) -> str:
    text = re.sub(r"packages = \[\n(?:    \"[^\"\n]+\",\n)*\]", packages_block(), text, count=1)
    if "pythonpath" not in text:
        text = text.replace(
            'testpaths = ["tests"]\n',
            'testpaths = ["tests"]\n# the benchmark scripts (benchmarks/, not installed) import '
            'each other by name, as the tests do\npythonpath = ["benchmarks"]\n',
            1,
        )
    if "\nsrc = " not in text:
        text = text.replace(
            'target-version = "py312"\n',
            'target-version = "py312"\n# benchmarks/: scripts importing each other by name '
            '(first-party to the import order)\nsrc = [".", "benchmarks"]\n',
            1,
        )
    return text


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dry-run", action="store_true", help="list the moves, change nothing")
    args = parser.parse_args(argv)
    missing = unplaced(git("ls-files", "validation").splitlines())
    if missing:
        print(
            "rooms: files of validation/ without a room in scripts/dev/rooms.py MOVES "
            "(add each, or a folder to STAYS):\n  " + "\n  ".join(missing),
            file=sys.stderr,
        )
        return 2
    for line in move(args.dry_run):
        print(line)
    if args.dry_run:
        return 0
    changed = []
    for f in text_files():
        path = ROOT / f
        text = path.read_text(encoding="utf-8")
        new = rewrite_text(rewrite_pyproject(text) if f == "pyproject.toml" else text, f)
        if f == "tests/test_layers.py" and LAYERS_MARKER not in new:
            new = new.rstrip("\n") + "\n" + LAYERS_RULES
        if new != text:
            path.write_text(new, encoding="utf-8")
            changed.append(f)
    print(f"rooms: {len(changed)} files rewritten" + "".join(f"\n  {f}" for f in changed))
    stale = check()
    if stale:
        print("rooms: references left to old modules:\n  " + "\n  ".join(stale), file=sys.stderr)
        return 1
    return 0


# ---------------------------------------------------------------------------------------------
# 5. the check


def check() -> list[str]:
    """Imports of old modules, and old dotted names or paths, still in the rewritten files."""
    olds = set(MODULES) | set(SCRIPTS) | set(SCRIPT_PACKAGES)
    bad = []
    for f in text_files():
        text = (ROOT / f).read_text(encoding="utf-8")
        for m in DOTTED.finditer(text):
            if longest("lcefem.validation." + m.group(1), {o: o for o in olds}):
                bad.append(f"{f}: {m.group(0)}")
        for m in PATH.finditer(text):
            if m.group(1) in PATHS or m.group(1).split("/")[0] in (
                "commands",
                "benchmarks",
                "calibration",
            ):
                bad.append(f"{f}: validation/{m.group(1)}")
        if f.endswith(".py"):
            try:
                tree = ast.parse(text)
            except SyntaxError as exc:
                bad.append(f"{f}: does not parse: {exc}")
                continue
            for node in ast.walk(tree):
                if isinstance(node, ast.ImportFrom) and node.module == "lcefem.validation":
                    bad += [
                        f"{f}:{node.lineno}: from lcefem.validation import {a.name}"
                        for a in node.names
                        if f"lcefem.validation.{a.name}" in olds
                    ]
    return bad


if __name__ == "__main__":
    sys.exit(main())
