"""Compiled (numba) banded Cholesky factorisation and solves (LAPACK lower band storage
ab[i - j, j] = A[i, j]): the symmetric banded systems of the DER Newton loop
(:mod:`lcefem.solvers.der.compiled_newton`) and of the section heat step.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit


# ----------------------------------------------------------------------------------------------
# Banded Cholesky (the Newton loop's and the heat step's symmetric banded systems)
# ----------------------------------------------------------------------------------------------
@njit(cache=True, error_model="numpy")
def band_cholesky(ab):
    """Lower banded Cholesky factor in place (LAPACK dpbtf2 storage ab[i - j, j] = H[i, j]); returns
    info (0: done; k > 0: the leading minor of order k is not positive definite).

    The arithmetic of dpbtf2 in its order (scale the column, rank-one update of the trailing block
    as dsyr does it), on a transposed copy so that each update runs along contiguous memory (1.5x
    faster at 399 x 11; the same factor bit for bit): :func:`band_cholesky_rows`."""
    kd = ab.shape[0] - 1
    n = ab.shape[1]
    L = np.empty((n, kd + 1))  # L[j, i] = ab[i, j]
    for j in range(n):
        for i in range(kd + 1):
            L[j, i] = ab[i, j]
    info = band_cholesky_rows(L)
    for j in range(n):
        for i in range(kd + 1):
            ab[i, j] = L[j, i]
    return info


@njit(cache=True, error_model="numpy")
def band_cholesky_rows(L):
    """:func:`band_cholesky` on the transposed storage L[j, i] = H[j + i, j] (row j: column j of the
    band), in place; returns info. A caller that assembles in this layout skips the two copies
    (the heat step, :func:`heat_solve`)."""
    n = L.shape[0]
    kd = L.shape[1] - 1
    info = 0
    for j in range(n):
        ajj = L[j, 0]
        if not ajj > 0.0:
            info = j + 1
            break
        ajj = math.sqrt(ajj)
        L[j, 0] = ajj
        kn = min(kd, n - 1 - j)
        if kn > 0:
            r = 1.0 / ajj
            for i in range(1, kn + 1):
                L[j, i] *= r
            for c in range(kn):  # symmetric rank-one update of the trailing block (dsyr, lower)
                xc = L[j, c + 1]
                if xc != 0.0:
                    temp = -xc
                    for p in range(c, kn):
                        L[j + 1 + c, p - c] += L[j, p + 1] * temp
    return info


@njit(cache=True, error_model="numpy")
def band_cholesky_solve_rows(L, x):
    """:func:`band_cholesky_solve` with the factor of :func:`band_cholesky_rows` (the same
    operations in the same order)."""
    n = L.shape[0]
    kd = L.shape[1] - 1
    for j in range(n):
        if x[j] != 0.0:
            x[j] /= L[j, 0]
            temp = x[j]
            for i in range(1, min(kd, n - 1 - j) + 1):
                x[j + i] -= temp * L[j, i]
    for j in range(n - 1, -1, -1):
        temp = x[j]
        for i in range(1, min(kd, n - 1 - j) + 1):
            temp -= L[j, i] * x[j + i]
        x[j] = temp / L[j, 0]


@njit(cache=True, error_model="numpy")
def band_cholesky_solve(factor, x):
    """Solves L L^T y = x in place with the factor of :func:`band_cholesky` (LAPACK dpbtrs,
    lower)."""
    kd = factor.shape[0] - 1
    n = factor.shape[1]
    for j in range(n):  # L z = x (dtbsv, lower, no transpose)
        if x[j] != 0.0:
            x[j] /= factor[0, j]
            temp = x[j]
            for i in range(1, min(kd, n - 1 - j) + 1):
                x[j + i] -= temp * factor[i, j]
    for j in range(n - 1, -1, -1):  # L^T y = z (dtbsv, lower, transpose)
        temp = x[j]
        for i in range(1, min(kd, n - 1 - j) + 1):
            temp -= factor[i, j] * x[j + i]
        x[j] = temp / factor[0, j]
