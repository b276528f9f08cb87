"""Closed forms of elastic stability for the fixed-fixed Kapton specimen (seed 001, Fig. 2G): the
Euler load and the inextensible elastica's post-buckling force (Timoshenko & Gere, Theory of Elastic
Stability, 1961). Units: N, mm, MPa."""

from __future__ import annotations

import math

from scipy import special
from scipy.optimize import brentq

from lcefem.models.errors import InputError


def euler_fixed_fixed(bending_stiffness: float, length: float) -> float:
    """Euler load of a fixed-fixed column, P = 4 pi^2 EI/L^2 [N] (EI [N mm^2], L [mm])."""
    return 4.0 * math.pi**2 * bending_stiffness / length**2


def elastica_force_ratio(compression: float) -> float:
    """P/P_cr of the inextensible Euler elastica at end shortening ``compression`` = e/L.

    Fixed-fixed and pinned-pinned columns share e/L = 2 (1 - E(m)/K(m)) and P/P_cr = (2 K(m)/pi)^2,
    m = k^2, k = sin(alpha/2) (Timoshenko & Gere, Theory of Elastic Stability, 1961, Sec. 2.7).
    """
    if not 0.0 <= compression < 1.0:
        raise InputError(f"compression = {compression}: must be in [0, 1)")
    if compression == 0.0:
        return 1.0
    g = lambda mm: 2.0 * (1.0 - special.ellipe(mm) / special.ellipk(mm)) - compression
    m = brentq(g, 1e-12, 1.0 - 1e-15)
    return (2.0 * special.ellipk(m) / math.pi) ** 2


def specimen_closed_forms(
    specimen, youngs_modulus: float, poisson_ratio: float, measured: float
) -> dict[str, float]:
    """Euler loads [N] of a fixed-fixed specimen (``specimen``: length [mm], second_moment [mm^4]):
    beam E I and plate strip E I/(1 - nu^2); and the free length [mm] and modulus [MPa] for which
    4 pi^2 E I/L^2 equals the ``measured`` load [N]."""
    ei = youngs_modulus * specimen.second_moment
    return {
        "Euler, E I (datasheet E) [N]": euler_fixed_fixed(ei, specimen.length),
        "Euler, plate strip E I/(1 - nu^2) [N]": euler_fixed_fixed(
            ei / (1.0 - poisson_ratio**2), specimen.length
        ),
        "free length giving the measured load [mm]": 2.0 * math.pi * math.sqrt(ei / measured),
        "modulus giving the measured load [MPa]": measured
        * specimen.length**2
        / (4.0 * math.pi**2 * specimen.second_moment),
    }
