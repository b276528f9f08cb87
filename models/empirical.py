"""The paper's empirical laws (seed 001): Eq. 1, steady stretch vs electric power, and Eq. 2,
the curvature of a composite beam. Inputs and outputs in lcefem units (mW, mm, 1/mm)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from lcefem.models.bar_hinge_materials import PUBLISHED_LAMBDA_N
from lcefem.models.parameters import param


@dataclass(frozen=True)
class Eq1:
    """lambda = gamma_1 / (1 + exp(gamma_2 (P - gamma_3))) + 1 (seed 001, Eq. 1; still air ~25
    C)."""

    gamma_1: float = param(0.426, "-", "seed 001, Eq. 1 (fitted over 0.04-0.09 A)")
    gamma_2: float = param(11.97e-3, "1/mW", "seed 001, Eq. 1: 11.97 1/W")
    gamma_3: float = param(635.0, "mW", "seed 001, Eq. 1: 0.635 W")


#: Nematic relative length lambda_N [-] = 1 + gamma_1, Eq. 1's limit as P -> 0 (seed 001, Eq. 1):
#: the strip model's as-built spontaneous stretch (:class:`lcefem.models.lce.NematicTransition`).
EQ1_LAMBDA_N: float = 1.0 + Eq1().gamma_1


def eq1_stretch(power, law: Eq1 = Eq1()):
    """Steady relative length lambda [-] (current over isotropic length) at electric power P
    [mW]."""
    power = np.asarray(power, dtype=float)
    return law.gamma_1 / (1.0 + np.exp(law.gamma_2 * (power - law.gamma_3))) + 1.0


def eq1_power(stretch, law: Eq1 = Eq1()):
    """Inverse of Eq. 1: the electric power P [mW] that holds the strip at ``stretch`` in (1, 1 +
    gamma_1)."""
    stretch = np.asarray(stretch, dtype=float)
    return law.gamma_3 + np.log(law.gamma_1 / (stretch - 1.0) - 1.0) / law.gamma_2


@dataclass(frozen=True)
class Eq2:
    """kappa = 16 eta (lT - lB) / ((lT + lB)(t_a + l_p sqrt(4 - (lT + lB)^2 / lN^2))) (seed 001, Eq.
    2)."""

    eta: float = param(0.57, "-", "seed 001, Eq. 2: linear scaling factor fitted to experiments")
    ribbon_length: float = param(
        30.0,
        "mm",
        "l_p, straight (pre-buckled) ribbon segment length "
        "(published reduced-order model: Lx = 30 mm)",
        positive=True,
    )
    strip_thickness: float = param(
        2.0, "mm", "t_a, LCE strip thickness (seed 001: 2 mm deep mould)", positive=True
    )
    lambda_N: float = param(
        PUBLISHED_LAMBDA_N,
        "-",
        "nematic relative length (published reduced-order model: 1/0.7143)",
        minimum=1.0,
    )


def eq2_curvature(lambda_top, lambda_bottom, law: Eq2 = Eq2()):
    """Curvature kappa [1/mm] of a composite beam with top/bottom relative lengths (seed 001, Eq.
    2).

    Positive when the top strip is longer than the bottom one (the beam bends towards the bottom).
    """
    lt = np.asarray(lambda_top, dtype=float)
    lb = np.asarray(lambda_bottom, dtype=float)
    s = lt + lb
    height = law.strip_thickness + law.ribbon_length * np.sqrt(4.0 - s**2 / law.lambda_N**2)
    return 16.0 * law.eta * (lt - lb) / (s * height)
