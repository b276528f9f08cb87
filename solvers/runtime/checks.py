"""Physical bounds of every input (:func:`check_physical`, :func:`check_config`) and of every result
during a run (:func:`check_row`, raising lcefem.models.errors.PhysicalBoundsError), and the resolved
configuration written next to results (:func:`resolved`)."""

from __future__ import annotations

import dataclasses
import math

from lcefem.models.errors import InputError, PhysicalBoundsError
from lcefem.models.limits import (
    ABSOLUTE_ZERO,
    DECOMPOSITION_TEMPERATURE,
    MAX_DURATION,
    TEMPERATURE_RANGE,
    check_current,
    check_temperature,
)

__all__ = [
    "TEMPERATURE_RANGE",
    "check_config",
    "check_physical",
    "check_row",
    "check_seed",
    "check_temperature",
    "resolved",
]


def check_seed(name: str, value) -> int:
    """A random seed: an integer between 0 and 2^32 - 1, both included (numpy's legacy seed range,
    the one every command's --seed shares); raises InputError naming ``name``."""
    if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value <= 2**32 - 1:
        raise InputError(
            f"{name} = {value!r}: must be an integer between 0 and 2^32 - 1, both included "
            "(numpy's seed)"
        )
    return value


def check_physical(config, section: str = "") -> None:
    """Bounds every parameter must satisfy whatever its section: currents [A] (the one check,
    lcefem.models.limits.check_current), durations [s] up to MAX_DURATION, temperatures [C] above
    absolute zero and below decomposition, moduli [MPa] > 0 (other stiffness coefficients >= 0),
    integer fields integers.
    Walks nested dataclasses; the message names the field (``section.field``)."""
    for f in dataclasses.fields(config):
        value = getattr(config, f.name)
        name = f"{section}.{f.name}" if section else f.name
        if dataclasses.is_dataclass(value):
            check_physical(value, name)
            continue
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            continue
        if (
            isinstance(f.default, int)
            and not isinstance(f.default, bool)
            and not isinstance(value, int)
        ):
            raise InputError(f"{name} = {value}: must be an integer")
        if not math.isfinite(value):
            raise InputError(f"{name} = {value}: must be a finite number")
        unit = f.metadata.get("unit")
        if unit == "A" and "current" in f.name:
            check_current(name, value)
        if unit == "s" and "duration" in f.name and value > MAX_DURATION:
            raise InputError(
                f"{name} = {value} s: must be <= {MAX_DURATION} s (lcefem.models.limits)"
            )
        if unit == "C":
            check_temperature(name, value)
        elif unit == "MPa" and "modulus" in f.name and not value > 0:
            raise InputError(f"{name} = {value} MPa: a modulus must be > 0 MPa")
        elif unit == "MPa" and value < 0:
            raise InputError(f"{name} = {value} MPa: must be >= 0 MPa")


def check_row(row: dict, where: str) -> None:
    """Results must be finite (time may be infinite: a steady state) and temperatures (columns in
    [C]) inside the physical range; raises :class:`PhysicalBoundsError`."""
    for key, value in row.items():
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            continue
        if not math.isfinite(value):
            if key.startswith("time") and value == math.inf:
                continue
            raise PhysicalBoundsError(where, f"{key} = {value} is not a finite number")
        if key.endswith("[C]") and not ABSOLUTE_ZERO < value < DECOMPOSITION_TEMPERATURE:
            raise PhysicalBoundsError(where, f"{key} = {value:.6g}: must be {TEMPERATURE_RANGE}")


def check_config(config, raw_sections: tuple[str, ...] = ("petsc",)):
    """Each section's own bounds (lcefem.models.parameters.check), then :func:`check_physical`."""
    from lcefem.models.parameters import check

    for f in dataclasses.fields(config):
        if f.name not in raw_sections:
            check(getattr(config, f.name), f.name)
    check_physical(config)
    return config


def resolved(config) -> dict:
    """The configuration as written next to results: every value with its unit and source."""
    from lcefem.models.parameters import describe

    return {
        f.name: dict(getattr(config, f.name))
        if isinstance(getattr(config, f.name), dict)
        else describe(getattr(config, f.name))
        for f in dataclasses.fields(config)
    }
