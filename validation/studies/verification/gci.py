"""Observed order, Richardson extrapolation and Grid Convergence Index of three solutions.

Implements the procedure of Celik, Ghia, Roache, Freitas, Coleman and Raad, "Procedure for
estimation and reporting of uncertainty due to discretization in CFD applications", J. Fluids Eng.
130, 078001 (2008), Eqs. (2)-(10), including the fixed-point iteration for the apparent order p when
the two refinement ratios differ. Grid 1 is the finest: h1 < h2 < h3.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

SAFETY_FACTOR = 1.25  # Celik et al. 2008, Eq. (10): Fs = 1.25 for three or more grids


@dataclass(frozen=True)
class GCIResult:
    """Celik et al. 2008 step 3-5 for the finest pair (21) of a triple (all relative errors as
    fractions)."""

    p: float  #: apparent (observed) order [-], Eq. (3a); nan when a difference is zero
    extrapolated: float  #: phi_ext^21 = (r21^p phi1 - phi2)/(r21^p - 1), Eq. (4), unit of phi
    e_a: float  #: approximate relative error |(phi1 - phi2)/phi1|, Eq. (5a)
    e_ext: float  #: extrapolated relative error |(phi_ext - phi1)/phi_ext|, Eq. (5b)
    gci_fine: float  #: GCI_fine^21 = Fs e_a/(r21^p - 1), Eq. (6)
    r21: float  #: refinement ratio h2/h1 [-]
    r32: float  #: refinement ratio h3/h2 [-]
    oscillatory: bool  #: eps32/eps21 < 0 (Celik: "oscillatory convergence")
    iterations: int  #: fixed-point iterations used for p


def observed_order(
    h: tuple[float, float, float],
    phi: tuple[float, float, float],
    *,
    tol: float = 1e-12,
    max_iter: int = 500,
) -> tuple[float, int]:
    """Apparent order p of Celik et al. 2008, Eqs. (3a)-(3c), by fixed-point iteration from q = 0.

    p = |ln|eps32/eps21| + q(p)| / ln r21,  q(p) = ln((r21^p - s)/(r32^p - s)),  s =
    sign(eps32/eps21). Returns (p, iterations); p is nan when eps21 or eps32 is zero or the
    iteration does not settle.
    """
    h1, h2, h3 = h
    r21, r32 = h2 / h1, h3 / h2
    eps21, eps32 = phi[1] - phi[0], phi[2] - phi[1]
    if eps21 == 0.0 or eps32 == 0.0:
        return math.nan, 0
    s = math.copysign(1.0, eps32 / eps21)
    log_ratio = math.log(abs(eps32 / eps21))
    p = abs(log_ratio) / math.log(r21)  # q = 0: exact when r21 == r32
    for it in range(1, max_iter + 1):
        num, den = r21**p - s, r32**p - s
        if num <= 0.0 or den <= 0.0:  # p -> 0 with s = 1: no finite order
            return math.nan, it
        p_new = abs(log_ratio + math.log(num / den)) / math.log(r21)
        if abs(p_new - p) <= tol * max(1.0, p_new):
            return p_new, it
        p = p_new
    return math.nan, max_iter


def gci(
    h: tuple[float, float, float],
    phi: tuple[float, float, float],
    safety_factor: float = SAFETY_FACTOR,
) -> GCIResult:
    """GCI of the finest solution from three (h_i [any length unit], phi_i) with h1 < h2 < h3."""
    h1, h2, h3 = h
    if not 0.0 < h1 < h2 < h3:
        raise ValueError(f"mesh sizes must satisfy 0 < h1 < h2 < h3, got {h}")
    p, iterations = observed_order(h, phi)
    r21, r32 = h2 / h1, h3 / h2
    eps21, eps32 = phi[1] - phi[0], phi[2] - phi[1]
    e_a = abs(eps21 / phi[0]) if phi[0] != 0.0 else math.inf
    if math.isnan(p):
        # no order: a mesh-independent value (both differences zero) has zero error
        same = eps21 == 0.0 and eps32 == 0.0
        z = 0.0 if same else math.nan
        return GCIResult(p, phi[0] if same else math.nan, e_a, z, z, r21, r32, False, iterations)
    rp = r21**p
    ext = (rp * phi[0] - phi[1]) / (rp - 1.0)
    e_ext = abs((ext - phi[0]) / ext) if ext != 0.0 else math.inf
    return GCIResult(
        p,
        ext,
        e_a,
        e_ext,
        safety_factor * e_a / (rp - 1.0),
        r21,
        r32,
        eps32 / eps21 < 0.0,
        iterations,
    )
