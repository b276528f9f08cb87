"""Output space mapping: a design of a cheap (coarse) model corrected by an expensive (fine) one.

Bandler et al.'s output space mapping (J. W. Bandler, Q. S. Cheng, S. A. Dakroury, A. S. Mohamed,
M. H. Bakr, K. Madsen, J. Sondergaard, "Space mapping: the state of the art", IEEE Trans. Microwave
Theory Tech. 52 (2004) 337-361, section on output space mapping): the coarse model's residual
r_C(d) from the target is shifted by the fine model's gap at the current design d_k,

    D_k = r_F(d_k) - r_C(d_k),          d_{k+1} = argmin_d |r_C(d) + D_k|,

so that the corrected coarse model r_C + D_k equals the fine one at d_k (zeroth-order
consistency); the target the coarse model is designed for is T - D_k. No parameter of either
model changes. When the fine model is the coarse one plus a constant, D_k is that constant and one
correction gives the fine model's optimum (tests/validation/test_space_mapping.py).

Here r_F is the 3D FE surface's rigid residual from the target at the Kapton panel centres and r_C
the bar-and-hinge's (:mod:`lcefem.validation.studies.design.gridshell_reach_study`); the loop is
generic: it takes the three steps as callables. Units: those of the residuals (mm here).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

import numpy as np

from lcefem.models.errors import InputError


@dataclasses.dataclass
class SpaceMapStep:
    """One fine evaluation: the design, its fine RMS from the target, the coarse RMS from the
    corrected target the design was made for (``None`` for the start), the gap it gives."""

    design: np.ndarray
    fine_rms: float
    coarse_rms: float | None
    gap: np.ndarray


def rms(r) -> float:
    """Root mean square of the residual vector r (its units)."""
    r = np.asarray(r, dtype=float)
    return float(np.sqrt(np.mean(r * r)))


def output_space_map(
    d0,
    fine: Callable[[np.ndarray], np.ndarray],
    coarse: Callable[[np.ndarray], np.ndarray],
    redesign: Callable[[np.ndarray, np.ndarray], tuple[np.ndarray, float]],
    max_fine: int = 3,
    on_step: Callable[[int, SpaceMapStep], None] | None = None,
) -> tuple[list[SpaceMapStep], int]:
    """The output space-mapping loop from the coarse design ``d0``.

    Args:
        fine: d -> r_F(d), the fine model's residual from the target (k,).
        coarse: d -> r_C(d), the coarse model's residual at the same points (k,).
        redesign: (d_start, D) -> (d, coarse RMS of r_C(d) + D): the coarse design for the
            corrected target, warm-started at d_start.
        max_fine: most fine evaluations (>= 1).
        on_step: called after each fine evaluation (k, step), e.g. to store it.

    Returns the steps and the index of the best one (the lowest fine RMS). Stops when the fine RMS
    stops falling (not lower than the previous one) or after ``max_fine`` fine evaluations.
    """
    if max_fine < 1:
        raise InputError(f"max_fine = {max_fine}: allowed an integer >= 1")
    steps: list[SpaceMapStep] = []
    d, coarse_rms = np.asarray(d0, dtype=float), None
    for k in range(max_fine):
        r_f = np.asarray(fine(d), dtype=float)
        gap = r_f - np.asarray(coarse(d), dtype=float)
        steps.append(SpaceMapStep(d, rms(r_f), coarse_rms, gap))
        if on_step is not None:
            on_step(k, steps[-1])
        if k > 0 and steps[-1].fine_rms >= steps[-2].fine_rms:
            break
        if k + 1 < max_fine:
            d, coarse_rms = redesign(d, gap)
            d = np.asarray(d, dtype=float)
    best = int(np.argmin([s.fine_rms for s in steps]))
    return steps, best
