"""Physical limits every input and every result must respect (checked by lcefem.solvers.runtime.checks).

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
#: networks (RM257 thiol-acrylate, as in seed 001) start losing mass in thermogravimetric analysis at
#: about 300 C (5 % mass loss typically 300-350 C), and they are the first material of the robots to
#: decompose (Kapton HN is rated for continuous use up to 400 C, DuPont datasheet). Not measured for
#: the seed's material; the transition ends near 90 C, so every experiment stays far below.
DECOMPOSITION_TEMPERATURE = 300.0

#: Largest coil current [A]: 5 x 0.2 A, the largest current of seed 001's experiments (kept under
#: 30 s there to avoid overheating). At 1 A the Joule power (I^2 R, ~147 W per strip at 146.6 ohm)
#: is 25 times the 0.2 A power and drives the coil past the decomposition temperature within about a
#: second, which the result check then reports; larger currents are typing errors, not experiments.
MAX_CURRENT = 1.0
CURRENT_RANGE = f"between 0 and {MAX_CURRENT:g} A (5 x the largest current of seed 001, lcefem.models.limits)"


def current_param(default: float, source: str):
    """A coil-current field [A] of a parameter dataclass: its bounds [0, :data:`MAX_CURRENT`] in its
    metadata, checked with every bounded field (lcefem.models.parameters.check)."""
    return param(default, "A", source, minimum=0.0, maximum=MAX_CURRENT)


def check_current(name: str, value):
    """A coil current I [A] (a number or an array of strips' currents) in [0, :data:`MAX_CURRENT`]:
    the one check of a current, wherever it enters; raises InputError naming ``name``."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.ndarray, np.number, list, tuple)):
        raise InputError(f"{name} = {value!r}: must be a current [A] {CURRENT_RANGE}")
    arr = np.asarray(value, dtype=float)
    if not (np.all(np.isfinite(arr)) and np.all(arr >= 0.0) and np.all(arr <= MAX_CURRENT)):
        raise InputError(f"{name} = {value} A: must be {CURRENT_RANGE}")
    return value

#: Longest simulated heating time [s]: an hour, far beyond the strips' thermal time constant (about
#: 10 s, seed 001) and the ribbon's rolling demonstrations (about a minute).
MAX_DURATION = 3600.0


def check_lambda(name: str, value: float, lambda_N: float) -> float:
    """A strip's relative length lambda [-] (isotropic = 1, as built = lambda_N, seed 001's lambda):
    must lie in [1, lambda_N]; raises InputError naming ``name`` otherwise."""
    if not isinstance(value, (int, float)) or not math.isfinite(value) or not 1.0 <= value <= lambda_N:
        raise InputError(f"{name} = {value}: must be between 1 (isotropic) and lambda_N = "
                         f"{lambda_N} (as built)")
    return float(value)
