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

A measured curve instead of the sigmoid (:class:`MeasuredContraction`): a table of the free stretch
L(T_i) [-] of a lab's LCE along its director at temperatures T_i [C], interpolated piecewise
linearly (constant outside the table). It is normalised to the sigmoid law's two quantities,

    a(T)        = L(T) / L(T_ref)         (contraction ratio from the as-built state, a(T_ref) = 1),
    lambda_s(T) = L(T) / L_min            (spontaneous stretch from the isotropic length),
    lambda_N    = L(T_ref) / L_min,

with the table's smallest stretch L_min (its most contracted row) taken as the isotropic length: for
a curve that falls to a plateau it is the hot end; a measured curve that rises again above its
transition (thermal expansion of the isotropic network, e.g. the LTNI ink, +6 % from 70 to 150 C)
keeps lambda_s >= 1. A MeasuredContraction
passes wherever a :class:`NematicTransition` does: :func:`spontaneous_stretch`,
:func:`contraction_ratio`, :func:`order_parameter` (Q of lambda_s by the Warner-Terentjev relation),
:func:`spontaneous_deformation` and :func:`temperature_for_stretch` dispatch on it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import ufl

from lcefem.models import _math
from lcefem.models.empirical import EQ1_LAMBDA_N
from lcefem.models.errors import InputError
from lcefem.models.parameters import param

CALIBRATED = (
    "calibrated against seed 001 (Eq. 1 at 0.04-0.09 A, transients at 0.1 and 0.2 A) by "
    "benchmarks/calibration/calibrate_thermal.py; see validation/data/thermal_calibration.json"
)


@dataclass(frozen=True)
class NematicTransition:
    """Parameters of the nematic-isotropic transition of the RM257/EDDET/PETMP LCE (seed 001)."""

    T_NI: float = param(
        68.92, "C", "midpoint of Q(T); seed 001 gives 'T_NI (~70 C)'; " + CALIBRATED
    )
    width: float = param(6.188, "K", CALIBRATED, positive=True)
    lambda_N: float = param(
        EQ1_LAMBDA_N,
        "-",
        "nematic spontaneous stretch at T_ref = 1 + gamma_1 of Eq. 1 "
        "(seed 001, Eq. 1, P -> 0); the 9 free strips measured 130.22/80 = 1.63 "
        "+- 0.10 under an 8.2 g clip (seed 001, Fig. 2B text)",
        minimum=1.0,
    )
    T_ref: float = param(
        25.0, "C", "as-built room temperature (seed 001: experiments at about 25 C)"
    )


@dataclass(frozen=True)
class MeasuredContraction:
    """A measured free-stretch curve L(T) [-] of an LCE along its director against temperature [C],
    evaluated piecewise linearly between the rows and constant outside them (the first row's value
    below the table, the last row's above it: extrapolating a measured curve would invent data).

    Normalisation (module docstring): a(T) = L(T)/L(T_ref), lambda_s(T) = L(T)/L_min with L_min the
    table's smallest stretch (taken as isotropic), lambda_N = L(T_ref)/L_min. L may be measured from
    any length (e.g. L(T)/L(25 C), or strain + 1): only its ratios enter.

    Build it with :meth:`from_rows` (strain or stretch, either temperature order); a CSV file is
    read by ``lcefem.solvers.contraction_curve.read_contraction_csv``. Rows: >= 2, temperatures
    strictly increasing, stretch > 0 and finite. The UFL form is ``ufl.conditional`` branches, one
    per segment, nested by bisection (log2 n deep): fine for a measured table of tens to a few
    hundred rows; its cost grows with the rows in form compilation, not in the solve.
    """

    temperatures: tuple[float, ...]  # T_i [C], strictly increasing
    values: tuple[float, ...]  # L(T_i) [-], free stretch from any reference length
    source: str = ""  # where the curve comes from (paper, file, lab notebook)
    T_ref: float = (
        25.0  # as-built temperature [C] (NematicTransition.T_ref: seed 001 at about 25 C)
    )

    def __post_init__(self):
        T = np.asarray(self.temperatures, dtype=float)
        L = np.asarray(self.values, dtype=float)
        if T.ndim != 1 or L.shape != T.shape:
            raise InputError(
                f"contraction curve: {T.size} temperatures and {L.size} values; allowed one "
                "value per temperature"
            )
        if T.size < 2:
            raise InputError(f"contraction curve: {T.size} row; allowed at least 2 rows")
        if not (np.all(np.isfinite(T)) and np.all(np.isfinite(L)) and math.isfinite(self.T_ref)):
            raise InputError("contraction curve: a value is not finite; allowed finite numbers")
        if np.any(np.diff(T) <= 0):
            k = int(np.nonzero(np.diff(T) <= 0)[0][0])
            raise InputError(
                f"contraction curve: temperature {T[k + 1]:g} C after {T[k]:g} C; allowed "
                "strictly increasing temperatures"
            )
        if np.any(L <= 0):
            raise InputError(f"contraction curve: stretch {L[L <= 0][0]:g}; allowed stretch > 0")
        object.__setattr__(self, "temperatures", tuple(float(t) for t in T))
        object.__setattr__(self, "values", tuple(float(v) for v in L))

    @classmethod
    def from_rows(
        cls, temperatures_C, values, kind: str = "stretch", source: str = "", T_ref: float = 25.0
    ) -> "MeasuredContraction":
        """The curve from rows of temperature [C] and ``kind`` = "stretch" L [-] or "strain"
        e = L - 1 [-] (a contraction is negative strain); temperatures increasing or decreasing."""
        if kind not in ("stretch", "strain"):
            raise InputError(f"contraction curve: kind = {kind!r}; allowed stretch, strain")
        T = np.asarray(temperatures_C, dtype=float).reshape(-1)
        L = np.asarray(values, dtype=float).reshape(-1) + (1.0 if kind == "strain" else 0.0)
        if T.size >= 2 and T.size == L.size and np.all(np.diff(T) < 0):  # measured on cooling
            T, L = T[::-1], L[::-1]
        return cls(tuple(T), tuple(L), source, T_ref)

    def measured(self, T):
        """L(T) [-], the table interpolated piecewise linearly, constant outside (float, ndarray,
        UFL)."""
        xs, ys = self.temperatures, self.values
        if isinstance(T, ufl.core.expr.Expr):

            def segments(lo, hi):
                """L(T) on [x_lo, x_hi] [-]: the segments bisected, so the conditionals nest log2(n)
                deep (a flat chain of a few hundred rows exceeds Python's recursion limit in
                UFL)."""
                if hi - lo == 1:
                    slope = (ys[hi] - ys[lo]) / (xs[hi] - xs[lo])
                    return ys[lo] + slope * (T - xs[lo])
                mid = (lo + hi) // 2  # T = x_mid takes the upper half, whose value there is y_mid
                return ufl.conditional(ufl.lt(T, xs[mid]), segments(lo, mid), segments(mid, hi))

            inside = ufl.conditional(ufl.lt(T, xs[-1]), segments(0, len(xs) - 1), ys[-1])
            return ufl.conditional(ufl.lt(T, xs[0]), ys[0], inside)
        return np.interp(T, xs, ys)

    @property
    def reference_stretch(self) -> float:
        """L(T_ref) [-]."""
        return float(np.interp(self.T_ref, self.temperatures, self.values))

    @property
    def isotropic_stretch(self) -> float:
        """L_min [-]: the table's smallest stretch, taken as the isotropic length."""
        return min(self.values)

    @property
    def lambda_N(self) -> float:
        """L(T_ref) / L_min [-]: the as-built spontaneous stretch from the isotropic length."""
        return self.reference_stretch / self.isotropic_stretch

    def stretch(self, T):
        """Spontaneous stretch lambda_s(T) = L(T)/L_min [-] (float, ndarray or UFL)."""
        return self.measured(T) / self.isotropic_stretch

    def contraction(self, T):
        """a(T) = L(T)/L(T_ref) [-] (float, ndarray or UFL); a(T_ref) = 1."""
        return self.measured(T) / self.reference_stretch

    def temperature_for_stretch(self, stretch):
        """The temperature [C] where lambda_s(T) = ``stretch`` [-] (numpy or float), by inverse
        linear interpolation; needs a strictly decreasing curve (else the inverse is not unique)."""
        L = np.asarray(self.values) / self.isotropic_stretch
        if np.any(np.diff(L) >= 0):
            raise InputError(
                "contraction curve: the stretch does not fall strictly with temperature; "
                "a prescribed stretch needs a strictly decreasing curve"
            )
        return np.interp(stretch, L[::-1], np.asarray(self.temperatures)[::-1])

    def rows(self) -> list[tuple[float, float]]:
        """[(T [C], L [-])], the table as stored."""
        return list(zip(self.temperatures, self.values))


def order_parameter_from_stretch(stretch):
    """Nematic order parameter Q [-] whose Warner-Terentjev spontaneous stretch is ``stretch``
    [-]."""
    cube = stretch**3
    return (cube - 1.0) / (cube + 2.0)


def order_parameter(T, transition: NematicTransition | MeasuredContraction):
    """Nematic order parameter Q(T) [-] at temperature T [C] (sigmoid in T, see module docstring; of
    a measured curve, Q of its lambda_s(T))."""
    if isinstance(transition, MeasuredContraction):
        return order_parameter_from_stretch(transition.stretch(T))
    p = transition
    q_ref = order_parameter_from_stretch(p.lambda_N)
    q0 = q_ref * (1.0 + _math.exp((p.T_ref - p.T_NI) / p.width))
    return q0 / (1.0 + _math.exp((T - p.T_NI) / p.width))


def spontaneous_stretch(T, transition: NematicTransition | MeasuredContraction):
    """Spontaneous stretch lambda_s(T) [-] along the director, relative to the isotropic length.

    lambda_s = ((1 + 2Q)/(1 - Q))^(1/3) (Warner & Terentjev 2007); lambda_s(T_ref) = lambda_N and
    lambda_s -> 1 in the isotropic phase. A measured curve gives L(T)/L_min.
    """
    if isinstance(transition, MeasuredContraction):
        return transition.stretch(T)
    q = order_parameter(T, transition)
    return ((1.0 + 2.0 * q) / (1.0 - q)) ** (1.0 / 3.0)


def contraction_ratio(T, transition: NematicTransition | MeasuredContraction):
    """a(T) = lambda_s(T) / lambda_N [-]: stretch of the director fibres relative to the as-built
    state (a measured curve: L(T)/L(T_ref))."""
    if isinstance(transition, MeasuredContraction):
        return transition.contraction(T)
    return spontaneous_stretch(T, transition) / transition.lambda_N


def twisted_director(X, twist_rate):
    """Director [-] of a strip stretched along x and then twisted about the x axis at ``twist_rate``
    [rad/mm] (seed 000): the tangent of the helix that the material line through the reference point
    X (mm, on the helicoid) became, n = (1, -tau X2, tau X1) / sqrt(1 + tau^2 (X1^2 + X2^2)).
    Accepts UFL or numpy coordinates (X[0], X[1], X[2])."""
    t1, t2 = -twist_rate * X[2], twist_rate * X[1]
    if isinstance(X, ufl.core.expr.Expr):
        norm = ufl.sqrt(1.0 + t1**2 + t2**2)
        return ufl.as_vector([1.0 / norm, t1 / norm, t2 / norm])
    norm = np.sqrt(1.0 + t1**2 + t2**2)
    return (1.0 / norm, t1 / norm, t2 / norm)


def isochoric_uniaxial(a, director):
    """U(a) = a n(x)n + a^(-1/2) (I - n(x)n) (UFL 3x3): stretch a along the unit director n, det U =
    1."""
    nn = ufl.outer(director, director)
    return a * nn + a ** (-0.5) * (ufl.Identity(3) - nn)


def spontaneous_deformation(T, director, transition: NematicTransition | MeasuredContraction):
    """F_s(T) = a n(x)n + a^(-1/2) (I - n(x)n) with a = lambda_s(T)/lambda_N (UFL 3x3); F_s(T_ref) =
    I.

    Args:
        T: temperature [C], a UFL expression (e.g. a dolfinx Function).
        director: unit director n(X) [-], a UFL vector (Constant, Function or expression).
    """
    return isochoric_uniaxial(contraction_ratio(T, transition), director)


def inverse_spontaneous_deformation(
    T, director, transition: NematicTransition | MeasuredContraction
):
    """F_s^-1 = U(1/a) in closed form (no UFL inverse), a = lambda_s(T)/lambda_N."""
    return isochoric_uniaxial(1.0 / contraction_ratio(T, transition), director)


def temperature_for_stretch(stretch, transition: NematicTransition | MeasuredContraction):
    """The temperature T [C] at which the spontaneous stretch lambda_s(T) equals ``stretch`` [-]
    (inverse of :func:`spontaneous_stretch`: Q = (l^3 - 1)/(l^3 + 2), T = T_NI + w ln(q0/Q - 1)).
    Defined for 1 < stretch < lambda_s(-inf); stretch = lambda_N gives T_ref. numpy or float. A
    measured curve: :meth:`MeasuredContraction.temperature_for_stretch`."""
    if isinstance(transition, MeasuredContraction):
        return transition.temperature_for_stretch(stretch)
    p = transition
    q_ref = order_parameter_from_stretch(p.lambda_N)
    q0 = q_ref * (1.0 + _math.exp((p.T_ref - p.T_NI) / p.width))
    s = np.asarray(stretch, dtype=float)
    q = order_parameter_from_stretch(s)
    # the library's own check (the strip's prescribed stretch and any caller): outside (1,
    # lambda_s(-inf)) no temperature gives the stretch, and the logarithm would return NaN or +-inf
    bad = ~(np.isfinite(s) & (q > 0.0) & (q < q0))
    if np.any(bad):
        top = ((1.0 + 2.0 * q0) / (1.0 - q0)) ** (1.0 / 3.0) if q0 < 1.0 else _math.inf
        raise InputError(
            f"stretch = {s[bad].flat[0]:g}: must be > 1 (isotropic) and < {top:.6g} (the "
            "spontaneous stretch at T -> -inf): no temperature gives it"
        )
    return p.T_NI + p.width * np.log(q0 / q - 1.0)
