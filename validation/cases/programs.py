"""The experiments' programs (validation/data/programs.toml), read once and checked: the paper's
Fig. 4 drives of the gridshell (:data:`SHAPE_DRIVES`), the published model's recipes
(:data:`RECIPES`), the dome's current protocol (:data:`DOME_PROTOCOL`) and the temperature whose
crossing time the strip run reports (:data:`SEED_T_NI`). The solvers know none of them: they take
drives, recipes, protocols and thresholds as arguments, and validation passes these.

Units: lambda [-], current [A], time [s], temperature [C], rest fraction [-].
"""

from __future__ import annotations

import math
import pathlib
from collections.abc import Mapping

from lcefem.models.errors import InputError

PATH = pathlib.Path(__file__).resolve().parents[1] / "data" / "programs.toml"
CHANNELS = ("Tx", "Ty", "Bx", "By")
#: The bar-and-hinge supports a program may name (lcefem.solvers.problems.gridshell_bh.SUPPORTS).
BH_SUPPORTS = ("clamp", "rollers", "middle_rollers", "table")


def _keys(table, allowed, where: str, required=None) -> dict:
    """``table`` (a TOML table) with keys among ``allowed`` (and all of ``required``), else one
    InputError naming the place."""
    if not isinstance(table, dict):
        raise InputError(f"{where}: must be a table")
    unknown = [k for k in table if k not in allowed]
    if unknown:
        raise InputError(f"{where}: unknown key {unknown[0]!r} (allowed: {', '.join(allowed)})")
    missing = [k for k in (allowed if required is None else required) if k not in table]
    if missing:
        raise InputError(f"{where}: missing key {missing[0]!r}")
    return table


def _numbers(table, where: str, keys=None) -> dict[str, float]:
    """{name: number} (all ``keys`` if given, no other), else one InputError."""
    if keys is not None:
        _keys(table, keys, where)
    elif not isinstance(table, dict) or not table:
        raise InputError(f"{where}: must be a non-empty table of numbers")
    for k, v in table.items():
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            raise InputError(f"{where}.{k} = {v!r}: must be a number")
    return {k: float(v) for k, v in table.items()}


def _text(value, where: str) -> str:
    if not isinstance(value, str) or not value.strip():
        raise InputError(f"{where}: must be a non-empty text (the source: seed and place)")
    return value


def _support(value, where: str) -> str:
    if value not in BH_SUPPORTS:
        raise InputError(f"{where} = {value!r}: allowed {', '.join(BH_SUPPORTS)}")
    return value


def load_programs(path=PATH) -> dict:
    """The programs of ``path``, checked: {"shapes": {name: {"lambdas", "currents", "support"}},
    "shape_sources", "recipes": {name: (p0 by group, support)}, "recipe_source", "dome_protocol":
    ((start [s], {channel: current [A]}), ...), "dome_protocol_source", "strip_crossing" [C],
    "strip_crossing_source"}. A bad file is one InputError naming the key."""
    from lcefem.solvers.runtime.inputs import read_toml

    path = pathlib.Path(path)
    name = path.name
    data = _keys(
        read_toml(path, f"programs = {str(path)!r}"),
        (
            "gridshell_shapes",
            "gridshell_recipes",
            "dome_protocol",
            "strip_crossing",
            "run_programs",
        ),
        name,
        required=("gridshell_shapes", "gridshell_recipes", "dome_protocol", "strip_crossing"),
    )

    shapes_t = data["gridshell_shapes"]
    source = _keys(
        shapes_t.get("source"),
        ("lambdas", "currents", "support"),
        f"{name}: gridshell_shapes.source",
    )
    shapes = {}
    for shape, table in shapes_t.items():
        if shape == "source":
            continue
        where = f"{name}: gridshell_shapes.{shape}"
        _keys(table, ("lambdas", "currents", "support"), where)
        shapes[shape] = {
            "lambdas": _numbers(table["lambdas"], f"{where}.lambdas", CHANNELS),
            "currents": _numbers(table["currents"], f"{where}.currents", CHANNELS),
            "support": _support(table["support"], f"{where}.support"),
        }

    recipes_t = data["gridshell_recipes"]
    recipe_source = _keys(
        recipes_t.get("source"), ("recipes",), f"{name}: gridshell_recipes.source"
    )
    recipes = {}
    for recipe, table in recipes_t.items():
        if recipe == "source":
            continue
        where = f"{name}: gridshell_recipes.{recipe}"
        _keys(table, ("p0", "support"), where)
        recipes[recipe] = (
            _numbers(table["p0"], f"{where}.p0"),
            _support(table["support"], f"{where}.support"),
        )

    dome = _keys(data["dome_protocol"], ("source", "steps"), f"{name}: dome_protocol")
    steps = dome["steps"]
    if not isinstance(steps, list) or not steps:
        raise InputError(
            f"{name}: dome_protocol.steps: must be a non-empty list of {{start, currents}}"
        )
    protocol = []
    for i, step in enumerate(steps):
        where = f"{name}: dome_protocol.steps[{i}]"
        _keys(step, ("start", "currents"), where)
        start = _numbers({"start": step["start"]}, where)["start"]
        protocol.append((start, _numbers(step["currents"], f"{where}.currents", CHANNELS)))

    crossing = _keys(data["strip_crossing"], ("temperature", "source"), f"{name}: strip_crossing")
    run_programs = {}
    for program, table in (data.get("run_programs") or {}).items():
        where = f"{name}: run_programs.{program}"
        if not isinstance(table, dict):
            raise InputError(f"{where}: must be a table")
        run_programs[program] = (
            _run_program({k: v for k, v in table.items() if k != "source"}, where),
            _text(table.get("source"), f"{where}.source"),
        )
    return {
        "run_programs": run_programs,
        "shapes": shapes,
        "shape_sources": {
            k: _text(source[k], f"{name}: gridshell_shapes.source.{k}") for k in source
        },
        "recipes": recipes,
        "recipe_source": _text(
            recipe_source["recipes"], f"{name}: gridshell_recipes.source.recipes"
        ),
        "dome_protocol": tuple(protocol),
        "dome_protocol_source": _text(dome["source"], f"{name}: dome_protocol.source"),
        "strip_crossing": _numbers(
            {"temperature": crossing["temperature"]}, f"{name}: strip_crossing"
        )["temperature"],
        "strip_crossing_source": _text(crossing["source"], f"{name}: strip_crossing.source"),
    }


def _run_program(table: dict, where: str):
    from lcefem.solvers.program import program_from_table

    return program_from_table(table, where)


PROGRAMS = load_programs()


def run_program(name: str):
    """The program ``name`` of programs.toml's ``[run_programs]`` (a
    :class:`lcefem.solvers.program.Program` for the one door, lcefem.solvers.runner.run) and its
    source; an unknown name is an InputError listing them."""
    if name not in PROGRAMS["run_programs"]:
        raise InputError(f"program {name!r}: allowed {', '.join(PROGRAMS['run_programs'])}")
    return PROGRAMS["run_programs"][name]


#: The paper's Fig. 4 programs: lambda [-] and current [A] per channel, and the published support
#: (sources: :data:`SHAPE_DRIVE_SOURCES`; the curvatures the paper reports are
#: lcefem.validation.studies.gridshell.gridshell_bh.SHAPES).
SHAPE_DRIVES: dict[str, dict] = PROGRAMS["shapes"]
SHAPE_DRIVE_SOURCES = {k: PROGRAMS["shape_sources"][k] for k in ("lambdas", "currents")}
SUPPORT_SOURCE = PROGRAMS["shape_sources"]["support"]
#: The published model's recipes: (target rest fraction P0 per group (lambda = 1.4 P0), support).
RECIPES: dict[str, tuple[dict, str]] = PROGRAMS["recipes"]
RECIPE_SOURCE = PROGRAMS["recipe_source"]
#: The paper's dome protocol: (start time [s], currents [A] per channel), each held until the next.
DOME_PROTOCOL = PROGRAMS["dome_protocol"]
DOME_PROTOCOL_SOURCE = PROGRAMS["dome_protocol_source"]
#: Temperature [C] whose crossing time seed 001 reports ('T_NI (~70 C) within 10 s' at 0.2 A).
SEED_T_NI: float = PROGRAMS["strip_crossing"]
SEED_T_NI_SOURCE = PROGRAMS["strip_crossing_source"]
#: The lambda settings of the four Fig. 4 shapes, per channel (seed 001, Fig. 4 B-E).
FIG4_SHAPES = {name: dict(drive["lambdas"]) for name, drive in SHAPE_DRIVES.items()}
#: Supports of each shape in the published example script, as the 3D FE gridshell names them: the
#: bar-and-hinge "clamp" (centre junction held) is the FE "centre_clamp".
PUBLISHED_SUPPORTS = {
    name: {"clamp": "centre_clamp"}.get(drive["support"], drive["support"])
    for name, drive in SHAPE_DRIVES.items()
}


def pulse_currents(
    hold: Mapping[str, float], protocol=DOME_PROTOCOL
) -> tuple[float, dict[str, float]]:
    """The actuation pulse before a hold, from the dome's protocol (seed 001: 'we first apply 0.1 A
    to each of the top LCE strips and 0.2 A to the bottom ... after about 20 s, the currents are
    switched'; 'the other geometries are programmed similarly'): (its duration [s], the start of the
    protocol's second step; {channel: current [A]}), the protocol's larger pulse current on the
    channels whose ``hold`` current [A] is the largest (the most contracted), its smaller one on the
    others."""
    (_, pulse), (duration, _) = protocol[0], protocol[1]
    low, high = min(pulse.values()), max(pulse.values())
    top = max(hold.values())
    return duration, {
        k: (high if math.isclose(v, top, rel_tol=1e-9) else low) for k, v in hold.items()
    }


def fig4_shape(name: str, mesh_level: int = 0, symmetry: str = "quarter", **config):
    """A :class:`lcefem.solvers.problems.gridshell.GridshellFE` with the published supports of a
    Fig. 4 shape (not yet ramped)."""
    from lcefem.meshes.gridshell_fe import GridshellFEMesh
    from lcefem.solvers.problems.gridshell import GridshellConfig, GridshellFE, GridshellSupports

    if name not in FIG4_SHAPES:
        raise InputError(f"shape {name!r}: allowed {', '.join(FIG4_SHAPES)}")
    supports = config.pop("supports", GridshellSupports(kind=PUBLISHED_SUPPORTS[name]))
    cfg = GridshellConfig(
        mesh=GridshellFEMesh(level=mesh_level), symmetry=symmetry, supports=supports, **config
    )
    return GridshellFE(cfg)
