"""The aluminium ball of seed 001, Fig. 5B (object manipulation): a rigid sphere rolling on the
covered surface. Physics only: its parameters and the rolling sphere's inertia.

Units: mm, t, s, N.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from lcefem.models import units
from lcefem.models.parameters import param


@dataclass(frozen=True)
class Ball:
    """A solid sphere (moment of inertia 2 m r^2 / 5)."""

    mass: float = param(
        10.0 * units.GRAM,
        "t",
        "seed 001, Results (Fig. 5B): 'an aluminum ball (10 g)'",
        positive=True,
    )
    density: float = param(
        2.70 * units.G_PER_CM3, "t/mm^3", "aluminium, 2.70 g/cm^3 (handbook value)", positive=True
    )
    friction: float = param(
        0.3,
        "-",
        "assumed: Coulomb friction of aluminium on Kapton film (no datum "
        "in the seed); only checked against the rolling demand",
        positive=True,
    )
    rolling_resistance: float = param(
        0.01,
        "-",
        "assumed: rolling-resistance coefficient of a metal ball "
        "on a thin polymer film over a compliant grid (no datum in the seed); "
        "it sets how fast the ball settles, not where",
        minimum=0.0,
    )
    creep_speed: float = param(
        1.0,
        "mm/s",
        "assumed: below this speed the rolling resistance is "
        "proportional to the speed (regularised Coulomb law)",
        positive=True,
    )

    @property
    def radius(self) -> float:
        """r = (3 m / (4 pi rho))^(1/3) [mm]: 9.60 mm for 10 g of aluminium."""
        return (3.0 * self.mass / (4.0 * math.pi * self.density)) ** (1.0 / 3.0)

    @property
    def rolling_inertia_factor(self) -> float:
        """(m + I/r^2)/m = 7/5 for a solid sphere rolling without slipping."""
        return 1.4
