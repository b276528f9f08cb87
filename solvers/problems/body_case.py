"""The case file of ``lcefem run body``: a 3D FE thermo-mechanical LCE body from a mesh and a TOML
file, with no Python (docs/own_robot.md is the user's page; :data:`SCHEMA` is the one table of every
key, its unit, default and bounds, which the checks and that page follow).

:func:`load_case` reads the file (tomllib), checks every key before any mesh is built (the mesh
file's physical names are read, not meshed: :func:`lcefem.meshes.reader.physical_names`) and
returns a :class:`BodyCase`. Bad input is one :class:`~lcefem.models.errors.InputError` line
naming the file, the entry and what is allowed; an unknown key is refused.

Units are lcefem's (README): mm, s, N, MPa, mW, C; heat-exchange coefficients in mW/(mm^2 K)
(1 W/(m^2 K) = 1e-3 mW/(mm^2 K)).
"""

from __future__ import annotations

import math
import pathlib
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from lcefem.models.bar_hinge_materials import GlueBars
from lcefem.models.errors import InputError
from lcefem.models.heat import Coil, SurfaceExchange, ThermalProperties
from lcefem.models.hyperelastic import KAPTON_DATASHEET_MODULUS, KAPTON_POISSON_RATIO, LCEElasticity
from lcefem.models.lce import NematicTransition
from lcefem.models.limits import CURRENT_RANGE, check_current
from lcefem.solvers.continuation import PathControl

_T = NematicTransition()
_E = LCEElasticity()
_H = ThermalProperties()
_X = SurfaceExchange()
_P = PathControl()
#: Contact pressure per penetration [N/mm^3] of the composite beam's strip-ribbon contact
#: (solvers/contact.py PenaltyContact.stiffness, "chosen: about 100 x E_LCE/H_strip"; a test keeps
#: them equal). Not imported: this module is read before dolfinx is loaded.
CONTACT_PENALTY = 50.0

#: Passive presets: (E [MPa], nu [-], source).
PRESETS = {
    "kapton": (
        KAPTON_DATASHEET_MODULUS,
        KAPTON_POISSON_RATIO,
        "DuPont Kapton HN datasheet (models/hyperelastic.py)",
    ),
    "glue": (
        GlueBars().youngs_modulus,
        0.3,
        "E: the published model's glue bars (models/bar_hinge_materials.GlueBars); nu assumed 0.3",
    ),
}
MATERIALS = ("lce", "neo-hookean", *PRESETS)
SUPPORT_TYPES = ("clamp", "roller", "mirror", "point", "3-2-1")
HEAT_TYPES = ("convection", "radiation", "fixed")
LOAD_TYPES = ("force", "pressure", "gravity")
AXES = {"x": 0, "y": 1, "z": 2}

# Each key: (kind, unit, default (REQUIRED: none), bounds or allowed values, what it is).
REQUIRED = object()
POSITIVE = "> 0"  #: a lower bound: strictly positive
NUM, INT, STR, BOOL, VEC, NAMES, TABLE, ANY = (
    "number",
    "integer",
    "string",
    "boolean",
    "3-vector",
    "name or list of names",
    "table",
    "value",
)
EXPRS = "3 expressions"  #: a list of three strings of x, y, z (solvers/problems/body_expression.py)
#: the region keys that override [thermal] in that region
REGION_THERMAL = ("density", "specific_heat", "conductivity")

SCHEMA: dict[str, dict[str, tuple]] = {
    "mesh": {
        "file": (
            STR,
            "-",
            REQUIRED,
            None,
            "mesh file, relative to the case file: .geo, .msh or meshio-readable with named sets",
        ),
        "size_factor": (NUM, "-", 1.0, (0.01, 10.0), "gmsh Mesh.MeshSizeFactor for a .geo"),
        "symmetry_factor": (
            INT,
            "-",
            1,
            (1, 2, 4, 8),
            "the whole body is this many copies of the "
            "mesh (mirror planes): coil power and reactions are for the whole body",
        ),
        "refine": (
            INT,
            "-",
            0,
            (0, 4),
            "uniform refinements of the read mesh (each halves every "
            "edge: tetrahedra only; dolfinx.mesh.refine)",
        ),
    },
    "thermal": {
        "density": (
            NUM,
            "t/mm^3",
            _H.density,
            (POSITIVE, None),
            "density (heat capacity, gravity)",
        ),
        "specific_heat": (NUM, "mJ/(t K)", _H.specific_heat, (POSITIVE, None), "specific heat"),
        "conductivity": (
            NUM,
            "mW/(mm K)",
            _H.conductivity,
            (POSITIVE, None),
            "thermal conductivity",
        ),
        "initial_temperature": (
            NUM,
            "C",
            _X.ambient_temperature,
            (-273.15, 400.0),
            "uniform temperature at t = 0 (the as-built state)",
        ),
    },
    "regions": {
        "name": (NAMES, "-", REQUIRED, None, "physical name(s) of cell sets in the mesh"),
        "material": (STR, "-", REQUIRED, MATERIALS, "LCE, or a passive neo-Hookean solid"),
        "director": (VEC, "-", None, None, "LCE: director (normalised; not zero)"),
        "twist": (TABLE, "-", None, None, "LCE: through-thickness twist {axis, from_deg, to_deg}"),
        "director_expression": (
            EXPRS,
            "-",
            None,
            None,
            "LCE: director as three expressions of the "
            "reference x, y, z [mm] (numbers, pi, + - * / **, sin cos tan exp sqrt "
            "atan2), normalised; zero length anywhere is an error",
        ),
        "lambda_N": (NUM, "-", _T.lambda_N, (1.0, 3.0), "LCE: nematic spontaneous stretch"),
        "T_NI": (NUM, "C", _T.T_NI, (-50.0, 300.0), "LCE: midpoint of the order parameter's fall"),
        "width": (NUM, "K", _T.width, (0.1, 100.0), "LCE: width of the transition"),
        "T_ref": (
            NUM,
            "C",
            _T.T_ref,
            (-50.0, 300.0),
            "LCE: as-built temperature (lambda_s = lambda_N)",
        ),
        "shear_modulus": (
            NUM,
            "MPa",
            _E.shear_modulus,
            (1e-4, 1e3),
            "LCE: small-strain shear modulus (the whole law scaled, its Poisson ratio kept)",
        ),
        "curve": (STR, "-", None, None, "LCE: measured contraction curve, CSV with units"),
        "E": (NUM, "MPa", None, (1e-4, 1e6), "passive: Young's modulus (preset's by default)"),
        "nu": (NUM, "-", None, (0.0, 0.49), "passive: Poisson's ratio (preset's by default)"),
        "density": (
            NUM,
            "t/mm^3",
            None,
            (POSITIVE, None),
            "this region's density (heat capacity, gravity; default: [thermal])",
        ),
        "specific_heat": (
            NUM,
            "mJ/(t K)",
            None,
            (POSITIVE, None),
            "this region's specific heat (default: [thermal])",
        ),
        "conductivity": (
            NUM,
            "mW/(mm K)",
            None,
            (POSITIVE, None),
            "this region's thermal conductivity (default: [thermal])",
        ),
    },
    "coils": {
        "name": (STR, "-", REQUIRED, None, "the coil's name: its drive tag in [program] currents"),
        "region": (STR, "-", REQUIRED, None, "physical name of the (LCE) cell set it heats"),
        "resistance": (NUM, "ohm", Coil().resistance, (POSITIVE, 1e6), "electrical resistance"),
    },
    "heat": {
        "boundary": (NAMES, "-", REQUIRED, None, "physical name(s) of facet sets"),
        "type": (STR, "-", REQUIRED, HEAT_TYPES, "convection, radiation or fixed temperature"),
        "h": (NUM, "mW/(mm^2 K)", _X.film_coefficient, (0.0, 10.0), "convection: film coefficient"),
        "emissivity": (NUM, "-", _X.emissivity, (0.0, 1.0), "radiation: emissivity"),
        "T_inf": (
            NUM,
            "C",
            _X.ambient_temperature,
            (-273.15, 1000.0),
            "convection, radiation: ambient temperature",
        ),
        "temperature": (NUM, "C", None, (-273.15, 400.0), "fixed: temperature (also a drive)"),
        "name": (STR, "-", None, None, "fixed: drive tag in [program] temperatures"),
    },
    "supports": {
        "type": (
            STR,
            "-",
            REQUIRED,
            SUPPORT_TYPES,
            "clamp (all components), roller / mirror (normal component), point, 3-2-1",
        ),
        "boundary": (STR, "-", None, None, "clamp, roller, mirror: physical facet name"),
        "normal": (STR, "-", None, tuple(AXES), "roller, mirror: the fixed component"),
        "point": (VEC, "mm", None, None, "point: the node held"),
        "components": (ANY, "-", ["x", "y", "z"], None, "point: components held"),
        "points": (ANY, "mm", None, None, "3-2-1: three points [a, b, c]"),
        "name": (STR, "-", None, None, "reaction force observable's name (default: boundary)"),
    },
    "loads": {
        "type": (STR, "-", REQUIRED, LOAD_TYPES, "force on a boundary, dead pressure, gravity"),
        "boundary": (STR, "-", None, None, "force, pressure: physical facet name"),
        "force": (VEC, "N", None, None, "force: total dead force on the meshed boundary"),
        "pressure": (NUM, "MPa", None, (-1e3, 1e3), "pressure: on the reference normal (dead)"),
        "g": (VEC, "mm/s^2", [0.0, 0.0, -9810.0], None, "gravity: acceleration"),
        "name": (STR, "-", None, None, "drive tag in [program] loads (a factor [-], default 1)"),
    },
    "probes": {
        "name": (STR, "-", REQUIRED, None, "observable prefix"),
        "boundary": (STR, "-", None, None, "mean displacement and temperature of a facet set"),
        "point": (VEC, "mm", None, None, "displacement and temperature at a point"),
    },
    "program": {
        "duration": (NUM, "s", 30.0, (POSITIVE, 1e6), "simulated time (transient)"),
        "dt": (NUM, "s", 0.5, (POSITIVE, 1e5), "time step (backward Euler)"),
        "steady": (
            BOOL,
            "-",
            False,
            None,
            "thermal and mechanical equilibrium at the drives at t = 0",
        ),
        "currents": (
            TABLE,
            "A",
            {},
            None,
            "coil name = current, or [[t, I], ...] (" + CURRENT_RANGE + ")",
        ),
        "temperatures": (TABLE, "C", {}, (-273.15, 400.0), "fixed heat name = T, or [[t, T], ...]"),
        "loads": (TABLE, "-", {}, (-1e6, 1e6), "load name = factor, or [[t, f], ...]"),
        "schedule": (STR, "-", None, None, "CSV: 'time [s]' then '<tag> [A|C|-]' columns"),
        "stretches": (
            TABLE,
            "-",
            {},
            (1.0, 3.0),
            "LCE cell set = spontaneous stretch lambda, reached by "
            "a quasi-static ramp from the as-built lambda_N (load factor 0 -> 1, path follower; "
            "no heat steps, no currents or temperatures)",
        ),
    },
    "compare": {
        "observable": (
            STR,
            "-",
            REQUIRED,
            None,
            "a history observable of this body, 'name [unit]'",
        ),
        "data": (
            STR,
            "-",
            REQUIRED,
            None,
            "CSV relative to the case file: 'time [s]' and the "
            "observable's column with its unit (C or K, mm, um or m, N or mN, mW or W, 1/mm or "
            "1/m)",
        ),
        "tolerance": (
            STR,
            "unit or %",
            REQUIRED,
            None,
            "largest allowed deviation: '0.5 C' "
            "(absolute, any unit of the observable's kind) or '5 %' (of the measured value)",
        ),
        "source": (
            STR,
            "-",
            REQUIRED,
            None,
            "where the measurements come from (shown in the report)",
        ),
    },
    "contact": {
        "boundary": (STR, "-", REQUIRED, None, "facet set whose nodes may not pass through target"),
        "target": (
            STR,
            "-",
            REQUIRED,
            None,
            "facet set of the other body's face towards boundary (single-valued across axis)",
        ),
        "axis": (
            STR,
            "-",
            REQUIRED,
            tuple(AXES),
            "reference direction across the contact: a node of "
            "boundary pairs with the node of target at its two other coordinates",
        ),
        "penalty": (
            NUM,
            "N/mm^3",
            CONTACT_PENALTY,
            (POSITIVE, 1e9),
            "contact pressure per penetration "
            "(default: the composite beam's, solvers/contact.py PenaltyContact)",
        ),
        "name": (STR, "-", None, None, "observable name (default: boundary/target)"),
    },
    "path": {
        "first_step": (
            NUM,
            "-",
            _P.first_step,
            (POSITIVE, 1.0),
            "stretch ramp: first increment of the "
            "load factor (solvers/continuation.py PathControl, as the FE beam's run)",
        ),
        "max_step": (NUM, "-", _P.max_step, (POSITIVE, 1.0), "stretch ramp: largest increment"),
        "min_step": (
            NUM,
            "-",
            _P.min_step,
            (POSITIVE, 1.0),
            "stretch ramp: an increment below this that "
            "still fails is a fold, crossed by damped relaxation",
        ),
        "growth": (
            NUM,
            "-",
            _P.growth,
            (1.0, 100.0),
            "stretch ramp: largest increment growth per step",
        ),
        "target_iterations": (
            INT,
            "-",
            _P.target_iterations,
            (1, 100),
            "stretch ramp: Newton iterations per increment the step size aims at",
        ),
    },
    "curvature": {
        "name": (STR, "-", REQUIRED, None, "observable 'curvature <name> [1/mm]'"),
        "stations": (
            ANY,
            "mm",
            REQUIRED,
            None,
            "three or more stations, each a node [x, y, z] or a list "
            "of nodes (their deformed mean); a node beyond a mirror plane is its image's "
            "mirrored",
        ),
        "up": (
            ANY,
            "mm",
            REQUIRED,
            None,
            "two nodes [a, b]: the curvature is positive when the fitted "
            "circle's centre lies opposite to the deformed b - a",
        ),
    },
    "output": {
        "fields": (BOOL, "-", True, None, "write temperature.bp and displacement.bp (VTX)"),
        "every": (INT, "-", 1, (1, 100000), "a field frame every n steps"),
    },
}
ARRAYS = (
    "regions",
    "coils",
    "heat",
    "supports",
    "loads",
    "probes",
    "compare",
    "contact",
    "curvature",
)

#: Units a measured column or a tolerance may carry: {unit: (kind, scale, offset)}, value in
#: lcefem's unit = scale * value + offset (README: mm, s, N, mW, C). A tolerance is a difference:
#: scale only.
UNITS = {
    "C": ("temperature", 1.0, 0.0),
    "K": ("temperature", 1.0, -273.15),
    "mm": ("length", 1.0, 0.0),
    "um": ("length", 1e-3, 0.0),
    "m": ("length", 1e3, 0.0),
    "N": ("force", 1.0, 0.0),
    "mN": ("force", 1e-3, 0.0),
    "mW": ("power", 1.0, 0.0),
    "W": ("power", 1e3, 0.0),
    "s": ("time", 1.0, 0.0),
    "MPa": ("stress", 1.0, 0.0),
    "kPa": ("stress", 1e-3, 0.0),
    "-": ("ratio", 1.0, 0.0),
    "1/mm": ("curvature", 1.0, 0.0),
    "1/m": ("curvature", 1e-3, 0.0),
}
SECTIONS = ("mesh", "thermal", "program", "output", "petsc", "path", *ARRAYS)


@dataclass(frozen=True)
class Schedule:
    """A drive against time: piecewise linear through (t [s], value) points, constant outside."""

    times: tuple[float, ...]
    values: tuple[float, ...]

    def __call__(self, t: float) -> float:
        return float(np.interp(t, self.times, self.values))


@dataclass(frozen=True)
class BodyCase:
    """A checked case file: each section as a dict of resolved values (every key present)."""

    path: pathlib.Path
    mesh: dict
    thermal: dict
    regions: tuple[dict, ...]
    coils: tuple[dict, ...]
    heat: tuple[dict, ...]
    supports: tuple[dict, ...]
    loads: tuple[dict, ...]
    probes: tuple[dict, ...]
    program: dict
    output: dict
    compare: tuple[dict, ...] = ()
    contact: tuple[dict, ...] = ()
    curvature: tuple[dict, ...] = ()
    path_control: dict = field(default_factory=dict)  # [path]: the stretch ramp's stepping
    petsc: dict = field(default_factory=dict)
    drives: dict = field(default_factory=dict)  # {kind: {tag: Schedule}}
    cell_names: dict = field(default_factory=dict)
    facet_names: dict = field(default_factory=dict)

    @property
    def mesh_file(self) -> pathlib.Path:
        return (self.path.parent / self.mesh["file"]).resolve()

    def resolved(self) -> dict:
        """Every resolved value, with units (summary.json)."""

        def unitised(section: str, values: dict) -> dict:
            spec = SCHEMA[section]
            return {
                k: {"value": _jsonable(v), "unit": spec[k][1]} if k in spec else _jsonable(v)
                for k, v in values.items()
            }

        out = {
            "case_file": str(self.path),
            "mesh": unitised("mesh", self.mesh),
            "thermal": unitised("thermal", self.thermal),
            "program": unitised("program", self.program),
            "output": unitised("output", self.output),
            "petsc": dict(self.petsc),
            "mesh_cell_sets": dict(self.cell_names),
            "mesh_facet_sets": dict(self.facet_names),
        }
        for name in ARRAYS:
            out[name] = [unitised(name, e) for e in getattr(self, name)]
        if self.program.get("stretches"):  # the ramp's stepping
            out["path"] = unitised("path", self.path_control)
        return out


def _jsonable(v):
    if isinstance(v, Schedule):
        return [list(p) for p in zip(v.times, v.values)]
    if isinstance(v, dict):
        return {k: _jsonable(x) for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [_jsonable(x) for x in v]
    return v


class _Checker:
    """Checks one case file; every error names the file and the entry."""

    def __init__(self, path: pathlib.Path):
        self.file = path.name

    def fail(self, entry: str, what: str):
        raise InputError(f"{self.file}: {entry}: {what}")

    def number(self, entry, value, bounds, unit, integer=False):
        if (
            isinstance(value, bool)
            or not isinstance(value, (int, float))
            or (integer and not isinstance(value, int))
        ):
            self.fail(entry, f"{value!r} is not {'an integer' if integer else 'a number'}")
        if not math.isfinite(value):
            self.fail(entry, f"{value} is not finite")
        u = "" if unit in ("-", "") else f" {unit}"
        if isinstance(bounds, tuple) and len(bounds) == 2:
            lo, hi = bounds
            positive = lo == POSITIVE
            if (
                (positive and value <= 0)
                or (not positive and lo is not None and value < lo)
                or (hi is not None and value > hi)
            ):
                low = "> 0" if positive else f">= {lo:g}"
                self.fail(
                    entry,
                    f"{value:g}{u}: allowed {low}{u}"
                    + ("" if hi is None else f" and <= {hi:g}{u}"),
                )
        elif isinstance(bounds, tuple) and value not in bounds:
            self.fail(entry, f"{value}: allowed {', '.join(map(str, bounds))}")
        return float(value) if not integer else int(value)

    def vector(self, entry, value):
        if (
            not isinstance(value, list)
            or len(value) != 3
            or any(isinstance(v, bool) or not isinstance(v, (int, float)) for v in value)
        ):
            self.fail(entry, f"{value!r}: allowed a list of three numbers")
        return [float(v) for v in value]

    def names(self, entry, value):
        names = [value] if isinstance(value, str) else value
        if not isinstance(names, list) or not names or not all(isinstance(n, str) for n in names):
            self.fail(entry, f"{value!r}: allowed a name or a list of names")
        return list(names)

    def table(self, section: str, entry: str, table: Any) -> dict:
        if not isinstance(table, dict):
            self.fail(entry, "must be a table")
        spec = SCHEMA[section]
        unknown = [k for k in table if k not in spec]
        if unknown:
            self.fail(f"{entry}.{unknown[0]}", f"unknown key; allowed: {', '.join(spec)}")
        out = {}
        for key, (kind, unit, default, bounds, _) in spec.items():
            where = f"{entry}.{key}"
            if key not in table:
                if default is REQUIRED:
                    self.fail(where, f"missing ({kind})")
                out[key] = default
                continue
            value = table[key]
            if kind in (NUM, INT):
                out[key] = self.number(where, value, bounds, unit, integer=kind == INT)
            elif kind == STR:
                if not isinstance(value, str) or not value:
                    self.fail(where, f"{value!r} is not a (non-empty) string")
                if bounds is not None and value not in bounds:
                    self.fail(where, f"{value!r}: allowed {', '.join(bounds)}")
                out[key] = value
            elif kind == BOOL:
                if not isinstance(value, bool):
                    self.fail(where, f"{value!r}: allowed true or false")
                out[key] = value
            elif kind == VEC:
                out[key] = self.vector(where, value)
            elif kind == NAMES:
                out[key] = self.names(where, value)
            elif kind == TABLE:
                if not isinstance(value, dict):
                    self.fail(where, f"{value!r}: allowed a table")
                out[key] = value
            else:
                out[key] = value
        return out


def _schedule(check: _Checker, entry: str, value, bounds, unit) -> Schedule:
    """A constant, or [[t, value], ...] with increasing t."""
    if isinstance(value, list):
        if not value or not all(isinstance(p, list) and len(p) == 2 for p in value):
            check.fail(entry, f"{value!r}: allowed a number or a list of [time s, value] pairs")
        ts = [check.number(f"{entry} time", p[0], (0.0, None), "s") for p in value]
        vs = [check.number(entry, p[1], bounds, unit) for p in value]
        if any(b <= a for a, b in zip(ts, ts[1:])):
            check.fail(entry, "times must increase")
        return Schedule(tuple(ts), tuple(vs))
    v = check.number(entry, value, bounds, unit)
    return Schedule((0.0,), (v,))


def _read_schedule_csv(
    check: _Checker, path: pathlib.Path, entry: str
) -> dict[str, tuple[str, Schedule]]:
    """{tag: (unit, Schedule)} of a CSV with a 'time [s]' column and '<tag> [unit]' columns."""
    import csv

    from lcefem.solvers.runtime.inputs import read_text

    rows = list(csv.reader(read_text(path, f"{check.file}: {entry}").splitlines()))
    rows = [r for r in rows if r and not r[0].lstrip().startswith("#")]
    if len(rows) < 2:
        check.fail(entry, f"{path.name}: a header and at least one row needed")
    header = [h.strip() for h in rows[0]]
    if header[0] != "time [s]":
        check.fail(entry, f"{path.name}: first column must be 'time [s]' (got {header[0]!r})")
    try:
        data = np.array([[float(x) for x in r] for r in rows[1:]])
    except ValueError:
        check.fail(entry, f"{path.name}: every value must be a number")
    if data.shape[1] != len(header):
        check.fail(entry, f"{path.name}: every row needs {len(header)} values")
    if np.any(np.diff(data[:, 0]) <= 0):
        check.fail(entry, f"{path.name}: times must increase")
    out = {}
    for j, name in enumerate(header[1:], start=1):
        if not (name.endswith("]") and " [" in name):
            check.fail(
                entry,
                f"{path.name}: column {name!r}: allowed '<tag> [A]', '<tag> [C]' or '<tag> [-]'",
            )
        tag, unit = name[:-1].split(" [", 1)
        out[tag] = (unit, Schedule(tuple(data[:, 0]), tuple(data[:, j])))
    return out


def observable_names(
    cells, coils, probes, supports, contacts=(), curvatures=(), stretches=()
) -> list[str]:
    """The history observables "name [unit]" of a body with these cell sets, coils, probes,
    supports and contacts, as :meth:`lcefem.solvers.problems.body.BodyProblem.observables` names
    them."""
    names = ["T_mean [C]", "T_max [C]"]
    for n in cells:
        names += [f"T_mean {n} [C]", f"T_max {n} [C]"]
    names += [f"power {c['name']} [mW]" for c in coils]
    for p in probes:
        names += [f"u_{a} {p['name']} [mm]" for a in "xyz"] + [f"T {p['name']} [C]"]
    for s in supports:
        if s["type"] in ("clamp", "roller"):
            comps = "xyz" if s["type"] == "clamp" else s["normal"]
            names += [f"reaction_{a} {s['name'] or s['boundary']} [N]" for a in comps]
    for c in contacts:
        names += [f"contact_force {c['name']} [N]", f"min_gap {c['name']} [mm]"]
    names += [f"curvature {c['name']} [1/mm]" for c in curvatures]
    names += [f"stretch {n} [-]" for n in stretches]
    return names


def _check_curvatures(check: _Checker, curvatures: list[dict]) -> None:
    """``[[curvature]]``: names unique, stations a list of >= 3 stations (a point or a list of
    points each), up two points; stored as lists of point lists."""
    seen = set()
    for i, c in enumerate(curvatures):
        e = f"[[curvature]][{i}]"
        if c["name"] in seen:
            check.fail(f"{e}.name", f"{c['name']!r} is used twice")
        seen.add(c["name"])
        st = c["stations"]
        if not isinstance(st, list) or len(st) < 3:
            check.fail(
                f"{e}.stations",
                "allowed a list of three or more stations, each [x, y, z] or a list of [x, y, z]",
            )
        groups = []
        for j, g in enumerate(st):
            pts = [g] if isinstance(g, list) and g and not isinstance(g[0], list) else g
            if not isinstance(pts, list) or not pts:
                check.fail(f"{e}.stations[{j}]", "allowed [x, y, z] or a list of [x, y, z]")
            groups.append([check.vector(f"{e}.stations[{j}]", q) for q in pts])
        c["stations"] = groups
        up = c["up"]
        if not (isinstance(up, list) and len(up) == 2):
            check.fail(f"{e}.up", "allowed two points [[x, y, z], [x, y, z]]")
        c["up"] = [check.vector(f"{e}.up", q) for q in up]
        if np.allclose(c["up"][0], c["up"][1]):
            check.fail(f"{e}.up", "the two points coincide; allowed two different nodes")


def _check_stretches(check: _Checker, prog: dict, regions: list[dict], drives: dict) -> dict:
    """``[program] stretches``: {LCE cell set: target lambda [-]} (numbers, checked against the
    region's lambda_N: between 1 and lambda_N, as :func:`lcefem.models.limits.check_lambda`); a
    quasi-static ramp, so no currents, temperatures or steady state."""
    stretches = prog["stretches"]
    if not stretches:
        return {}
    lce = {n: r for r in regions if r["material"] == "lce" for n in r["name"]}
    for kind in ("currents", "temperatures"):
        if drives[kind]:
            check.fail(
                "[program].stretches",
                f"a stretch ramp is quasi-static: no [program] {kind} "
                f"(given: {', '.join(drives[kind])})",
            )
    if prog["steady"]:
        check.fail("[program].stretches", "a stretch ramp is quasi-static; allowed steady = false")
    out = {}
    for tag, value in stretches.items():
        entry = f"[program].stretches.{tag}"
        if tag not in lce:
            check.fail(entry, f"not an LCE cell set; allowed: {', '.join(lce) or 'none'}")
        v = check.number(entry, value, SCHEMA["program"]["stretches"][3], "-")
        if not 1.0 <= v <= lce[tag]["lambda_N"]:
            check.fail(
                entry,
                f"{v:g}: allowed >= 1 (isotropic) and <= the region's lambda_N = "
                f"{lce[tag]['lambda_N']:g} (as built)",
            )
        out[tag] = v
    return out


def _check_contacts(check: _Checker, contacts: list[dict], facet_set, comm) -> None:
    """``[[contact]]`` entries: two different facet sets of the mesh, names unique (default
    "boundary/target"); node-pair contact runs in serial only."""
    seen = set()
    for i, c in enumerate(contacts):
        e = f"[[contact]][{i}]"
        facet_set(f"{e}.boundary", c["boundary"])
        facet_set(f"{e}.target", c["target"])
        if c["boundary"] == c["target"]:
            check.fail(
                f"{e}.target", f"{c['target']!r} is the boundary itself; allowed another facet set"
            )
        c["name"] = c["name"] or f"{c['boundary']}/{c['target']}"
        if c["name"] in seen:
            check.fail(f"{e}.name", f"{c['name']!r} is used twice")
        seen.add(c["name"])
    _serial_only(check, "[[contact]]", bool(contacts), comm, "node-pair contact")


def _serial_only(check: _Checker, entry: str, used: bool, comm, what: str) -> None:
    """One line when a serial-only feature is used on more than one rank."""
    if used and comm is not None and comm.size > 1:
        check.fail(
            entry,
            f"{what} runs in serial only (this run has {comm.size} ranks); allowed: "
            f"no {entry} under mpiexec",
        )


def _name_unit(label: str) -> tuple[str, str]:
    """("name", "unit") of "name [unit]"."""
    label = label.strip()
    if not (label.endswith("]") and " [" in label):
        return label, ""
    name, unit = label[:-1].rsplit(" [", 1)
    return name.strip(), unit.strip()


def to_unit(value, unit: str, target: str, difference: bool = False):
    """``value`` [unit] in ``target`` (both keys of :data:`UNITS`, of one kind); a ``difference``
    (a tolerance) is scaled only (1 K = 1 C)."""
    _, a, a0 = UNITS[unit]
    _, b, b0 = UNITS[target]
    if difference:
        return np.asarray(value, float) * a / b
    return (np.asarray(value, float) * a + a0 - b0) / b


def _read_measured_csv(check: _Checker, path: pathlib.Path, entry: str, name: str, unit: str):
    """(times [s], values [unit], the file's unit) of a measured CSV: a 'time [s]' column and the
    observable's column ('<name> [<unit>]' or, in a two-column file, any '<label> [<unit>]'), its
    unit of the observable's kind (converted)."""
    import csv

    from lcefem.solvers.runtime.inputs import read_text

    if not path.is_file():
        check.fail(entry, f"{path.name}: file not found (relative to the case file)")
    rows = list(csv.reader(read_text(path, f"{check.file}: {entry}").splitlines()))
    rows = [r for r in rows if r and not r[0].lstrip().startswith("#")]
    if len(rows) < 2:
        check.fail(entry, f"{path.name}: a header and at least one row needed")
    header = [_name_unit(h) for h in rows[0]]
    if header[0] != ("time", "s"):
        check.fail(entry, f"{path.name}: first column must be 'time [s]' (got {rows[0][0]!r})")
    cols = [j for j, (n, _) in enumerate(header) if j and n == name] or (
        [1] if len(header) == 2 else []
    )
    if not cols:
        check.fail(entry, f"{path.name}: no column '{name} [unit]' (columns: {', '.join(rows[0])})")
    j = cols[0]
    got = header[j][1]
    if got not in UNITS or UNITS[got][0] != UNITS.get(unit, ("?",))[0]:
        same = [u for u, k in UNITS.items() if k[0] == UNITS.get(unit, ("?",))[0]]
        check.fail(
            entry,
            f"{path.name}: column {rows[0][j]!r}: unit {got or 'missing'!r}; allowed "
            f"{', '.join(same) or unit} (the observable is in {unit})",
        )
    try:
        data = np.array([[float(r[0]), float(r[j])] for r in rows[1:]])
    except (ValueError, IndexError):
        check.fail(entry, f"{path.name}: every row needs a number in 'time [s]' and {rows[0][j]!r}")
    if not np.all(np.isfinite(data)):
        check.fail(entry, f"{path.name}: values must be finite")
    if np.any(np.diff(data[:, 0]) <= 0):
        check.fail(entry, f"{path.name}: times must increase")
    return data[:, 0].tolist(), to_unit(data[:, 1], got, unit).tolist(), got


def _tolerance(check: _Checker, entry: str, text: str, unit: str) -> dict:
    """{"relative": fraction} of '5 %', or {"absolute": value [unit]} of '0.5 C' (any unit of the
    observable's kind)."""
    parts = text.split()
    try:
        value = float(parts[0]) if len(parts) == 2 else math.nan
    except ValueError:
        value = math.nan
    if not (math.isfinite(value) and value > 0):
        check.fail(entry, f"{text!r}: allowed '<number > 0> %' or '<number > 0> <unit>'")
    if parts[1] == "%":
        return {"relative": value / 100.0, "text": text}
    same = [u for u, k in UNITS.items() if k[0] == UNITS.get(unit, ("?",))[0]]
    if parts[1] not in same:
        check.fail(entry, f"{text!r}: unit {parts[1]!r}; allowed % or {', '.join(same) or unit}")
    return {
        "absolute": float(to_unit(value, parts[1], unit, difference=True)),
        "unit": unit,
        "text": text,
    }


def _check_director_expression(check: _Checker, entry: str, value) -> None:
    """Three strings, each an expression of the reference x, y, z [mm] within the allow-list of
    :mod:`lcefem.solvers.problems.body_expression` (data: parsed, never evaluated by Python)."""
    from lcefem.solvers.problems.body_expression import ALLOWED, ExpressionError, check_expression

    if not (isinstance(value, list) and len(value) == 3 and all(isinstance(v, str) for v in value)):
        check.fail(entry, f"{value!r}: allowed a list of three strings of {ALLOWED}")
    for c, text in zip("xyz", value):
        try:
            check_expression(text)
        except ExpressionError as exc:
            check.fail(f"{entry} ({c} component)", str(exc))


def load_case(path: str | pathlib.Path, comm=None, overrides: dict | None = None) -> BodyCase:
    """The checked case file at ``path`` (see the module docstring); ``overrides`` {(section, key):
    value} replace the file's values (command-line options) before the checks. InputError on bad
    input."""
    from lcefem.meshes.reader import physical_names
    from lcefem.solvers.contraction_curve import read_contraction_csv
    from lcefem.solvers.petsc_options import check_case_options
    from lcefem.solvers.runtime.inputs import read_toml

    path = pathlib.Path(path)
    data = read_toml(path, f"config = {str(path)!r}")
    check = _Checker(path)
    for (section, key), value in (overrides or {}).items():
        if not isinstance(data.setdefault(section, {}), dict):
            check.fail(f"[{section}]", "must be a table")
        data[section][key] = value
    for key, value in data.items():
        if key not in SECTIONS:
            check.fail(f"[{key}]", f"unknown section; allowed: {', '.join(SECTIONS)}")
        if key in ARRAYS and not (
            isinstance(value, list) and all(isinstance(v, dict) for v in value)
        ):
            check.fail(f"[[{key}]]", "must be an array of tables ([[" + key + "]])")
        if key not in ARRAYS and not isinstance(value, dict):
            check.fail(f"[{key}]", "must be a table")
    if "mesh" not in data:
        check.fail("[mesh]", "missing (at least: file = \"body.geo\")")
    if not data.get("regions"):
        check.fail("[[regions]]", "missing: every cell set of the mesh needs a material")
    sec = {
        s: check.table(s, f"[{s}]", data.get(s, {}))
        for s in ("mesh", "thermal", "program", "output", "path")
    }
    arr = {
        s: [check.table(s, f"[[{s}]][{i}]", t) for i, t in enumerate(data.get(s, []))]
        for s in ARRAYS
    }
    try:  # the allow-list every case file's [petsc] goes through (nothing that runs code or writes)
        petsc = check_case_options(data.get("petsc", {}), "[petsc]")
    except InputError as exc:
        check.fail("[petsc]", str(exc).removeprefix("[petsc] "))

    mesh_file = path.parent / sec["mesh"]["file"]
    if not mesh_file.is_file():
        check.fail(
            "[mesh].file", f"{sec['mesh']['file']!r}: file not found (relative to the case file)"
        )
    try:
        cells, facets = physical_names(mesh_file, sec["mesh"]["size_factor"], comm)
    except InputError as exc:
        check.fail("[mesh].file", str(exc))

    def cell_set(entry, name):
        if name not in cells:
            check.fail(
                entry,
                f"{name!r} is not a cell set of {mesh_file.name}; allowed: {', '.join(cells)}",
            )

    def facet_set(entry, name):
        if name not in facets:
            check.fail(
                entry,
                f"{name!r} is not a facet set of {mesh_file.name}; allowed: "
                f"{', '.join(facets) or 'none'}",
            )

    # Regions: every cell set exactly once; LCE and passive keys where they belong.
    material_of = {}
    for i, r in enumerate(arr["regions"]):
        e = f"[[regions]][{i}]"
        for n in r["name"]:
            cell_set(f"{e}.name", n)
            if n in material_of:
                check.fail(f"{e}.name", f"{n!r} already has a material (one region per cell set)")
            material_of[n] = r["material"]
        if r["material"] == "lce":
            for k in ("E", "nu"):
                if r[k] is not None:
                    check.fail(
                        f"{e}.{k}", "only for a passive material (neo-hookean, kapton, glue)"
                    )
            given = [k for k in ("director", "twist", "director_expression") if r[k] is not None]
            if len(given) != 1:
                check.fail(
                    f"{e}",
                    "an LCE region needs exactly one of director = [x, y, z], "
                    "twist = {axis, from_deg, to_deg} or director_expression = [\"...\", "
                    "\"...\", \"...\"]" + (f" (given: {', '.join(given)})" if given else ""),
                )
            if r["director_expression"] is not None:
                _check_director_expression(
                    check, f"{e}.director_expression", r["director_expression"]
                )
            if r["director"] is not None:
                n = np.linalg.norm(r["director"])
                if not n > 1e-12:
                    check.fail(
                        f"{e}.director", f"{r['director']}: zero length; allowed a nonzero vector"
                    )
                r["director"] = [v / n for v in r["director"]]
            if r["twist"] is not None:
                tw = dict(r["twist"])
                unknown = set(tw) - {"axis", "from_deg", "to_deg"}
                if unknown or tw.get("axis") not in AXES:
                    check.fail(
                        f"{e}.twist",
                        "allowed {axis = 'x'|'y'|'z', from_deg = number, to_deg = number}",
                    )
                for k in ("from_deg", "to_deg"):
                    check.number(f"{e}.twist.{k}", tw.get(k), (-3600.0, 3600.0), "deg")
            if r["curve"] is not None:
                # A measured curve (CSV with units, lcefem.solvers.contraction_curve) replaces T_NI,
                # width and lambda_N; read once here so a bad table stops before any mesh is built.
                curve_file = (path.parent / r["curve"]).resolve()
                try:
                    read_contraction_csv(curve_file, T_ref=r["T_ref"])
                except InputError as exc:
                    check.fail(f"{e}.curve", str(exc))
                r["curve"] = str(curve_file)
            if r["lambda_N"] <= 1.0:
                check.fail(f"{e}.lambda_N", f"{r['lambda_N']}: allowed > 1")
        else:
            for k in ("director", "twist", "director_expression", "curve"):
                if r[k] is not None:
                    check.fail(
                        f"{e}.{k}", f"only for material = 'lce' (this region is {r['material']!r})"
                    )
            preset = PRESETS.get(r["material"])
            if preset is None and (r["E"] is None or r["nu"] is None):
                check.fail(e, "a neo-hookean region needs E [MPa] and nu [-]")
            if preset is not None:
                r["E"] = preset[0] if r["E"] is None else r["E"]
                r["nu"] = preset[1] if r["nu"] is None else r["nu"]
    missing = [n for n in cells if n not in material_of]
    if missing:
        check.fail(
            "[[regions]]",
            f"cell set {missing[0]!r} of {mesh_file.name} has no material; "
            "every cell set needs one region",
        )

    # Coils: on LCE regions, names unique.
    coil_names = set()
    for i, c in enumerate(arr["coils"]):
        e = f"[[coils]][{i}]"
        cell_set(f"{e}.region", c["region"])
        if material_of[c["region"]] != "lce":
            check.fail(
                f"{e}.region",
                f"{c['region']!r} is a passive region ({material_of[c['region']]}); "
                "a coil heats an LCE region",
            )
        if c["name"] in coil_names:
            check.fail(f"{e}.name", f"{c['name']!r} is used twice")
        coil_names.add(c["name"])

    # Heat exchange: boundaries named, one ambient per boundary, fixed temperatures named.
    fixed_names, ambient, kinds = set(), {}, {}
    for i, h in enumerate(arr["heat"]):
        e = f"[[heat]][{i}]"
        for b in h["boundary"]:
            facet_set(f"{e}.boundary", b)
            if h["type"] in kinds.get(b, ()):
                check.fail(f"{e}.boundary", f"{b!r} has a {h['type']} entry already")
            if h["type"] == "fixed" and kinds.get(b) or "fixed" in kinds.get(b, ()):
                check.fail(
                    f"{e}.boundary", f"{b!r}: a fixed temperature excludes convection and radiation"
                )
            kinds.setdefault(b, set()).add(h["type"])
            if h["type"] != "fixed":
                if b in ambient and ambient[b] != h["T_inf"]:
                    check.fail(f"{e}.T_inf", f"{b!r}: convection and radiation need one T_inf")
                ambient[b] = h["T_inf"]
        if h["type"] == "fixed":
            if h["temperature"] is None:
                check.fail(f"{e}.temperature", "missing: a fixed temperature [C]")
            h["name"] = h["name"] or "+".join(h["boundary"])
            fixed_names.add(h["name"])
        elif h["name"] is not None or h["temperature"] is not None:
            check.fail(e, "name and temperature are keys of a fixed temperature only")

    # Supports: named boundaries, no component constrained twice.
    held: dict[str, set] = {}
    for i, s in enumerate(arr["supports"]):
        e = f"[[supports]][{i}]"
        t = s["type"]
        if t in ("clamp", "roller", "mirror"):
            if s["boundary"] is None:
                check.fail(f"{e}.boundary", f"missing: a {t} acts on a facet set")
            facet_set(f"{e}.boundary", s["boundary"])
            if t != "clamp" and s["normal"] is None:
                check.fail(f"{e}.normal", f"missing: the component a {t} fixes ('x', 'y' or 'z')")
            comps = {0, 1, 2} if t == "clamp" else {AXES[s["normal"]]}
            twice = held.setdefault(s["boundary"], set()) & comps
            if twice:
                check.fail(
                    e,
                    f"boundary {s['boundary']!r}: component "
                    f"{'xyz'[min(twice)]} is constrained twice; allowed one support per component",
                )
            held[s["boundary"]] |= comps
        elif t == "point":
            if s["point"] is None:
                check.fail(f"{e}.point", "missing: [x, y, z] mm")
            comps = s["components"]
            if not (
                isinstance(comps, list)
                and comps
                and all(c in AXES for c in comps)
                and len(set(comps)) == len(comps)
            ):
                check.fail(
                    f"{e}.components", f"{comps!r}: allowed a list of distinct 'x', 'y', 'z'"
                )
        else:  # 3-2-1
            pts = s["points"]
            if not (isinstance(pts, list) and len(pts) == 3):
                check.fail(f"{e}.points", "allowed three points [[x, y, z], [x, y, z], [x, y, z]]")
            s["points"] = [check.vector(f"{e}.points", p) for p in pts]
    load_names = set()
    for i, ld in enumerate(arr["loads"]):
        e = f"[[loads]][{i}]"
        if ld["type"] in ("force", "pressure"):
            if ld["boundary"] is None:
                check.fail(f"{e}.boundary", f"missing: a {ld['type']} acts on a facet set")
            facet_set(f"{e}.boundary", ld["boundary"])
            if ld[ld["type"]] is None:
                check.fail(f"{e}.{ld['type']}", "missing")
        ld["name"] = ld["name"] or f"{ld['type']}{i}"
        load_names.add(ld["name"])
    for i, p in enumerate(arr["probes"]):
        e = f"[[probes]][{i}]"
        if (p["boundary"] is None) == (p["point"] is None):
            check.fail(e, "a probe needs exactly one of boundary or point")
        if p["boundary"] is not None:
            facet_set(f"{e}.boundary", p["boundary"])

    _check_contacts(check, arr["contact"], facet_set, comm)

    if sec["mesh"]["refine"] and mesh_file.suffix.lower() == ".geo":
        check.fail(
            "[mesh].refine",
            "a .geo is refined by its size_factor; refine is for a read mesh (.msh, .vtu, .xdmf)",
        )

    # Comparisons with measurements: the observable exists, the data's units are known and of its
    # kind.
    _check_curvatures(check, arr["curvature"])
    names = observable_names(
        cells,
        arr["coils"],
        arr["probes"],
        arr["supports"],
        arr["contact"],
        arr["curvature"],
        sec["program"]["stretches"],
    )
    for i, c in enumerate(arr["compare"]):
        e = f"[[compare]][{i}]"
        name, unit = _name_unit(c["observable"])
        if c["observable"] not in names:
            check.fail(
                f"{e}.observable",
                f"{c['observable']!r} is not an observable of this body; allowed: "
                f"{', '.join(names)}",
            )
        data_file = (path.parent / c["data"]).resolve()
        c["data"] = str(data_file)
        c["times [s]"], c["values"], c["data_unit"] = _read_measured_csv(
            check, data_file, f"{e}.data", name, unit
        )
        c["tolerance"] = _tolerance(check, f"{e}.tolerance", c["tolerance"], unit)

    # The program: drives by tag, each a constant or a schedule.
    prog = sec["program"]
    if not prog["steady"]:
        if prog["dt"] > prog["duration"]:
            check.fail(
                "[program].dt", f"{prog['dt']} s: allowed <= duration = {prog['duration']} s"
            )
    drives = {"currents": {}, "temperatures": {}, "loads": {}}
    known = {"currents": coil_names, "temperatures": fixed_names, "loads": load_names}
    units = {"currents": "A", "temperatures": "C", "loads": "-"}
    for kind in drives:
        bounds = SCHEMA["program"][kind][3]
        for tag, value in prog[kind].items():
            if tag not in known[kind]:
                check.fail(
                    f"[program].{kind}.{tag}",
                    f"not a {kind[:-1]} tag; allowed: {', '.join(sorted(known[kind])) or 'none'}",
                )
            drives[kind][tag] = _schedule(
                check, f"[program].{kind}.{tag}", value, bounds, units[kind]
            )
            if kind == "currents":
                check_current(
                    f"{check.file}: [program].currents.{tag}", list(drives[kind][tag].values)
                )
    if prog["schedule"] is not None:
        by_unit = {"A": "currents", "C": "temperatures", "-": "loads"}
        for tag, (unit, sched) in _read_schedule_csv(
            check, path.parent / prog["schedule"], "[program].schedule"
        ).items():
            kind = by_unit.get(unit)
            if kind is None or tag not in known[kind]:
                check.fail(
                    "[program].schedule",
                    f"column '{tag} [{unit}]': not a coil [A], fixed "
                    "temperature [C] or load [-] tag of this case",
                )
            if tag in drives[kind]:
                check.fail("[program].schedule", f"{tag!r} is also given in [program].{kind}")
            for v in sched.values:
                check.number(f"[program].schedule {tag}", v, SCHEMA["program"][kind][3], unit)
            if kind == "currents":
                check_current(f"{check.file}: [program].schedule {tag}", list(sched.values))
            drives[kind][tag] = sched
    prog["stretches"] = _check_stretches(check, prog, arr["regions"], drives)
    _serial_only(
        check,
        "[program].stretches",
        bool(prog["stretches"]),
        comm,
        "the stretch ramp's relaxation across folds (nodal damping)",
    )
    _serial_only(check, "[[curvature]]", bool(arr["curvature"]), comm, "the station lookup")
    if prog["stretches"] and arr["compare"]:
        check.fail(
            "[[compare]]",
            "measurements are compared against time and a stretch ramp's clock is "
            "its load factor; allowed: no [[compare]] with [program] stretches",
        )
    path_ = sec["path"]
    if path_["min_step"] > path_["max_step"] or path_["first_step"] > path_["max_step"]:
        check.fail(
            "[path]",
            f"allowed min_step ({path_['min_step']:g}) and first_step "
            f"({path_['first_step']:g}) <= max_step ({path_['max_step']:g})",
        )
    if "path" in data and not prog["stretches"]:
        check.fail("[path]", "only with a stretch ramp ([program] stretches)")
    return BodyCase(
        path=path.resolve(),
        mesh=sec["mesh"],
        thermal=sec["thermal"],
        regions=tuple(arr["regions"]),
        coils=tuple(arr["coils"]),
        heat=tuple(arr["heat"]),
        supports=tuple(arr["supports"]),
        loads=tuple(arr["loads"]),
        probes=tuple(arr["probes"]),
        program=prog,
        output=sec["output"],
        compare=tuple(arr["compare"]),
        contact=tuple(arr["contact"]),
        curvature=tuple(arr["curvature"]),
        path_control=sec["path"],
        petsc=petsc,
        drives=drives,
        cell_names=cells,
        facet_names=facets,
    )
