"""A smooth law of one variable, tabulated: piecewise cubic on a uniform grid, the law outside it.

On the interval [x_k, x_k + h] the cubic through the law's values at x_(k-1), x_k, x_(k+1), x_(k+2)
(Lagrange, monomial coefficients in u = (x - x_k)/h stored per interval), whose error is at most
(9/16) h^4 max|f''''| / 4! (about 1e-10 for the contraction ratio a(T) at h = 0.05 K; measured by
:meth:`TabulatedLaw.max_error`, tested in ``tests/solvers/test_der_tabulated.py``).

Why: the rolling ribbon's natural shape evaluates the contraction ratio a(T) (an exp and a cube
root, ``models.lce.contraction_ratio``) at every section quadrature point of every edge each time
step, ~19,000 points at 100 nodes: 0.6 ms per step in numpy, a table lookup a fraction of it (issue
17).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np
from numba import njit

# u^p at the nodes u = -1, 0, 1, 2 of the interval's cubic; its inverse maps values to coefficients
_NODES = np.array([-1.0, 0.0, 1.0, 2.0])
_TO_COEFFICIENTS = np.linalg.inv(_NODES[:, None] ** np.arange(4)[None, :])


@njit(cache=True, error_model="numpy")
def piecewise_cubic(x, lo, inv_h, coefficients, out):
    """out[i] = the interval cubic at x[i] (Horner); nan where x[i] is outside [lo, lo + n h) or not
    finite. Returns the number of such points."""
    n = coefficients.shape[0]
    outside = 0
    for i in range(len(x)):
        s = (x[i] - lo) * inv_h
        if not (s >= 0.0 and s < n):
            out[i] = np.nan
            outside += 1
            continue
        k = int(s)
        u = s - k
        out[i] = coefficients[k, 0] + u * (
            coefficients[k, 1] + u * (coefficients[k, 2] + u * coefficients[k, 3])
        )
    return outside


@dataclass(frozen=True)
class TabulatedLaw:
    """``law`` (a numpy ufunc-like callable) tabulated on [lo, hi) with the spacing ``spacing``
    (units of its argument); callable on arrays of any shape, exact (the law itself) outside."""

    law: Callable
    lo: float
    spacing: float
    coefficients: np.ndarray  # (n, 4) per interval, in u = (x - x_k)/h

    @classmethod
    def of(cls, law: Callable, lo: float, hi: float, spacing: float) -> "TabulatedLaw":
        n = int(math.ceil((hi - lo) / spacing))
        nodes = lo + spacing * np.arange(-1, n + 2)
        values = np.asarray(law(nodes), float)
        stencil = np.stack([values[k : k + n] for k in range(4)], axis=1)  # f at x_(k-1) .. x_(k+2)
        return cls(
            law, float(lo), float(spacing), np.ascontiguousarray(stencil @ _TO_COEFFICIENTS.T)
        )

    @property
    def hi(self) -> float:
        return self.lo + self.spacing * len(self.coefficients)

    def __call__(self, x) -> np.ndarray:
        x = np.asarray(x, float)
        flat = np.ascontiguousarray(x).reshape(-1)
        out = np.empty_like(flat)
        if piecewise_cubic(flat, self.lo, 1.0 / self.spacing, self.coefficients, out):
            outside = np.isnan(out)
            out[outside] = self.law(flat[outside])
        return out.reshape(x.shape)

    def max_error(self, samples: int = 200_001) -> float:
        """Largest |table - law| over ``samples`` points spread evenly over the table (with the
        interval midpoints, where a cubic's error peaks, among them)."""
        x = np.linspace(self.lo, self.hi, samples, endpoint=False)
        x = np.concatenate([x, self.lo + self.spacing * (np.arange(len(self.coefficients)) + 0.5)])
        return float(np.max(np.abs(self(x) - self.law(x))))
