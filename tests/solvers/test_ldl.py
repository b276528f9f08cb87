"""The reused-pattern LDL^T (solvers/bar_hinge/ldl.py): solves and inertia against dense algebra."""

import numpy as np
import pytest
import scipy.sparse as sp

from lcefem.solvers.bar_hinge.ldl import SymbolicLDL, inserted_before
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


def test_inserted_before_counts_the_new_keys_before_each_stored_key():
    """The count by bincount equals a search of every stored key among the new ones, new keys
    before the first, between and after the last stored key included, and none."""
    rng = np.random.default_rng(3)
    keys = np.unique(rng.integers(0, 10**6, 5000))
    spare = np.setdiff1d(np.arange(-5, 10**6 + 5), keys)
    for count in (0, 1, 40, 3000):
        new = np.sort(rng.choice(spare, count, replace=False))
        at = np.searchsorted(keys, new)
        assert np.array_equal(inserted_before(at, keys.size), np.searchsorted(new, keys))
    edges = np.array([-3, 10**6 + 3])  # before the first and after the last stored key
    shift = inserted_before(np.searchsorted(keys, edges), keys.size)
    assert shift[0] == 1 and shift[-1] == 1


def test_ldl_zero_pivot_falls_back_to_pivoting_lu():
    # [[0, 1], [1, 0]]: no LDL^T without pivoting; SuperLU pivots off the diagonal (inertia
    # unknown).
    k = sp.csc_matrix(np.array([[0.0, 1.0], [1.0, 0.0]]))
    symbolic = SymbolicLDL(k.indices, k.indptr, 2)
    assert symbolic.factorize(k.data) is None
    factors, negative, zero = factorize(k, ldl=symbolic)
    assert np.allclose(factors.solve(np.array([1.0, 2.0])), [2.0, 1.0])
    assert (negative, zero) == (-1, -1)


def test_reduced_tangent_with_closed_contacts_is_the_models_hessian():
    """The reduced tangent keeps only the closed contacts in its pattern: on the published
    gridshell, flat (every contact open) and displaced (some pressed shut), it equals the model's
    Hessian on the free DOFs, drops only zeros, and its LDL^T (the contact-free ordering, the
    closed contacts merged in) solves it, shifted by mu I."""
    from lcefem.meshes.gridshell import build_gridshell_bar_hinge
    from lcefem.solvers.bar_hinge import BarHingeModel, ReducedHessian

    model = BarHingeModel.from_materials(build_gridshell_bar_hinge())
    free = np.arange(12, model.ndof)  # four nodes held
    reduced = ReducedHessian.of(model, free)
    rng = np.random.default_rng(5)
    closed_counts = []
    for scale in (0.0, 0.05, 0.2):  # [mm]
        x = model.reference.reshape(-1).copy()
        x[free] += scale * rng.standard_normal(free.size)
        _, grad, coo = model.evaluate(x)
        closed = model.closed_contacts(coo)
        closed_counts.append(closed.size)
        k = reduced.matrix(coo)
        full = model.hessian(x)[free][:, free].tocsc()
        assert abs(k - full).max() <= 1e-12 * abs(full).max()
        pattern = k.copy()
        pattern.data[:] = 1.0
        assert k.nnz < full.nnz  # the open contacts' entries are left out ...
        assert (full - full.multiply(pattern)).count_nonzero() == 0  # ... and only they: zeros
        assert np.array_equal(reduced.diagonal(k), k.diagonal())
        # shifted: the flat structure held at four nodes has mechanisms (zero pivots)
        mu = 1e-3 * abs(full).max()
        factors, negative, _ = factorize(k, reduced.diagonal(k) + mu, mu, reduced.ldl_of(k))
        rhs = grad[free]
        step = factors.solve(rhs)
        assert np.linalg.norm(full @ step + mu * step - rhs) <= 1e-9 * np.linalg.norm(rhs)
    assert closed_counts[0] == 0 and closed_counts[-1] > 0
