"""The phenomenon each validation case must show at every resolution (issue 16).

A quick (CI) level is only worth running when it shows the same physics as the full level: the
ribbon rolls or does not roll, the specimen buckles, the beam bends towards its shorter strip. Each
case's phenomena are declared once, in ``validation/data/phenomena.toml``, as conditions on the
values of its own metrics; ``lcefem validate`` evaluates them at whatever level it runs (the report
lists them, a phenomenon that is not shown is flagged), and tests/validation/test_quick_cases.py
asserts that the quick level shows every one of them. The full level is judged by the same
declarations in the report of ``make validate``.

Declaration (one ``[[phenomenon]]`` per claim)::

    [[phenomenon]]
    case = "beam_curvature_fe"
    phenomenon = "the beam bends towards its shorter (bottom) strip"
    metric = "kappa_FE at (1.33, 1.05) vs Eq. 2"      # exact metric name, or
    # pattern = "^dome \\(lambda\\): kappa_[xy] circle"  # a regular expression (every match
    #                                                    must hold)
    above = 0.0                                        # and/or below = ...; value strictly inside
    why = "seed 001 Fig. 3: the strip that contracts more (lambda_B < lambda_T) is on the inside"

The bounds are qualitative (a sign, "rolls" meaning a speed above a creep level), never a tolerance:
tolerances belong to the judged rows.
"""

from __future__ import annotations

import functools
import math
import pathlib
import re
import tomllib
from dataclasses import dataclass

from lcefem.models.errors import InputError

PHENOMENA_FILE = pathlib.Path(__file__).resolve().parents[1] / "data" / "phenomena.toml"
_KEYS = {"case", "phenomenon", "metric", "pattern", "above", "below", "why"}


@dataclass(frozen=True)
class Phenomenon:
    """A qualitative claim about a case's result: every selected metric value lies in (above,
    below)."""

    case: str
    phenomenon: str  #: what is shown, in words
    why: str  #: the physics or the source that says it must be so
    metric: str = ""  #: exact metric name ...
    pattern: str = ""  #: ... or a regular expression over metric names (re.search)
    above: float | None = None
    below: float | None = None

    def selects(self, name: str) -> bool:
        return name == self.metric if self.metric else re.search(self.pattern, name) is not None

    def holds_for(self, value) -> bool:
        if value is None or not isinstance(value, (int, float)) or not math.isfinite(value):
            return False
        return (self.above is None or value > self.above) and (
            self.below is None or value < self.below
        )

    def condition(self) -> str:
        parts = ([f"> {self.above:g}"] if self.above is not None else []) + (
            [f"< {self.below:g}"] if self.below is not None else []
        )
        return " and ".join(parts)


def _parse(entry: dict, where: str) -> Phenomenon:
    unknown = set(entry) - _KEYS
    if unknown:
        raise InputError(f"{where}: unknown key(s) {sorted(unknown)}; allowed: {sorted(_KEYS)}")
    for key in ("case", "phenomenon", "why"):
        if not isinstance(entry.get(key), str) or not entry[key].strip():
            raise InputError(f"{where}.{key}: a non-empty string is required")
    if bool(entry.get("metric")) == bool(entry.get("pattern")):
        raise InputError(
            f"{where}: give exactly one of metric (exact name) or pattern (regular expression)"
        )
    if entry.get("pattern"):
        try:
            re.compile(entry["pattern"])
        except re.error as exc:
            raise InputError(f"{where}.pattern: not a regular expression ({exc})") from None
    bounds = {k: entry.get(k) for k in ("above", "below")}
    if all(v is None for v in bounds.values()):
        raise InputError(f"{where}: give above and/or below")
    for k, v in bounds.items():
        if v is not None and (isinstance(v, bool) or not isinstance(v, (int, float))):
            raise InputError(f"{where}.{k}: must be a number, got {v!r}")
    return Phenomenon(
        case=entry["case"],
        phenomenon=entry["phenomenon"],
        why=entry["why"],
        metric=entry.get("metric", ""),
        pattern=entry.get("pattern", ""),
        above=None if bounds["above"] is None else float(bounds["above"]),
        below=None if bounds["below"] is None else float(bounds["below"]),
    )


@functools.cache
def declared(path: pathlib.Path = PHENOMENA_FILE) -> tuple[Phenomenon, ...]:
    """Every declared phenomenon, in file order."""
    with open(path, "rb") as fh:
        data = tomllib.load(fh)
    entries = data.get("phenomenon", [])
    if set(data) - {"phenomenon"}:
        raise InputError(
            f"{path.name}: unknown table(s) {sorted(set(data) - {'phenomenon'})}; "
            "only [[phenomenon]] entries are allowed"
        )
    return tuple(_parse(e, f"{path.name}: phenomenon {i + 1}") for i, e in enumerate(entries))


def for_case(case: str) -> list[Phenomenon]:
    return [p for p in declared() if p.case == case]


def evaluate(case: str, metrics: list[dict]) -> list[dict]:
    """The case's phenomena checked against its metric rows (dicts with "metric" and "value").

    Each result: phenomenon, why, condition, the selected values {metric: value}, and ``holds``
    (True when at least one row is selected and every selected value meets the condition; a
    phenomenon whose metric is missing does not hold: the case no longer reports what it must
    show)."""
    out = []
    for p in for_case(case):
        values = {m["metric"]: m.get("value") for m in metrics if p.selects(m["metric"])}
        holds = bool(values) and all(p.holds_for(v) for v in values.values())
        out.append(
            {
                "phenomenon": p.phenomenon,
                "why": p.why,
                "condition": p.condition(),
                "selector": p.metric or f"/{p.pattern}/",
                "values": values,
                "holds": holds,
            }
        )
    return out
