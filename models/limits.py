"""Physical limits every input and result must respect (checked by lcefem.solvers.runtime.checks).

Beyond them the models describe nothing real: a run is refused (inputs, exit 2) or stopped
(results, exit 3) with the field named.
"""

import math

import numpy as np

from lcefem.models.errors import InputError
from lcefem.models.parameters import param

#: Absolute zero [C].
ABSOLUTE_ZERO = -273.15

#: Highest temperature [C] any of our bodies survives: the LCE. Assumption: acrylate-based LCE
#: networks (RM257 thiol-acrylate, as in seed 001) start losing mass in thermogravimetric analysis
#: at about 300 C (5 % mass loss typically 300-350 C), and they are the first material of the robots
#: to decompose (Kapton HN is rated for continuous use up to 400 C, DuPont datasheet). Not measured
#: for the seed's material; the transition ends near 90 C, so every experiment stays far below.
DECOMPOSITION_TEMPERATURE = 300.0

#: Largest coil current [A]: 5 x 0.2 A, the largest current of seed 001's experiments (kept under
#: 30 s there to avoid overheating). At 1 A the Joule power (I^2 R, ~147 W per strip at 146.6 ohm)
#: is 25 times the 0.2 A power and drives the coil past the decomposition temperature within about a
#: second, which the result check then reports; larger currents are typing errors, not experiments.
MAX_CURRENT = 1.0
CURRENT_RANGE = (
    f"between 0 and {MAX_CURRENT:g} A (5 x the largest current of seed 001, lcefem.models.limits)"
)


def current_param(default: float, source: str):
    """A coil-current field [A] of a parameter dataclass: its bounds [0, :data:`MAX_CURRENT`] in its
    metadata, checked with every bounded field (lcefem.models.parameters.check)."""
    return param(default, "A", source, minimum=0.0, maximum=MAX_CURRENT)


def check_current(name: str, value):
    """A coil current I [A] (a number or an array of strips' currents) in [0, :data:`MAX_CURRENT`]:
    the one check of a current, wherever it enters; raises InputError naming ``name``."""
    if isinstance(value, bool) or not isinstance(
        value, (int, float, np.ndarray, np.number, list, tuple)
    ):
        raise InputError(f"{name} = {value!r}: must be a current [A] {CURRENT_RANGE}")
    arr = np.asarray(value, dtype=float)
    if not (np.all(np.isfinite(arr)) and np.all(arr >= 0.0) and np.all(arr <= MAX_CURRENT)):
        raise InputError(f"{name} = {value} A: must be {CURRENT_RANGE}")
    return value


def range_text(
    low: float,
    high: float,
    unit: str = "",
    *,
    low_open: bool = False,
    high_open: bool = False,
    low_note: str = "",
    high_note: str = "",
) -> str:
    """The words of a bounded range, from the same flags the check uses (so a message never says
    'between a and b' of a range that excludes b): e.g. '> -273.15 C (absolute zero) and < 300 C
    (decomposition)'; a closed range 'between a and b, both included'."""
    u = f" {unit}" if unit else ""
    lo = f"{low:g}{u}" + (f" ({low_note})" if low_note else "")
    hi = f"{high:g}{u}" + (f" ({high_note})" if high_note else "")
    if not (low_open or high_open):
        return f"between {lo} and {hi}, both included"
    return f"{'>' if low_open else '>='} {lo} and {'<' if high_open else '<='} {hi}"


def check_between(
    name: str,
    value,
    low: float,
    high: float,
    unit: str = "",
    *,
    low_open: bool = False,
    high_open: bool = False,
    low_note: str = "",
    high_note: str = "",
) -> float:
    """The one bounded-range check of an input: ``value`` a finite number in the range (each end
    closed unless ``*_open``); raises InputError naming ``name`` with the range in words
    (:func:`range_text`, the same ends: 'between a and b, both included' or '> a and <= b').
    Returns the value as float."""
    text = range_text(
        low,
        high,
        unit,
        low_open=low_open,
        high_open=high_open,
        low_note=low_note,
        high_note=high_note,
    )
    if (
        isinstance(value, bool)
        or not isinstance(value, (int, float, np.number))
        or not math.isfinite(value)
    ):
        raise InputError(f"{name} = {value!r}: must be a number {text}")
    above = value > low if low_open else value >= low
    below = value < high if high_open else value <= high
    if not (above and below):
        raise InputError(f"{name} = {value:g}{' ' + unit if unit else ''}: must be {text}")
    return float(value)


def check_temperature(name: str, value) -> float:
    """A temperature [C] above absolute zero and below decomposition (both ends excluded: at
    :data:`DECOMPOSITION_TEMPERATURE` the LCE decomposes); the one temperature check of inputs."""
    return check_between(
        name,
        value,
        ABSOLUTE_ZERO,
        DECOMPOSITION_TEMPERATURE,
        "C",
        low_open=True,
        high_open=True,
        low_note="absolute zero",
        high_note="decomposition, lcefem.models.limits",
    )


#: The words of :func:`check_temperature`'s range (results are checked against the same range).
TEMPERATURE_RANGE = range_text(
    ABSOLUTE_ZERO,
    DECOMPOSITION_TEMPERATURE,
    "C",
    low_open=True,
    high_open=True,
    low_note="absolute zero",
    high_note="decomposition, lcefem.models.limits",
)


#: Longest simulated heating time [s]: an hour, far beyond the strips' thermal time constant (about
#: 10 s, seed 001) and the ribbon's rolling demonstrations (about a minute).
MAX_DURATION = 3600.0


def check_lambda(name: str, value: float, lambda_N: float) -> float:
    """A strip's relative length lambda [-] (isotropic = 1, as built = lambda_N, seed 001's lambda):
    must lie in [1, lambda_N]; raises InputError naming ``name`` otherwise."""
    if (
        not isinstance(value, (int, float))
        or not math.isfinite(value)
        or not 1.0 <= value <= lambda_N
    ):
        raise InputError(
            f"{name} = {value}: must be between 1 (isotropic) and lambda_N = {lambda_N} (as built)"
        )
    return float(value)


def check_time_step(name: str, dt) -> float:
    """A time step [s] of a library call (``StripSimulation.advance(dt)``, ...): > 0 s and at most
    :data:`MAX_DURATION`, the longest run a command accepts; raises InputError naming ``name``."""
    return check_between(
        name,
        dt,
        0.0,
        MAX_DURATION,
        "s",
        low_open=True,
        high_note="the longest run, lcefem.models.limits",
    )
