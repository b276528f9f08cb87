"""Liquid-crystal elastomer: nematic order, spontaneous stretch and the spontaneous-strain tensor.

The as-built (nematic, room-temperature) strip is the reference configuration the meshes
represent. Heating lowers the nematic order parameter Q(T); the spontaneous stretch along the
director, measured from the isotropic length as the paper's lambda (seed 001, "Actuation of the LCE
strips"), follows Warner & Terentjev (Liquid Crystal Elastomers, 2007, Ch. 6):

    lambda_s(T) = ((1 + 2 Q) / (1 - Q))^(1/3),
    Q(T)        = Q_0 / (1 + exp((T - T_NI) / w)),

with Q_0 chosen so that lambda_s(T_ref) = lambda_N exactly. Relative to the reference configuration
the spontaneous deformation is isochoric,

    F_s(T) = a n (x) n + a^(-1/2) (I - n (x) n),   a = lambda_s(T) / lambda_s(T_ref),

so F_s(T_ref) = I and det F_s = 1. Every function accepts floats, numpy arrays or UFL expressions.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import ufl

from lcefem.models import _math
from lcefem.models.empirical import EQ1_LAMBDA_N
from lcefem.models.errors import InputError
from lcefem.models.parameters import param

CALIBRATED = ("calibrated against seed 001 (Eq. 1 at 0.04-0.09 A, transients at 0.1 and 0.2 A) by "
              "validation/calibration/calibrate_thermal.py; see validation/data/thermal_calibration.json")


@dataclass(frozen=True)
class NematicTransition:
    """Parameters of the nematic-isotropic transition of the RM257/EDDET/PETMP LCE (seed 001)."""

    T_NI: float = param(68.92, "C", "midpoint of Q(T); seed 001 gives 'T_NI (~70 C)'; " + CALIBRATED)
    width: float = param(6.188, "K", CALIBRATED, positive=True)
    lambda_N: float = param(EQ1_LAMBDA_N, "-", "nematic spontaneous stretch at T_ref = 1 + gamma_1 of Eq. 1 "
                            "(seed 001, Eq. 1, P -> 0); the 9 free strips measured 130.22/80 = 1.63 "
                            "+- 0.10 under an 8.2 g clip (seed 001, Fig. 2B text)", minimum=1.0)
    T_ref: float = param(25.0, "C", "as-built room temperature (seed 001: experiments at about 25 C)")


def order_parameter_from_stretch(stretch):
    """Nematic order parameter Q [-] whose Warner-Terentjev spontaneous stretch is ``stretch`` [-]."""
    cube = stretch ** 3
    return (cube - 1.0) / (cube + 2.0)


def order_parameter(T, transition: NematicTransition):
    """Nematic order parameter Q(T) [-] at temperature T [C] (sigmoid in T, see module docstring)."""
    p = transition
    q_ref = order_parameter_from_stretch(p.lambda_N)
    q0 = q_ref * (1.0 + _math.exp((p.T_ref - p.T_NI) / p.width))
    return q0 / (1.0 + _math.exp((T - p.T_NI) / p.width))


def spontaneous_stretch(T, transition: NematicTransition):
    """Spontaneous stretch lambda_s(T) [-] along the director, relative to the isotropic length.

    lambda_s = ((1 + 2Q)/(1 - Q))^(1/3) (Warner & Terentjev 2007); lambda_s(T_ref) = lambda_N and
    lambda_s -> 1 in the isotropic phase.
    """
    q = order_parameter(T, transition)
    return ((1.0 + 2.0 * q) / (1.0 - q)) ** (1.0 / 3.0)


def contraction_ratio(T, transition: NematicTransition):
    """a(T) = lambda_s(T) / lambda_N [-]: stretch of the director fibres relative to the as-built state."""
    return spontaneous_stretch(T, transition) / transition.lambda_N


def twisted_director(X, twist_rate):
    """Director [-] of a strip stretched along x and then twisted about the x axis at ``twist_rate``
    [rad/mm] (seed 000): the tangent of the helix that the material line through the reference point
    X (mm, on the helicoid) became, n = (1, -tau X2, tau X1) / sqrt(1 + tau^2 (X1^2 + X2^2)).
    Accepts UFL or numpy coordinates (X[0], X[1], X[2])."""
    t1, t2 = -twist_rate * X[2], twist_rate * X[1]
    if isinstance(X, ufl.core.expr.Expr):
        norm = ufl.sqrt(1.0 + t1 ** 2 + t2 ** 2)
        return ufl.as_vector([1.0 / norm, t1 / norm, t2 / norm])
    norm = np.sqrt(1.0 + t1 ** 2 + t2 ** 2)
    return (1.0 / norm, t1 / norm, t2 / norm)


def isochoric_uniaxial(a, director):
    """U(a) = a n(x)n + a^(-1/2) (I - n(x)n) (UFL 3x3): stretch a along the unit director n, det U = 1."""
    nn = ufl.outer(director, director)
    return a * nn + a ** (-0.5) * (ufl.Identity(3) - nn)


def spontaneous_deformation(T, director, transition: NematicTransition):
    """F_s(T) = a n(x)n + a^(-1/2) (I - n(x)n) with a = lambda_s(T)/lambda_N (UFL 3x3); F_s(T_ref) = I.

    Args:
        T: temperature [C], a UFL expression (e.g. a dolfinx Function).
        director: unit director n(X) [-], a UFL vector (Constant, Function or expression).
    """
    return isochoric_uniaxial(contraction_ratio(T, transition), director)


def inverse_spontaneous_deformation(T, director, transition: NematicTransition):
    """F_s^-1 = U(1/a) in closed form (no UFL inverse), a = lambda_s(T)/lambda_N."""
    return isochoric_uniaxial(1.0 / contraction_ratio(T, transition), director)


def temperature_for_stretch(stretch, transition: NematicTransition):
    """The temperature T [C] at which the spontaneous stretch lambda_s(T) equals ``stretch`` [-]
    (inverse of :func:`spontaneous_stretch`: Q = (l^3 - 1)/(l^3 + 2), T = T_NI + w ln(q0/Q - 1)).
    Defined for 1 < stretch < lambda_s(-inf); stretch = lambda_N gives T_ref. numpy or float."""
    p = transition
    q_ref = order_parameter_from_stretch(p.lambda_N)
    q0 = q_ref * (1.0 + _math.exp((p.T_ref - p.T_NI) / p.width))
    s = np.asarray(stretch, dtype=float)
    q = order_parameter_from_stretch(s)
    # the library's own check (the strip's prescribed stretch and any caller): outside (1, lambda_s(-inf))
    # no temperature gives the stretch, and the logarithm would return NaN or +-inf
    bad = ~(np.isfinite(s) & (q > 0.0) & (q < q0))
    if np.any(bad):
        top = ((1.0 + 2.0 * q0) / (1.0 - q0)) ** (1.0 / 3.0) if q0 < 1.0 else _math.inf
        raise InputError(f"stretch = {s[bad].flat[0]:g}: must be > 1 (isotropic) and < {top:.6g} (the "
                         "spontaneous stretch at T -> -inf): no temperature gives it")
    return p.T_NI + p.width * np.log(q0 / q - 1.0)
