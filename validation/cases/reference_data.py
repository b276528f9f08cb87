"""Reference numbers with units and sources, read from ``validation/data/*.toml``.

Cases take every measured or published number from here, never from literals::

    from lcefem.validation.cases.reference_data import reference
    f_ult = reference("blocked.rupture_force")      # Reference
    f_ult.value, f_ult.unit                          # 1.36, "N"  (lcefem units)
    f_ult.source                                     # 'seed 001 (...), Results, ...:
                                                     #  "The ultimate ..."'
    p = reference("strip.transient_powers")          # value (1500.0, 3260.0, 5790.0) mW,
                                                     # spread in mW
    reference("surface.dome.curvature_exp")["kx"]    # -0.016 (1/mm), by component name

Values are converted from the published unit (``published_value``, ``published_unit``) into the
lcefem unit system (mm, s, N, MPa, mJ, mW, tonne, C; currents in A, resistances in ohm).
"""

from __future__ import annotations

import functools
import math
import pathlib
import tomllib
from dataclasses import dataclass

from lcefem.models import units
from lcefem.models.empirical import Eq2
from lcefem.models.errors import InputError

DATA_DIR = pathlib.Path(__file__).resolve().parents[1] / "data"
DATASETS = ("seed001",)

#: published unit -> (lcefem unit, factor): internal = factor * published
UNIT_CONVERSIONS: dict[str, tuple[str, float]] = {
    "-": ("-", 1.0),
    "%": ("-", 0.01),
    "count": ("count", 1.0),
    "mm": ("mm", 1.0),
    "um": ("mm", 1.0e-3),
    "1/mm": ("1/mm", 1.0),
    "s": ("s", 1.0),
    "Hz": ("1/s", 1.0),
    "C": ("C", 1.0),
    "N": ("N", 1.0),
    "MPa": ("MPa", 1.0),
    "g": ("t", units.GRAM),
    "W": ("mW", units.W),
    "1/W": ("1/mW", 1.0 / units.W),
    "A": ("A", 1.0),
    "ohm": ("ohm", 1.0),
    "ohm/mm": ("ohm/mm", 1.0),
}

KINDS = ("measured", "fitted", "setting", "design", "simulated", "definition")
BOUNDS = ("", "approx", "upper", "lower")
REQUIRED = ("value", "unit", "kind", "section", "quote")
OPTIONAL = ("spread", "spread_kind", "samples", "bound", "components", "note")

Number = float | tuple[float, ...]


@dataclass(frozen=True)
class Reference:
    """One reference number (or a list of numbers that belong together), in lcefem units."""

    key: str
    value: Number  #: in ``unit`` (lcefem units)
    unit: str
    published_value: Number
    published_unit: str
    kind: str  #: measured | fitted | setting | design | simulated | definition
    section: str  #: where in the source document
    quote: str  #: short verbatim excerpt holding the number
    citation: str  #: the document, e.g. "seed 001 (Liu, Hacker, Daraio, Sci. Robotics 2021)"
    spread: Number | None = None  #: +- in ``unit`` (see ``spread_kind``)
    spread_kind: str = ""
    samples: int | None = None
    bound: str = ""  #: "" (as stated) | approx | upper | lower
    components: tuple[str, ...] | None = None
    note: str = ""

    @property
    def source(self) -> str:
        """Citation, place and quote, for Metric.source and figure captions."""
        return f'{self.citation}, {self.section}: "{self.quote}"'

    @property
    def cite(self) -> str:
        """Citation and place without the quote (short, for figure footers and captions)."""
        return f"{self.citation}, {self.section}"

    def __getitem__(self, component: str) -> float:
        """The entry of a list value by component name, e.g. ``ref["kx"]``."""
        if self.components is None or component not in self.components:
            allowed = ", ".join(self.components or ())
            raise InputError(
                f"{self.key}: no component '{component}'; allowed: {allowed or 'none'}"
            )
        return self.value[self.components.index(component)]

    def __float__(self) -> float:
        if isinstance(self.value, tuple):
            raise TypeError(f"{self.key} holds {len(self.value)} numbers; index it")
        return self.value


def _numbers(raw, key: str, field: str) -> Number:
    if isinstance(raw, bool):
        raise InputError(f"{key}.{field} = {raw!r}: expected a number or a list of numbers")
    if isinstance(raw, (int, float)):
        return float(raw)
    if (
        isinstance(raw, list)
        and raw
        and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in raw)
    ):
        return tuple(float(v) for v in raw)
    raise InputError(f"{key}.{field} = {raw!r}: expected a number or a list of numbers")


def _scale(value: Number, factor: float) -> Number:
    return tuple(factor * v for v in value) if isinstance(value, tuple) else factor * value


def _entry(key: str, table: dict, citation: str) -> Reference:
    unknown = set(table) - set(REQUIRED) - set(OPTIONAL)
    if unknown:
        raise InputError(
            f"{key}: unknown field(s) {', '.join(sorted(unknown))}; allowed: "
            f"{', '.join(REQUIRED + OPTIONAL)}"
        )
    missing = [f for f in REQUIRED if not table.get(f) and table.get(f) != 0]
    if missing:
        raise InputError(f"{key}: missing {', '.join(missing)}")
    unit = table["unit"]
    if unit not in UNIT_CONVERSIONS:
        raise InputError(f"{key}.unit = '{unit}': allowed: {', '.join(UNIT_CONVERSIONS)}")
    if table["kind"] not in KINDS:
        raise InputError(f"{key}.kind = '{table['kind']}': allowed: {', '.join(KINDS)}")
    bound = table.get("bound", "")
    if bound not in BOUNDS:
        raise InputError(f"{key}.bound = '{bound}': allowed: {', '.join(b for b in BOUNDS if b)}")
    value = _numbers(table["value"], key, "value")
    if not all(math.isfinite(v) for v in (value if isinstance(value, tuple) else (value,))):
        raise InputError(f"{key}.value: must be finite")
    spread = _numbers(table["spread"], key, "spread") if "spread" in table else None
    components = tuple(table["components"]) if "components" in table else None
    for name, other in (("spread", spread), ("components", components)):
        if other is not None and (
            isinstance(value, tuple) != isinstance(other, tuple)
            or (isinstance(value, tuple) and len(other) != len(value))
        ):
            raise InputError(f"{key}.{name}: must have the same shape as value")
    internal_unit, factor = UNIT_CONVERSIONS[unit]
    return Reference(
        key=key,
        value=_scale(value, factor),
        unit=internal_unit,
        published_value=value,
        published_unit=unit,
        kind=table["kind"],
        section=table["section"],
        quote=table["quote"],
        citation=citation,
        spread=None if spread is None else _scale(spread, factor),
        spread_kind=table.get("spread_kind", ""),
        samples=table.get("samples"),
        bound=bound,
        components=components,
        note=table.get("note", ""),
    )


def _flatten(table: dict, prefix: str, citation: str, out: dict[str, Reference]) -> None:
    for name, sub in table.items():
        key = f"{prefix}{name}"
        if not isinstance(sub, dict):
            raise InputError(f"{key}: expected a table with value, unit, kind, section, quote")
        if "value" in sub:
            out[key] = _entry(key, sub, citation)
        else:
            _flatten(sub, f"{key}.", citation, out)


@functools.cache
def load(dataset: str = "seed001") -> dict[str, Reference]:
    """All references of ``validation/data/<dataset>.toml``, by dotted key."""
    if dataset not in DATASETS:
        raise InputError(f"dataset '{dataset}': allowed: {', '.join(DATASETS)}")
    path = DATA_DIR / f"{dataset}.toml"
    with path.open("rb") as fh:
        doc = tomllib.load(fh)
    meta = doc.pop("meta", {})
    citation = meta.get("short") or meta.get("citation") or dataset
    out: dict[str, Reference] = {}
    _flatten(doc, "", citation, out)
    return out


def metadata(dataset: str = "seed001") -> dict:
    """The ``[meta]`` table (seed file name, full citation)."""
    with (DATA_DIR / f"{dataset}.toml").open("rb") as fh:
        return tomllib.load(fh).get("meta", {})


def reference(key: str, dataset: str = "seed001") -> Reference:
    """The reference stored under ``key``; an unknown key raises InputError naming close matches."""
    table = load(dataset)
    if key not in table:
        import difflib

        close = difflib.get_close_matches(key, table, n=5, cutoff=0.5)
        hint = f"; did you mean: {', '.join(close)}" if close else ""
        raise InputError(f"unknown reference '{key}' in {dataset}{hint}")
    return table[key]


@dataclass(frozen=True)
class Cause:
    """One distinct physical gap behind one or more known disagreements
    (``validation/data/known_disagreements.toml``, ``[[cause]]``)."""

    id: str  #: named by the rows it explains
    title: str  #: a few words
    statement: str  #: what disagrees and why
    controlled_changes: str  #: the measured changes that show the cause, with their sources
    missing_datum: str  #: what the experiment would have to give to decide it
    issue: int  #: the issue that decides it


@dataclass(frozen=True)
class KnownDisagreement:
    """A judged row that fails because the model genuinely disagrees with its reference
    (``validation/data/known_disagreements.toml``, ``[[disagreement]]``): listed by the report under
    its cause, tolerated by the tests."""

    case: str
    metric: str  #: exactly as in metrics.json
    cause: Cause
    level: str  #: quick | full | both: where the row is expected to fail
    note: str = ""  #: the row's own numbers, one line

    @property
    def issue(self) -> int:
        """The issue that decides the row's cause."""
        return self.cause.issue

    @property
    def explanation(self) -> str:
        """The row's note and its cause's statement."""
        return " ".join(t for t in (self.note, self.cause.statement) if t)


_CAUSE_FIELDS = ("id", "title", "statement", "controlled_changes", "missing_datum", "issue")
_ROW_FIELDS = ("case", "metric", "cause", "level", "note")


@functools.cache
def _registry(
    path: pathlib.Path,
) -> tuple[dict[str, Cause], dict[tuple[str, str], KnownDisagreement]]:
    with path.open("rb") as fh:
        data = tomllib.load(fh)
    causes: dict[str, Cause] = {}
    for i, c in enumerate(data.get("cause", [])):
        if set(c) != set(_CAUSE_FIELDS) or not all(str(c[k]).strip() for k in _CAUSE_FIELDS):
            raise InputError(
                f"{path.name}: cause {i + 1} needs exactly {', '.join(sorted(_CAUSE_FIELDS))}"
                f" (none empty); got {', '.join(sorted(c))}"
            )
        if c["id"] in causes:
            raise InputError(f"{path.name}: cause {c['id']} listed twice")
        causes[c["id"]] = Cause(**c)
    rows: dict[tuple[str, str], KnownDisagreement] = {}
    for i, e in enumerate(data.get("disagreement", [])):
        if not {"case", "metric", "cause", "level"} <= set(e) <= set(_ROW_FIELDS) or e[
            "level"
        ] not in ("quick", "full", "both"):
            raise InputError(
                f"{path.name}: entry {i + 1} needs case, metric, cause, level (quick | full |"
                f" both) and may have a note; got {', '.join(sorted(e))}"
            )
        if e["cause"] not in causes:
            raise InputError(
                f"{path.name}: entry {i + 1} names cause '{e['cause']}', not one of "
                f"{', '.join(causes)}"
            )
        key = (e["case"], e["metric"])
        if key in rows:
            raise InputError(f"{path.name}: {key[0]} / {key[1]} listed twice")
        rows[key] = KnownDisagreement(**{**e, "cause": causes[e["cause"]]})
    idle = sorted(set(causes) - {k.cause.id for k in rows.values()})
    if idle:
        raise InputError(f"{path.name}: cause(s) {', '.join(idle)} explain no row")
    return causes, rows


def known_disagreements(
    path: pathlib.Path | None = None,
) -> dict[tuple[str, str], KnownDisagreement]:
    """The registry of known disagreements, by (case, metric), each with its :class:`Cause`; a
    malformed entry, a row naming no registered cause or a cause explaining no row raises
    InputError."""
    return _registry(DATA_DIR / "known_disagreements.toml" if path is None else pathlib.Path(path))[
        1
    ]


def causes(path: pathlib.Path | None = None) -> dict[str, Cause]:
    """The causes of the known disagreements, by id, in the registry's order."""
    return _registry(DATA_DIR / "known_disagreements.toml" if path is None else pathlib.Path(path))[
        0
    ]


def eq2_parameters(eq2: Eq2 = Eq2()) -> str:
    """Eq. 2's inputs as text for captions, from the one definition in :class:`Eq2`."""
    return (
        f"eta = {eq2.eta:g}, l_p = {eq2.ribbon_length:g} mm, t_a = {eq2.strip_thickness:g} mm, "
        f"lambda_N = {eq2.lambda_N:g}"
    )


def eq2_inputs_note(eq2: Eq2 = Eq2()) -> str:
    """How Eq. 2's inputs are chosen, as text for captions and sources."""
    return (
        f"Eq. 2 with l_p = {eq2.ribbon_length:g} mm (the segment's straight length, as the beam's "
        f"bottom strips span it), t_a = {eq2.strip_thickness:g} mm (the cast strip thickness), "
        f"lambda_N = {eq2.lambda_N:g} (the published model's isotropic/nematic ratio, the same "
        "lambda_N the bar-and-hinge rest lengths use, so that lambda_T = lambda_B = lambda_N is "
        "the "
        f"flat as-built beam in both), eta = {eq2.eta:g} (seed 001)"
    )
