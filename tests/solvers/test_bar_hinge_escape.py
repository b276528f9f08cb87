"""Newton's escape test and stall damping (solvers/bar_hinge/newton.py): the inertia of K + tau I
decides whether a negative curvature is numerically zero; the Levenberg-like damping bookkeeping."""

import importlib
import types

import numpy as np
import pytest
import scipy.sparse as sp

from lcefem.solvers.bar_hinge.ldl import SymbolicLDL

#: The Newton module (the package re-exports its function ``newton`` under the same name).
newton_module = importlib.import_module("lcefem.solvers.bar_hinge.newton")


def _rotated(eigenvalues, seed=1):
    """Q diag(eigenvalues) Q^T (dense pattern, as a CSC matrix) with a random orthogonal Q."""
    rng = np.random.default_rng(seed)
    q, _ = np.linalg.qr(rng.standard_normal((len(eigenvalues), len(eigenvalues))))
    k = sp.csc_matrix(q @ np.diag(eigenvalues) @ q.T)
    k.sort_indices()
    return k


def _reduced(k):
    symbolic = SymbolicLDL(k.indices, k.indptr, k.shape[0])
    return types.SimpleNamespace(diagonal=lambda m: m.diagonal(), ldl_of=lambda m: symbolic)


@pytest.mark.parametrize(
    "lowest, negligible", [(-1e-13, True), (-1e-9, True), (-1e-5, False), (-1.0, False)]
)
def test_negligible_negative_curvature_follows_the_lowest_eigenvalue(lowest, negligible):
    # Spectrum from `lowest` to 1000 N/mm: the largest diagonal entry is below 1000, so tau =
    # 1e-10 of it is below 1e-7: -1e-9 and -1e-13 are above -tau (numerically zero), -1e-5 below.
    k = _rotated(np.concatenate([[lowest], np.linspace(1e-3, 1000.0, 29)]))
    scale = float(np.max(np.abs(k.diagonal())))
    assert (abs(lowest) < newton_module.NEGLIGIBLE_CURVATURE * scale) == negligible  # the premise
    assert newton_module._negligible_negative_curvature(k, _reduced(k)) == negligible


def test_stall_damping_bookkeeping():
    stall = newton_module._stall
    assert stall(1.0, 7, 3, 0.4, 0.9, 1e-5) == (0.4, 0, 0)  # residual halved: undamped again
    assert stall(1.0, 7, 3, 0.8, 0.9, 1e-5) == (1.0, 8, 2)  # damped step helped: less damping
    assert stall(1.0, 7, 3, 0.95, 0.9, 1e-5) == (1.0, 8, 4)  # it did not: more damping
    assert stall(1.0, 7, 6, 0.95, 0.9, 1e-2) == (1.0, 8, 6)  # at most 1e-2 (level 6)
    assert stall(1.0, 2, 0, 0.8, 0.9, 0.0) == (1.0, 3, 0)  # undamped step: only the count moves
