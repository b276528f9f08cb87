"""The experiments' programs are data (validation/data/programs.toml, read by
lcefem.validation.cases.programs): solvers/ defines none of them, the loaded values are the ones the
Python held before the move (golden, copied from solvers/problems/gridshell_bh_run.py,
gridshell_heated.py and strip.py), and a bad file is a one-line error naming the key."""

from __future__ import annotations

import ast
import pathlib

import pytest

from lcefem.models.errors import InputError
from lcefem.validation.cases import programs

ROOT = pathlib.Path(__file__).resolve().parents[2]
#: The experiment programs (and what derives from them) that once lived in solvers/.
NAMES = {
    "SHAPE_DRIVES",
    "SHAPE_DRIVE_SOURCES",
    "RECIPES",
    "RECIPE_SOURCE",
    "DOME_PROTOCOL",
    "SEED_T_NI",
    "FIG4_SHAPES",
    "PUBLISHED_SUPPORTS",
}

GOLDEN_SHAPE_DRIVES = {
    "table": {
        "lambdas": {"Tx": 1.05, "Ty": 1.05, "Bx": 1.05, "By": 1.05},
        "currents": {"Tx": 0.2, "Ty": 0.2, "Bx": 0.2, "By": 0.2},
        "support": "rollers",
    },
    "dome": {
        "lambdas": {"Tx": 1.33, "Ty": 1.33, "Bx": 1.05, "By": 1.05},
        "currents": {"Tx": 0.04, "Ty": 0.04, "Bx": 0.07, "By": 0.07},
        "support": "rollers",
    },
    "saddle": {
        "lambdas": {"Tx": 1.33, "Ty": 1.05, "Bx": 1.05, "By": 1.33},
        "currents": {"Tx": 0.04, "Ty": 0.07, "Bx": 0.07, "By": 0.04},
        "support": "clamp",
    },
    "cylinder": {
        "lambdas": {"Tx": 1.05, "Ty": 1.33, "Bx": 1.33, "By": 1.33},
        "currents": {"Tx": 0.07, "Ty": 0.04, "Bx": 0.04, "By": 0.04},
        "support": "rollers",
    },
}
GOLDEN_RECIPES = {
    "saddle": ({"XD": 0.75, "YD": 0.95, "XU": 0.95, "YU": 0.75}, "clamp"),
    "dome": ({"XD": 0.75, "YD": 0.75, "XU": 0.95, "YU": 0.95}, "rollers"),
    "cylinder": ({"XD": 0.95, "YD": 0.95, "XU": 0.95, "YU": 0.75}, "rollers"),
    "table": ({"XD": 0.75, "YD": 0.75, "XU": 0.72, "YU": 0.72}, "rollers"),
    "cone": ({"XD1": 0.75, "XD2": 0.85, "XD3": 0.95, "YD": 0.90, "XU": 0.95, "YU": 0.90}, "clamp"),
    "twisted": (
        {
            "XD1": 0.85,
            "XD2": 0.80,
            "XD3": 0.95,
            "YD": 0.90,
            "XU1": 0.95,
            "XU2": 0.80,
            "XU3": 0.85,
            "YU": 0.90,
        },
        "clamp",
    ),
    "wave": (
        {
            "XD:x<70.5": 0.95,
            "XD:x>70.5": 0.75,
            "YD": 0.90,
            "XU:x<70.5": 0.75,
            "XU:x>70.5": 0.95,
            "YU": 0.90,
        },
        "clamp",
    ),
    "dustpan": (
        {
            "XD:x<70.5": 0.95,
            "XD:x>70.5": 0.85,
            "YD": 0.95,
            "XU:x<70.5": 0.80,
            "XU:x>70.5": 0.95,
            "YU": 0.80,
        },
        "clamp",
    ),
}
GOLDEN_DOME_PROTOCOL = (
    (0.0, {"Tx": 0.1, "Ty": 0.1, "Bx": 0.2, "By": 0.2}),
    (20.0, {"Tx": 0.04, "Ty": 0.04, "Bx": 0.07, "By": 0.07}),
)


def test_solvers_define_no_experiment_program():
    """No module of solvers/ binds one of the names at any depth (ast: assignments, functions,
    classes); a walk that saw nothing would pass, so it must see the run module it once held
    them."""
    sources = sorted((ROOT / "solvers").rglob("*.py"))
    assert ROOT / "solvers" / "problems" / "gridshell_bh_run.py" in sources
    defined = []
    for path in sources:
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            targets = []
            if isinstance(node, ast.Assign):
                targets = [t for t in node.targets if isinstance(t, ast.Name)]
            elif isinstance(node, (ast.AnnAssign, ast.AugAssign)) and isinstance(
                node.target, ast.Name
            ):
                targets = [node.target]
            names = {t.id for t in targets}
            if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
                names = {node.name}
            defined += [f"{path.relative_to(ROOT)}:{node.lineno}: {n}" for n in names & NAMES]
    assert not defined, "\n".join(defined)


def test_loaded_programs_equal_the_former_python_values():
    assert programs.SHAPE_DRIVES == GOLDEN_SHAPE_DRIVES
    assert list(programs.SHAPE_DRIVES) == [
        "table",
        "dome",
        "saddle",
        "cylinder",
    ]  # order: shape index
    assert programs.RECIPES == GOLDEN_RECIPES and list(programs.RECIPES) == list(GOLDEN_RECIPES)
    assert programs.DOME_PROTOCOL == GOLDEN_DOME_PROTOCOL
    assert programs.SEED_T_NI == 70.0
    assert programs.PUBLISHED_SUPPORTS == {
        "table": "rollers",
        "dome": "rollers",
        "saddle": "centre_clamp",
        "cylinder": "rollers",
    }
    assert programs.FIG4_SHAPES["saddle"] == GOLDEN_SHAPE_DRIVES["saddle"]["lambdas"]
    # every program carries its source (seed and place)
    assert programs.SHAPE_DRIVE_SOURCES["lambdas"].startswith("seed 001, Results (Fig. 4 B-E)")
    assert programs.SHAPE_DRIVE_SOURCES["currents"].startswith("dome: seed 001, Results")
    assert "RoboticSurface_SciRob_LiuK" in programs.RECIPE_SOURCE
    assert programs.DOME_PROTOCOL_SOURCE.startswith("seed 001, Results")
    assert "T_NI (~70 C) within 10 s" in programs.SEED_T_NI_SOURCE


def _variant(tmp_path, old: str, new: str) -> pathlib.Path:
    text = programs.PATH.read_text(encoding="utf-8")
    assert old in text
    path = tmp_path / "programs.toml"
    path.write_text(text.replace(old, new, 1), encoding="utf-8")
    return path


@pytest.mark.parametrize(
    "old, new, message",
    [
        (
            '[gridshell_shapes.dome]\nlambdas',
            '[gridshell_shapes.dome]\nlambda = 1.0\nlambdas',
            r"^programs.toml: gridshell_shapes.dome: unknown key 'lambda' \(allowed: lambdas, "
            r"currents, support\)$",
        ),
        (
            'support = "clamp"',
            'support = "clamps"',
            r"gridshell_shapes.saddle.support = 'clamps': allowed clamp,",
        ),
        (
            'Tx = 1.33, Ty = 1.33, Bx = 1.05',
            'Tx = "1.33", Ty = 1.33, Bx = 1.05',
            r"gridshell_shapes.dome.lambdas.Tx = '1.33': must be a number$",
        ),
        ('{ start = 20.0,', '{ begin = 20.0,', r"dome_protocol.steps\[1\]: unknown key 'begin'"),
        (
            'temperature = 70.0',
            'temperature = 70.0\nunit = "C"',
            r"strip_crossing: unknown key 'unit'",
        ),
        (
            '# ---------------------------------------------------------------- single strip',
            '[ribbon]\nx = 1\n',
            r"^programs.toml: unknown key 'ribbon'",
        ),
    ],
)
def test_a_bad_programs_file_is_one_line_naming_the_key(tmp_path, old, new, message):
    with pytest.raises(InputError, match=message) as err:
        programs.load_programs(_variant(tmp_path, old, new))
    assert "\n" not in str(err.value)
    assert programs.load_programs(programs.PATH)["shapes"] == GOLDEN_SHAPE_DRIVES


def test_the_pulse_before_a_hold_is_the_dome_protocols():
    """One source for the actuation pulse: the dome protocol's first step. For the dome's hold it
    gives back that step (0.1 A top, 0.2 A bottom) and its 20 s; each shape's schedule file written
    from the rule carries the same pulse for its hold currents."""
    from lcefem.solvers.runtime.inputs import read_toml

    duration, pulse = programs.pulse_currents(GOLDEN_DOME_PROTOCOL[1][1])
    assert duration == 20.0 and pulse == GOLDEN_DOME_PROTOCOL[0][1]
    files = sorted((ROOT / "validation" / "data").glob("gridshell_*_current_schedule.toml"))
    assert len(files) >= 4
    for path in files:
        data = read_toml(path, path.name)
        hold = {k: v[1] for k, v in data["currents"].items()}
        assert data["schedule"]["times"][1] == duration
        assert programs.pulse_currents(hold)[1] == {k: v[0] for k, v in data["currents"].items()}, (
            path.name
        )
