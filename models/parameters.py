"""Parameter dataclasses whose every field carries a unit and a source.

A field is declared with :func:`param`; :func:`describe` turns an instance into the resolved
configuration written next to results; :func:`with_overrides` applies a case file's table
and rejects unknown keys with a one-line :class:`~lcefem.models.errors.InputError`.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

from lcefem.models.errors import InputError


def param(
    default: Any,
    unit: str,
    source: str,
    *,
    minimum: float | None = None,
    maximum: float | None = None,
    positive: bool = False,
) -> Any:
    """A dataclass field with ``unit`` and ``source`` metadata and optional bounds."""
    meta = {
        "unit": unit,
        "source": source,
        "minimum": minimum,
        "maximum": maximum,
        "positive": positive,
    }
    return dataclasses.field(default=default, metadata=meta)


def describe(obj: Any) -> dict[str, dict[str, Any]]:
    """``{field: {"value", "unit", "source"}}`` for a parameter dataclass instance."""
    out = {}
    for f in dataclasses.fields(obj):
        out[f.name] = {
            "value": getattr(obj, f.name),
            "unit": f.metadata.get("unit", ""),
            "source": f.metadata.get("source", ""),
        }
    return out


def check(obj: Any, section: str = "") -> Any:
    """Check every bounded field of ``obj``; raise InputError naming the first bad one."""
    prefix = f"{section}." if section else ""
    for f in dataclasses.fields(obj):
        value = getattr(obj, f.name)
        meta = f.metadata
        if not isinstance(value, (int, float)) or isinstance(value, bool):
            continue
        name = f"{prefix}{f.name}"
        unit = f" {meta.get('unit')}" if meta.get("unit") not in (None, "", "-") else ""
        if not math.isfinite(value):
            raise InputError(f"{name} = {value}: must be a finite number")
        if meta.get("positive") and value <= 0:
            raise InputError(f"{name} = {value}: must be > 0{unit}")
        if meta.get("minimum") is not None and value < meta["minimum"]:
            raise InputError(f"{name} = {value}: must be >= {meta['minimum']}{unit}")
        if meta.get("maximum") is not None and value > meta["maximum"]:
            raise InputError(f"{name} = {value}: must be <= {meta['maximum']}{unit}")
    return obj


def with_overrides(obj: Any, table: dict[str, Any] | None, section: str) -> Any:
    """Return a copy of ``obj`` with the keys of ``table`` replaced, type-checked and bounded.

    Raises:
        InputError: for an unknown key (the message lists the allowed ones), a value of the
            wrong type, or a value outside the field's bounds.
    """
    if not table:
        return check(obj, section)
    names = {f.name: f for f in dataclasses.fields(obj)}
    changes = {}
    for key, value in table.items():
        if key not in names:
            allowed = ", ".join(sorted(names))
            raise InputError(f"unknown key '{section}.{key}'; allowed: {allowed}")
        current = getattr(obj, key)
        if isinstance(current, bool) or isinstance(value, bool):
            ok = isinstance(value, bool) and isinstance(current, bool)
        elif isinstance(current, (int, float)):
            ok = isinstance(value, (int, float))
            if ok and isinstance(current, float):
                value = float(value)
        else:
            ok = isinstance(value, type(current))
        if not ok:
            raise InputError(f"{section}.{key} = {value!r}: expected {type(current).__name__}")
        changes[key] = value
    return check(dataclasses.replace(obj, **changes), section)
