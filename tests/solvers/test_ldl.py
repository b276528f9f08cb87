"""The reused-pattern LDL^T (solvers/bar_hinge/ldl.py): solves and inertia against dense algebra."""

import numpy as np
import pytest
import scipy.sparse as sp

from lcefem.solvers.bar_hinge.ldl import SymbolicLDL
from lcefem.solvers.bar_hinge.newton import factorize


def _symmetric(n, density, seed, shift):
    """A sparse symmetric matrix plus a diagonal in [shift, shift + 2] (shift < 0: indefinite)."""
    rng = np.random.default_rng(seed)
    a = sp.random(n, n, density=density, random_state=rng, format="coo")
    a = (a + a.T).tocsc()
    d = shift + 2.0 * rng.random(n)
    return (a + sp.diags(d)).tocsc()


@pytest.mark.parametrize("shift", [6.0, 0.5, -1.0])
def test_ldl_solve_and_inertia_match_dense(shift):
    k = _symmetric(80, 0.05, 3, shift)
    k.sort_indices()
    symbolic = SymbolicLDL(k.indices, k.indptr, k.shape[0])
    eig = np.linalg.eigvalsh(k.toarray())
    factors, negative, zero = factorize(k, ldl=symbolic)
    assert (negative, zero) == (int(np.sum(eig < 0)), 0)  # Sylvester's law of inertia
    rhs = np.linspace(-1.0, 2.0, k.shape[0])
    x = factors.solve(rhs)
    assert np.linalg.norm(k @ x - rhs) <= 1e-10 * np.linalg.norm(rhs) * np.max(np.abs(1 / eig))
    both = factors.solve(np.column_stack([rhs, 2.0 * rhs]))  # several right-hand sides at once
    assert np.array_equal(both[:, 0], x) and np.allclose(both[:, 1], 2.0 * x, rtol=1e-14, atol=0)
    # A shift mu I on the diagonal makes it positive definite.
    mu = 1.0 - min(eig.min(), 0.0)
    shifted, negative, _ = factorize(k, shift=mu, ldl=symbolic)
    assert negative == 0
    assert np.allclose(k @ shifted.solve(rhs) + mu * shifted.solve(rhs), rhs, atol=1e-10)


def test_ldl_zero_pivot_falls_back_to_pivoting_lu():
    # [[0, 1], [1, 0]]: no LDL^T without pivoting; SuperLU pivots off the diagonal (inertia
    # unknown).
    k = sp.csc_matrix(np.array([[0.0, 1.0], [1.0, 0.0]]))
    symbolic = SymbolicLDL(k.indices, k.indptr, 2)
    assert symbolic.factorize(k.data) is None
    factors, negative, zero = factorize(k, ldl=symbolic)
    assert np.allclose(factors.solve(np.array([1.0, 2.0])), [2.0, 1.0])
    assert (negative, zero) == (-1, -1)
